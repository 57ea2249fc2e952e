//! MRCLAM metric frames as a percept stream, and back.
//!
//! `lplace extract --from mrclam` turns one robot's files into the same JSON-lines stream of
//! [`FrameRecord`]s as every other extractor, so that the metric layer (`lplace grid`) and the
//! place engine read one format. This module holds both directions of that conversion:
//!
//! * [`to_record`]: a [`MetricFrame`] becomes a record with the odometry increment (metres,
//!   degrees), one `landmark_range` and one `landmark_bearing` percept per sighting (the
//!   subject's map name as argument; metres and degrees; the degree is the reading's
//!   reliability, [`reliability`]) and the Vicon truth pose (and the map place containing it).
//! * [`RecordReader`]: records become [`MetricFrame`]s again, subjects looked up by name; a range
//!   and a bearing of the same subject in one record form one sighting.
//!
//! Like the rest of `io`, nothing here opens a file.
//!
//! # Example
//!
//! ```
//! use lplace::core::Pose2;
//! use lplace::localize::{LandmarkReading, MetricFrame};
//! use lplace::io::mrclam_stream::{to_record, RecordReader};
//! let names = |id: u32| format!("L{id}");
//! let f = MetricFrame {
//!     t: 3.0,
//!     dt: 0.0,
//!     odometry: Default::default(),
//!     observations: vec![LandmarkReading { subject: 6, range: 2.0, bearing: 0.1 }],
//!     truth: Some(Pose2 { x: 1.0, y: 2.0, theta: 0.5 }),
//! };
//! let rec = to_record(&f, &names, |_, _| None);
//! assert_eq!(rec.percepts.len(), 2);
//! let mut back = RecordReader::new([("L6".to_string(), 6)]);
//! let g = back.convert(&rec);
//! assert_eq!(g.observations[0].subject, 6);
//! assert!((g.observations[0].bearing - 0.1).abs() < 1e-9);
//! ```

use super::record::{FrameRecord, Odometry, PerceptRecord, Truth, FORMAT_VERSION};
use crate::core::angle::wrap_180;
use crate::core::Pose2;
use crate::localize::{LandmarkReading, MetricFrame};
use std::collections::BTreeMap;

/// Percept name of a range reading (argument: the subject's name; value: metres).
pub const RANGE: &str = "landmark_range";
/// Percept name of a bearing reading (argument: the subject's name; value: degrees, robot
/// frame, counter-clockwise, in (−180, 180]).
pub const BEARING: &str = "landmark_bearing";

/// MRCLAM's subject ids of the robots (the data set's README: 1–5 robots, 6–20 landmarks).
pub const ROBOTS: std::ops::RangeInclusive<u32> = 1..=5;

/// A robot's subject name in a stream (`Robot4`), for sightings of another robot.
pub fn robot_name(id: u32) -> String {
    format!("Robot{id}")
}

/// The robot a subject name of [`robot_name`]'s form names, if any.
pub fn robot_of(name: &str) -> Option<u32> {
    let id = name.strip_prefix("Robot")?.parse().ok()?;
    ROBOTS.contains(&id).then_some(id)
}

/// Reliability of a camera sighting at `range` metres, used as the percept's degree.
///
/// The barcode shrinks in the image with distance, so far readings are misread and mis-ranged
/// more often: 1 up to 3 m, falling linearly to 0.5 at 7.5 m (the data set's longest readings),
/// never below 0.5. A heuristic, not a calibration.
pub fn reliability(range: f64) -> f64 {
    if !range.is_finite() {
        return 0.5;
    }
    (1.0 - 0.5 * (range - 3.0) / 4.5).clamp(0.5, 1.0)
}

/// Rounds to `1e-6` so that streams stay short and diffable; micrometres and microdegrees are far
/// below every sensor's resolution here.
fn r6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// Converts one frame. `name_of` names a subject id (the map's landmark name); `place_at` names
/// the place containing a truth position, if any.
pub fn to_record(
    f: &MetricFrame,
    name_of: &dyn Fn(u32) -> String,
    place_at: impl Fn(f64, f64) -> Option<String>,
) -> FrameRecord {
    let mut percepts = Vec::with_capacity(2 * f.observations.len());
    for o in &f.observations {
        let name = name_of(o.subject);
        let degree = reliability(o.range);
        percepts.push(PerceptRecord {
            name: RANGE.to_string(),
            args: vec![name.clone()],
            value: Some(r6(o.range)),
            degree,
        });
        percepts.push(PerceptRecord {
            name: BEARING.to_string(),
            args: vec![name],
            value: Some(r6(wrap_180(o.bearing.to_degrees()))),
            degree,
        });
    }
    let truth = f.truth.map(|p| Truth {
        place: place_at(p.x, p.y),
        pose: Some([r6(p.x), r6(p.y), r6(wrap_180(p.theta.to_degrees()))]),
    });
    FrameRecord {
        version: Some(FORMAT_VERSION),
        t: Some(f.t),
        odometry: Some(Odometry {
            dx: r6(f.odometry.forward),
            dy: r6(f.odometry.left),
            dtheta: r6(f.odometry.turn.to_degrees()),
        }),
        heading: None,
        percepts,
        truth,
        region: None,
    }
}

/// What [`RecordReader`] could not use, summed over the records it converted.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReadStats {
    /// Range or bearing percepts without their partner in the same record.
    pub unpaired: usize,
    /// Landmark percepts naming no subject the reader knows, other robots aside (a map that
    /// misses landmarks, typos).
    pub unknown: usize,
    /// Sightings of other robots ([`robot_of`] names) the reader does not know as landmarks.
    pub robots: usize,
    /// Landmark percepts below the reader's minimum degree, or with no finite value.
    pub dropped: usize,
}

/// Turns frame records back into [`MetricFrame`]s (see the module docs).
#[derive(Debug, Clone)]
pub struct RecordReader {
    ids: BTreeMap<String, u32>,
    prev_t: Option<f64>,
    /// Landmark percepts whose degree is below this are left out. Default 0.
    pub min_degree: f64,
    /// What was left out so far.
    pub stats: ReadStats,
}

impl RecordReader {
    /// A reader that knows these `(name, subject id)` pairs.
    pub fn new(names: impl IntoIterator<Item = (String, u32)>) -> Self {
        RecordReader {
            ids: names.into_iter().collect(),
            prev_t: None,
            min_degree: 0.0,
            stats: ReadStats::default(),
        }
    }

    /// Converts one record. A record without `t` is taken to be at the previous record's time
    /// (0 for the first); the frame's `dt` is the time since the previous record.
    pub fn convert(&mut self, rec: &FrameRecord) -> MetricFrame {
        let percepts = rec.percepts.iter().map(|p| Reading {
            name: &p.name,
            subject: p.args.first().map(String::as_str),
            value: p.value,
            degree: p.degree,
        });
        let truth_pose = rec.truth.as_ref().and_then(|tr| tr.pose);
        self.convert_parts(
            rec.t,
            rec.odometry.unwrap_or_default(),
            truth_pose,
            percepts,
        )
    }

    /// [`RecordReader::convert`] on a record's parts, so that a reader holding them in another
    /// form (the stream reader's dense frame) converts alike. `percepts` in the record's order.
    pub fn convert_parts<'a>(
        &mut self,
        t: Option<f64>,
        o: Odometry,
        truth_pose: Option<[f64; 3]>,
        percepts: impl IntoIterator<Item = Reading<'a>>,
    ) -> MetricFrame {
        let t = t.filter(|t| t.is_finite()).or(self.prev_t).unwrap_or(0.0);
        let dt = self.prev_t.map_or(0.0, |p| (t - p).max(0.0));
        self.prev_t = Some(t);
        // Pair ranges with bearings by subject name, in first-seen order.
        let mut pairs: Vec<(&str, Option<f64>, Option<f64>)> = Vec::new();
        for p in percepts {
            let is_range = p.name == RANGE;
            if !is_range && p.name != BEARING {
                continue;
            }
            let (Some(arg), Some(v)) = (p.subject, p.value.filter(|v| v.is_finite())) else {
                self.stats.dropped += 1;
                continue;
            };
            if p.degree < self.min_degree {
                self.stats.dropped += 1;
                continue;
            }
            let k = match pairs.iter().position(|e| e.0 == arg) {
                Some(k) => k,
                None => {
                    pairs.push((arg, None, None));
                    pairs.len() - 1
                }
            };
            if is_range {
                pairs[k].1 = Some(v);
            } else {
                pairs[k].2 = Some(v.to_radians());
            }
        }
        let observations = self.sightings(pairs);
        let truth = truth_pose
            .filter(|p| p.iter().all(|v| v.is_finite()))
            .map(|[x, y, th]| Pose2 {
                x,
                y,
                theta: wrap_180(th).to_radians(),
            });
        MetricFrame {
            t,
            dt,
            odometry: crate::core::Odometry {
                forward: o.dx,
                left: o.dy,
                turn: o.dtheta.to_radians(),
            },
            observations,
            truth,
        }
    }

    /// The paired readings of known subjects; unpaired and unknown ones are counted.
    fn sightings(&mut self, pairs: Vec<(&str, Option<f64>, Option<f64>)>) -> Vec<LandmarkReading> {
        let mut observations = Vec::with_capacity(pairs.len());
        for (name, range, bearing) in pairs {
            let (Some(range), Some(bearing)) = (range, bearing) else {
                self.stats.unpaired += 1;
                continue;
            };
            match self.ids.get(name) {
                Some(&subject) => observations.push(LandmarkReading {
                    subject,
                    range,
                    bearing,
                }),
                None if robot_of(name).is_some() => self.stats.robots += 1,
                None => self.stats.unknown += 1,
            }
        }
        observations
    }
}

/// One percept of a record as [`RecordReader::convert_parts`] takes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading<'a> {
    /// Percept name ([`RANGE`], [`BEARING`]; others are passed over).
    pub name: &'a str,
    /// Its first argument: the subject's name.
    pub subject: Option<&'a str>,
    /// Metres or degrees.
    pub value: Option<f64>,
    /// Reliability.
    pub degree: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robot_names_go_both_ways_for_the_five_robots_only() {
        for id in ROBOTS {
            assert_eq!(robot_of(&robot_name(id)), Some(id));
        }
        for name in ["Robot0", "Robot6", "Robot", "Robot-1", "robot2", "L6", "S7"] {
            assert_eq!(robot_of(name), None, "{name}");
        }
    }

    #[test]
    fn the_reader_counts_other_robots_apart_from_unknown_subjects() {
        let mut r = RecordReader::new([("L6".to_string(), 6)]);
        let read = |subject| {
            [RANGE, BEARING].map(|name| Reading {
                name,
                subject: Some(subject),
                value: Some(1.0),
                degree: 1.0,
            })
        };
        let percepts = [read("L6"), read("Robot2"), read("Robot5"), read("S9")].concat();
        let f = r.convert_parts(Some(1.0), Odometry::default(), None, percepts);
        assert_eq!(f.observations.len(), 1);
        assert_eq!((r.stats.robots, r.stats.unknown), (2, 1));
    }
}
