//! CARMEN log → percept stream: one [`FrameRecord`] per `FLASER` scan, with the raw odometry
//! increment since the previous scan, the percepts of the scan extractors
//! ([`crate::percept::ScanExtractor`]: `laser_wall(Front)`, `laser_corner(Front)`,
//! `sonar_wall(Left|Right)`; [`crate::percept::layout`]: `corridor_width`, `side_openings`;
//! when `compass.enabled`, [`crate::percept::compass`]: `free_range(East|North|West|South)`) and,
//! when a map is given, the ground truth. With the compass, `heading` carries its axis-locked
//! heading estimate. Library code behind `lplace extract --from carmen`;
//! like the readers it does no I/O of its own.
//!
//! # Odometry
//! In the corrected logs a scan's `x y theta` *and* `odom_x odom_y odom_theta` both hold the
//! SLAM-corrected pose; the raw odometry survives only in the `ODOM` lines, re-chained from the
//! last scan's pose (data README). The increment between scans k and k+1 is therefore
//! `(last ODOM before scan k+1) ⊖ (odom pose of scan k)`, expressed in the robot frame of scan
//! k. The same formula is right for raw logs, where both are in the odometry frame. Without an
//! `ODOM` in between — or with none but one restating scan k's odom pose, the chain's restart
//! — the two scans' odom poses are used. The first frame has no odometry.
//!
//! The side-wall fits of eq. (4) place readings in one frame by *integrating these raw
//! increments*, never by the corrected pose, so no ground truth leaks into the percepts.
//!
//! # Time
//! `t` is the scan's `ipc_ts`, held non-decreasing (a scan stamped earlier than the one before
//! it keeps the previous time).
//!
//! # Truth
//! With places given, `truth.place` is the first place, in map order, whose extent holds the
//! corrected pose (none when no extent does) and `truth.pose` is that pose in metres and
//! degrees. Overlapping extents are resolved by declaration order, so a map lists its small
//! places (doorways, junctions) before the larger ones around them.

use std::io::BufRead;

use crate::core::angle::{wrap_180, wrap_pi};
use crate::core::Pose2;
use crate::io::carmen::{CarmenError, CarmenMessage, CarmenReader, CarmenStats, LaserScan};
use crate::io::record::{
    FrameRecord, Odometry, PerceptRecord as WireRecord, Truth, FORMAT_VERSION,
};
use crate::map::Place;
use crate::percept::compass::CompassTracker;
use crate::percept::layout::layout;
use crate::percept::scan::ScanView;
use crate::percept::{ConfigError, ExtractConfig, PerceptArg, PerceptRecord, ScanExtractor, Side};

/// Turns CARMEN messages into frame records, one per scan. Feed it every message in log order
/// with [`CarmenFramer::push`].
#[derive(Debug, Clone)]
pub struct CarmenFramer<'m> {
    extractor: ScanExtractor,
    /// Axis-locked heading and compass free ranges, when enabled in the config.
    compass: Option<CompassTracker>,
    places: Option<&'m [Place]>,
    /// Odom pose of the previous scan.
    prev_scan_odom: Option<Pose2>,
    /// Last `ODOM` pose since the previous scan.
    last_odom: Option<Pose2>,
    /// Integrated raw odometry: the robot's own idea of where it is.
    dead_reckoning: Pose2,
    /// Largest scan time so far.
    last_t: f64,
    frames: u64,
    /// What the extraction's quality figures are made of.
    quality: QualityCounts,
}

/// Running counts behind [`ExtractQuality`].
#[derive(Debug, Clone, Default)]
struct QualityCounts {
    distance: f64,
    free_ranges: u64,
    capped: u64,
    short: u64,
    locked: u64,
    /// Per locking frame, the size of the heading correction, degrees.
    residuals: Vec<f64>,
    /// Per frame with a heading and a true pose, the size of the heading's error, degrees.
    truth_errors: Vec<f64>,
    /// Odometry increments (every scan but the first), and those taken from the two scans'
    /// own odom poses because no `ODOM` reading came between them.
    steps: u64,
    from_scan_poses: u64,
    /// The previous frame's true heading, radians, when it had one.
    prev_truth_theta: Option<f64>,
    /// Per step with two true poses and a compass turn, the size of the compass's and of
    /// the raw odometry's turn error against the true turn, degrees.
    turn_errors: Vec<(f64, f64)>,
}

/// Quality figures of an extraction, from the stream alone (no ground truth): how densely the
/// log samples the path, how much of the compass view reads nothing, and how steadily the
/// heading lock follows the odometry from scan to scan. When the frames carry true poses (a
/// map given), also how far the heading is from them: a quarter-turn lost is as steady from scan
/// to scan as the right one, so only this figure shows it.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ExtractQuality {
    /// Frames extracted.
    pub frames: u64,
    /// Odometry distance travelled, metres.
    pub distance_m: f64,
    /// Frames per metre of travel.
    pub frames_per_metre: f64,
    /// Share of `free_range` values at the cap (nothing seen that way).
    pub capped_share: f64,
    /// Share of `free_range` values under 0.1 m (points dead-reckoned onto the robot).
    pub short_share: f64,
    /// Share of frames whose scan locked the heading (corrected the odometry's prediction).
    pub locked_share: f64,
    /// Share of those corrections within 5°: the lock agrees with the odometry from scan to
    /// scan (a lock that jumps between wall directions makes large ones).
    pub heading_consistent_share: f64,
    /// Median and 90th percentile of the corrections' size, degrees.
    pub heading_residual_median_deg: f64,
    /// See `heading_residual_median_deg`.
    pub heading_residual_p90_deg: f64,
    /// Share of the frames with a true pose whose heading is within 10° of it; `None` without
    /// true poses (no map) or without a heading (compass off).
    pub truth_heading_within_10_share: Option<f64>,
    /// Median of the heading's error against the true poses, degrees; `None` as above.
    pub truth_heading_error_median_deg: Option<f64>,
    /// Odometry increments, one per scan after the first.
    pub odometry_steps: u64,
    /// Of them, those taken from the two scans' own odom poses, no `ODOM` reading coming
    /// between: in a corrected log those slots hold the corrected pose, so such a step carries
    /// the corrected motion, not the robot's odometry.
    pub odometry_from_scan_poses: u64,
    /// With `compass.scan_rotation`, the odometry steps whose turn came from the scans and all
    /// the steps the tracker took; `None` without it.
    pub scan_turns: Option<(u64, u64)>,
    /// With `compass.scan_match`, the odometry steps whose motion came from an accepted scan
    /// match and all the steps it was tried on; `None` without it.
    pub scan_matches: Option<(u64, u64)>,
    /// Of the steps between two frames with true poses, the share whose turn (the one the
    /// heading's prediction took: the scans' or the odometry's) is within 2° of the true
    /// turn, and the same share for the raw odometry's turn; `None` without true poses or
    /// without a heading.
    pub truth_turn_within_2_share: Option<(f64, f64)>,
}

impl std::fmt::Display for ExtractQuality {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:.1} frames/m over {:.1} m; free ranges at the cap {:.1} %, under 0.1 m {:.1} %; \
             heading locked on {:.1} % of frames, corrections within 5° on {:.1} % of them \
             (median {:.2}°, 90th percentile {:.2}°)",
            self.frames_per_metre,
            self.distance_m,
            100.0 * self.capped_share,
            100.0 * self.short_share,
            100.0 * self.locked_share,
            100.0 * self.heading_consistent_share,
            self.heading_residual_median_deg,
            self.heading_residual_p90_deg
        )?;
        if let (Some(within), Some(median)) = (
            self.truth_heading_within_10_share,
            self.truth_heading_error_median_deg,
        ) {
            write!(
                f,
                "; against the true poses, heading within 10° on {:.1} % of frames (median error \
                 {median:.1}°)",
                100.0 * within
            )?;
        }
        if let Some((compass, odometry)) = self.truth_turn_within_2_share {
            write!(
                f,
                "; turn between scans within 2° of the true poses' on {:.1} % of steps (the \
                 odometry's: {:.1} %)",
                100.0 * compass,
                100.0 * odometry
            )?;
        }
        if let Some((from_scans, steps)) = self.scan_turns {
            write!(f, "; turn from the scans on {from_scans} of {steps} steps")?;
        }
        if let Some((matched, steps)) = self.scan_matches {
            write!(
                f,
                "; motion from the scan match on {matched} of {steps} steps (the odometry's on \
                 the others)"
            )?;
        }
        if self.odometry_from_scan_poses > 0 {
            write!(
                f,
                "; odometry from the scans' own poses on {} of {} steps (no ODOM between two \
                 scans: in a corrected log, the corrected motion)",
                self.odometry_from_scan_poses, self.odometry_steps
            )?;
        }
        Ok(())
    }
}

impl<'m> CarmenFramer<'m> {
    /// A framer with extractor parameters `cfg`; `places` (from a map) enables ground truth.
    ///
    /// # Errors
    /// [`ConfigError`] when a parameter is out of range.
    pub fn new(cfg: ExtractConfig, places: Option<&'m [Place]>) -> Result<Self, ConfigError> {
        Ok(CarmenFramer {
            extractor: ScanExtractor::new(cfg)?,
            compass: if cfg.compass.enabled {
                Some(CompassTracker::new(cfg.compass)?)
            } else {
                None
            },
            places,
            prev_scan_odom: None,
            last_odom: None,
            dead_reckoning: Pose2::default(),
            last_t: f64::NEG_INFINITY,
            frames: 0,
            quality: QualityCounts::default(),
        })
    }

    /// Frames produced so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// The quality figures of the frames produced so far.
    pub fn quality(&self) -> ExtractQuality {
        let q = &self.quality;
        let share = |a: u64, b: u64| if b > 0 { a as f64 / b as f64 } else { 0.0 };
        let mut r = q.residuals.clone();
        r.sort_by(f64::total_cmp);
        let pick = |p: f64| {
            let i = ((r.len() as f64 - 1.0) * p).round().max(0.0) as usize;
            r.get(i).copied().unwrap_or(0.0)
        };
        let consistent = r.iter().filter(|&&v| v <= 5.0).count() as u64;
        let mut e = q.truth_errors.clone();
        e.sort_by(f64::total_cmp);
        let truth_within = e.iter().filter(|&&v| v <= 10.0).count() as u64;
        let has_truth = !e.is_empty();
        ExtractQuality {
            frames: self.frames,
            distance_m: q.distance,
            frames_per_metre: if q.distance > 0.0 {
                self.frames as f64 / q.distance
            } else {
                0.0
            },
            capped_share: share(q.capped, q.free_ranges),
            short_share: share(q.short, q.free_ranges),
            locked_share: share(q.locked, self.frames),
            heading_consistent_share: share(consistent, r.len() as u64),
            heading_residual_median_deg: pick(0.5),
            heading_residual_p90_deg: pick(0.9),
            truth_heading_within_10_share: has_truth.then(|| share(truth_within, e.len() as u64)),
            truth_heading_error_median_deg: e.get(e.len() / 2).copied(),
            odometry_steps: q.steps,
            odometry_from_scan_poses: q.from_scan_poses,
            scan_turns: self
                .compass
                .as_ref()
                .filter(|c| c.config().scan_rotation)
                .map(CompassTracker::scan_turns),
            scan_matches: self
                .compass
                .as_ref()
                .filter(|c| c.config().scan_match)
                .map(CompassTracker::scan_matches),
            truth_turn_within_2_share: (!q.turn_errors.is_empty()).then(|| {
                let n = q.turn_errors.len() as u64;
                let within = |f: fn(&(f64, f64)) -> f64| {
                    q.turn_errors.iter().filter(|e| f(e) <= 2.0).count() as u64
                };
                (share(within(|e| e.0), n), share(within(|e| e.1), n))
            }),
        }
    }

    /// Counts the frame's heading and turn errors against its true pose `truth` (radians)
    /// for [`Self::quality`].
    fn count_truth(&mut self, heading: Option<f64>, odometry: Option<&Pose2>, truth: Option<f64>) {
        let q = &mut self.quality;
        let prev = std::mem::replace(&mut q.prev_truth_theta, truth);
        let Some(truth) = truth else {
            return;
        };
        if let Some(h) = heading {
            let error = wrap_180(h - truth.to_degrees()).abs();
            if error.is_finite() {
                q.truth_errors.push(error);
            }
        }
        let turn = self.compass.as_ref().and_then(CompassTracker::last_turn);
        if let (Some(prev), Some(turn), Some(d)) = (prev, turn, odometry) {
            let true_turn = truth - prev;
            let compass = wrap_pi(turn - true_turn).to_degrees().abs();
            let odometry = wrap_pi(d.theta - true_turn).to_degrees().abs();
            if compass.is_finite() && odometry.is_finite() {
                q.turn_errors.push((compass, odometry));
            }
        }
    }

    /// Counts one frame's contribution to [`Self::quality`].
    fn count_quality(&mut self, odometry: Option<&Pose2>, free: &[f64]) {
        let q = &mut self.quality;
        if let Some(d) = odometry {
            let ds = d.x.hypot(d.y);
            if ds.is_finite() {
                q.distance += ds;
            }
        }
        let Some(compass) = self.compass.as_ref() else {
            return;
        };
        let cap = compass.config().cap_m.ln();
        for &v in free {
            q.free_ranges += 1;
            q.capped += u64::from(v >= cap - 1e-9);
            q.short += u64::from(v < 0.1f64.ln());
        }
        if let Some(c) = compass.correction().map(f64::to_degrees) {
            q.locked += 1;
            if c.is_finite() {
                q.residuals.push(c.abs());
            }
        }
    }

    /// Takes the next message; returns a frame for each `FLASER`. `laser_offset` is
    /// `PARAM robot_frontlaser_offset` (see [`CarmenReader::laser_offset`]).
    pub fn push(&mut self, msg: &CarmenMessage, laser_offset: f64) -> Option<FrameRecord> {
        match msg {
            CarmenMessage::Odom(o) => {
                // An `ODOM` that restates the last scan's odom pose (in the corrected logs, the
                // line the chain restarts from) is no motion reading: a segment with nothing
                // else is a gap in the raw odometry, bridged by the scans' poses as when no
                // `ODOM` came at all, not read as standing still (Seattle: an 80° turn lost).
                if self.prev_scan_odom != Some(o.pose) {
                    self.last_odom = Some(o.pose);
                }
                None
            }
            CarmenMessage::Param { .. } => None,
            CarmenMessage::Laser(scan) => Some(self.frame(scan, None, laser_offset)),
        }
    }

    /// A frame for a scan whose beams do not follow the FLASER convention (a ROS
    /// `LaserScan`, `io::rosbag2`): beam `i` at bearing `first_bearing + i·bearing_step`,
    /// radians. Odometry comes from [`CarmenFramer::push`]ed `Odom` messages as for CARMEN.
    pub fn push_scan(
        &mut self,
        scan: &LaserScan,
        first_bearing: f64,
        bearing_step: f64,
        laser_offset: f64,
    ) -> FrameRecord {
        self.frame(scan, Some((first_bearing, bearing_step)), laser_offset)
    }

    /// The odometry increment since the previous scan (from the latest `ODOM`, else the scan's
    /// own pose), folded into the dead reckoning; `None` for the first scan.
    fn advance_odometry(&mut self, scan: &LaserScan) -> Option<Pose2> {
        if self.prev_scan_odom.is_some() {
            self.quality.steps += 1;
            self.quality.from_scan_poses += u64::from(self.last_odom.is_none());
        }
        let odometry = self.prev_scan_odom.map(|prev| {
            let now = self.last_odom.unwrap_or(scan.odom_pose);
            relative(&prev, &now)
        });
        if let Some(inc) = odometry {
            self.dead_reckoning = compose(&self.dead_reckoning, &inc);
        }
        self.prev_scan_odom = Some(scan.odom_pose);
        self.last_odom = None;
        odometry
    }

    /// Steps the compass (when configured) and appends its `free_range` percepts; returns the
    /// free ranges that have a value (at most 8), for the quality counts.
    fn compass_percepts(
        &mut self,
        view: &ScanView<'_>,
        odometry: Option<&Pose2>,
        odom_theta: f64,
        percepts: &mut Vec<WireRecord>,
    ) -> ([f64; 8], usize) {
        let mut free = [0.0f64; 8];
        let mut n_free = 0;
        if let Some(compass) = self.compass.as_mut() {
            for r in compass.step(view, odometry, odom_theta) {
                if let (Some(v), Some(slot)) = (r.value, free.get_mut(n_free)) {
                    *slot = v;
                    n_free += 1;
                }
                percepts.push(WireRecord {
                    name: "free_range".to_owned(),
                    args: vec![r.direction.to_owned()],
                    value: r.value,
                    degree: r.degree,
                });
            }
        }
        (free, n_free)
    }

    /// The recorded true pose and the place containing it, when the framer knows the places.
    fn truth(&self, scan: &LaserScan) -> Option<Truth> {
        self.places.map(|places| {
            let p = scan.pose;
            Truth {
                place: places
                    .iter()
                    .find(|pl| pl.contains(p.x, p.y))
                    .map(|pl| pl.name.clone()),
                pose: Some([p.x, p.y, wrap_180(p.theta.to_degrees())]),
            }
        })
    }

    fn frame(
        &mut self,
        scan: &LaserScan,
        geometry: Option<(f64, f64)>,
        laser_offset: f64,
    ) -> FrameRecord {
        let odometry = self.advance_odometry(scan);
        let mut view = scan.view(laser_offset);
        view.pose = self.dead_reckoning;
        if let Some((first, step)) = geometry {
            view.first_bearing = first;
            view.bearing_step = step;
        }
        let mut percepts: Vec<WireRecord> = self.extractor.step(&view).iter().map(wire).collect();
        for r in layout(&view, &self.extractor.config().layout) {
            percepts.push(WireRecord {
                name: r.name.to_owned(),
                args: Vec::new(),
                value: r.value,
                degree: r.degree,
            });
        }
        let (free, n_free) = self.compass_percepts(
            &view,
            odometry.as_ref(),
            scan.odom_pose.theta,
            &mut percepts,
        );
        // The axis-locked heading is the extractor's own estimate (no corrected pose enters it).
        let heading = self
            .compass
            .as_ref()
            .and_then(CompassTracker::pose)
            .map(|p| wrap_180(p.theta.to_degrees()));
        self.count_quality(odometry.as_ref(), &free[..n_free]);
        let truth = self.truth(scan);
        let true_theta = truth.as_ref().and(Some(scan.pose.theta));
        self.count_truth(heading, odometry.as_ref(), true_theta);
        self.frames += 1;
        // Scan `ipc_ts` occasionally steps back by a fraction of a second (4 times in the Intel
        // log) although lines are in chronological order (data README), and a stream's time
        // must not go backwards: such a scan keeps the previous time.
        self.last_t = self.last_t.max(scan.timestamp);
        FrameRecord {
            version: Some(FORMAT_VERSION),
            t: Some(self.last_t),
            odometry: odometry.map(|p| Odometry {
                dx: p.x,
                dy: p.y,
                dtheta: wrap_180(p.theta.to_degrees()),
            }),
            heading,
            percepts,
            truth,
            region: None,
        }
    }
}

/// The wire form of an extractor record: sides become the constants `Front`, `Left`, `Right`
/// (rule-file constants are capitalised), landmark ids their decimal text.
fn wire(r: &PerceptRecord) -> WireRecord {
    let args = match r.arg {
        PerceptArg::None => Vec::new(),
        PerceptArg::Side(Side::Front) => vec!["Front".to_owned()],
        PerceptArg::Side(Side::Left) => vec!["Left".to_owned()],
        PerceptArg::Side(Side::Right) => vec!["Right".to_owned()],
        PerceptArg::Landmark(id) => vec![id.to_string()],
    };
    WireRecord {
        name: r.kind.as_str().to_owned(),
        args,
        value: r.value,
        degree: r.degree,
    }
}

/// `b ⊖ a`: pose `b` in the frame of pose `a` (radians).
pub fn relative(a: &Pose2, b: &Pose2) -> Pose2 {
    let (s, c) = a.theta.sin_cos();
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    Pose2 {
        x: c * dx + s * dy,
        y: -s * dx + c * dy,
        theta: wrap_pi(b.theta - a.theta),
    }
}

/// `a ⊕ d`: increment `d` (in `a`'s frame) applied to `a`.
pub fn compose(a: &Pose2, d: &Pose2) -> Pose2 {
    let (s, c) = a.theta.sin_cos();
    Pose2 {
        x: a.x + c * d.x - s * d.y,
        y: a.y + s * d.x + c * d.y,
        theta: wrap_pi(a.theta + d.theta),
    }
}

/// What a whole conversion did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ConvertSummary {
    /// Frames written.
    pub frames: u64,
    /// The reader's counts (lines, messages, rejected lines, skipped message types).
    pub stats: CarmenStats,
}

/// Converts a whole log: every frame goes to `on_frame` (which may fail, e.g. on a closed
/// pipe, and then stops the conversion), every malformed line to `on_error`, after which the
/// conversion goes on with the next line.
///
/// # Errors
/// Whatever `on_frame` returns.
pub fn convert<R: BufRead, E>(
    source: R,
    framer: &mut CarmenFramer<'_>,
    mut on_frame: impl FnMut(FrameRecord) -> Result<(), E>,
    mut on_error: impl FnMut(&CarmenError),
) -> Result<ConvertSummary, E> {
    let mut reader = CarmenReader::new(source);
    let mut frames = 0;
    while let Some(item) = reader.next() {
        match item {
            Ok((_, msg)) => {
                if let Some(frame) = framer.push(&msg, reader.laser_offset()) {
                    frames += 1;
                    on_frame(frame)?;
                }
            }
            Err(e) => on_error(&e),
        }
    }
    Ok(ConvertSummary {
        frames,
        stats: reader.stats().clone(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_and_compose_are_inverse() {
        let a = Pose2 {
            x: 1.0,
            y: -2.0,
            theta: 2.5,
        };
        let b = Pose2 {
            x: -0.5,
            y: 3.0,
            theta: -2.9,
        };
        let d = relative(&a, &b);
        let back = compose(&a, &d);
        assert!((back.x - b.x).abs() < 1e-12 && (back.y - b.y).abs() < 1e-12);
        assert!((back.theta - b.theta).abs() < 1e-12);
    }

    #[test]
    fn increment_is_in_the_previous_robot_frame() {
        // Facing +y, the robot moves 1 m along +y: 1 m forward.
        let a = Pose2 {
            x: 0.0,
            y: 0.0,
            theta: std::f64::consts::FRAC_PI_2,
        };
        let b = Pose2 {
            x: 0.0,
            y: 1.0,
            theta: std::f64::consts::FRAC_PI_2,
        };
        let d = relative(&a, &b);
        assert!((d.x - 1.0).abs() < 1e-12 && d.y.abs() < 1e-12 && d.theta.abs() < 1e-12);
        assert_eq!(wrap_180(540.0), 180.0);
        assert_eq!(wrap_180(-190.0), 170.0);
    }

    /// A CARMEN log of `n` scans in a square room (walls 3 m from its centre, square to the
    /// axes): the robot drives along +x from (-1, 0) facing East by its odometry, while its
    /// recorded (true) heading is `true_offset_deg` off that.
    fn square_room_log(n: usize, true_offset_deg: f64) -> String {
        let mut log = String::new();
        for k in 0..n {
            let x = -1.0 + 0.3 * k as f64;
            let ranges: Vec<String> = (0..181)
                .map(|i| {
                    let phi = (i as f64 - 90.0).to_radians();
                    let (s, c) = phi.sin_cos();
                    let to_x = if c > 1e-9 {
                        (3.0 - x) / c
                    } else if c < -1e-9 {
                        (-3.0 - x) / c
                    } else {
                        f64::INFINITY
                    };
                    let to_y = if s.abs() > 1e-9 {
                        3.0 / s.abs()
                    } else {
                        f64::INFINITY
                    };
                    format!("{:.3}", to_x.min(to_y))
                })
                .collect();
            let truth = true_offset_deg.to_radians();
            log.push_str(&format!(
                "FLASER 181 {} {x} 0 {truth} {x} 0 0 {k}.0 host {k}.0\n",
                ranges.join(" ")
            ));
        }
        log
    }

    fn quality_of(log: &str, with_places: bool) -> ExtractQuality {
        let text = "map m; room R; place P room in R at (0, 0) extent box (-3, -3, 3, 3) { }";
        let ast = crate::syntax::parse_map(text).expect("parses");
        let map = crate::map::Map::from_ast(&ast).expect("builds");
        let places = with_places.then(|| map.places());
        let mut framer = CarmenFramer::new(ExtractConfig::travelling(), places).expect("valid");
        let done = convert(
            log.as_bytes(),
            &mut framer,
            |_| Ok::<(), ()>(()),
            |e| panic!("{e}"),
        );
        assert_eq!(done.map(|s| s.frames), Ok(6));
        framer.quality()
    }

    #[test]
    fn the_heading_is_scored_against_the_true_poses_only_when_they_are_known() {
        // Odometry and truth agree: the locked heading is the true one.
        let q = quality_of(&square_room_log(6, 0.0), true);
        assert_eq!(q.truth_heading_within_10_share, Some(1.0));
        assert!(
            q.truth_heading_error_median_deg.is_some_and(|e| e < 1.0),
            "{q}"
        );
        assert!(
            q.to_string()
                .contains("heading within 10° on 100.0 % of frames"),
            "{q}"
        );
        // The log's true heading is a quarter-turn off the odometry's: the lock keeps the
        // odometry's quarter-turn, steady from scan to scan, and only the truth shows it.
        let q = quality_of(&square_room_log(6, 90.0), true);
        assert_eq!(q.truth_heading_within_10_share, Some(0.0));
        assert!(
            q.truth_heading_error_median_deg
                .is_some_and(|e| (e - 90.0).abs() < 1.0),
            "{q}"
        );
        assert!(q.heading_consistent_share > 0.99, "{q}");
        // Without a map there is no truth to score against, and the line says nothing of it.
        let q = quality_of(&square_room_log(6, 90.0), false);
        assert_eq!(q.truth_heading_within_10_share, None);
        assert_eq!(q.truth_heading_error_median_deg, None);
        assert!(!q.to_string().contains("true poses"), "{q}");
    }

    #[test]
    fn steps_without_an_odom_reading_are_counted_and_named() {
        // FLASER lines only: every step after the first comes from the scans' own poses.
        let q = quality_of(&square_room_log(6, 0.0), false);
        assert_eq!((q.odometry_from_scan_poses, q.odometry_steps), (5, 5));
        assert!(q.to_string().contains("own poses on 5 of 5 steps"), "{q}");
        // An ODOM reading before every scan but the third: one step from the scans' poses.
        let mut log = String::new();
        for (k, line) in square_room_log(6, 0.0).lines().enumerate() {
            if k > 0 && k != 3 {
                let x = -1.0 + 0.3 * k as f64;
                log.push_str(&format!("ODOM {x} 0 0 0 0 0 {k}.0 host {k}.0\n"));
            }
            log.push_str(line);
            log.push('\n');
        }
        let q = quality_of(&log, false);
        assert_eq!((q.odometry_from_scan_poses, q.odometry_steps), (1, 5));
        // With ODOM readings throughout, the line says nothing of it.
        let log = log.replace("FLASER", "ODOM -9 0 0 0 0 0 0.0 host 0.0\nFLASER");
        let q = quality_of(&log, false);
        assert_eq!(q.odometry_from_scan_poses, 0, "{q}");
        assert!(!q.to_string().contains("own poses"), "{q}");
    }

    #[test]
    fn the_turn_between_scans_is_scored_against_the_true_turn() {
        // The robot drives straight through the room (the scans and the true poses never
        // turn) while each ODOM reading says it turned 8° since the previous scan's odom pose
        // (whose angle is 0 in every FLASER line): the odometry's turn is 8° wrong on every
        // step, the scan match's (the travelling settings) right on every one.
        let mut log = String::new();
        for (k, line) in square_room_log(6, 0.0).lines().enumerate() {
            if k > 0 {
                let x = -1.0 + 0.3 * k as f64;
                let theta = 8f64.to_radians();
                log.push_str(&format!("ODOM {x} 0 {theta} 0 0 0 {k}.0 host {k}.0\n"));
            }
            log.push_str(line);
            log.push('\n');
        }
        let q = quality_of(&log, true);
        assert_eq!(q.scan_matches, Some((5, 5)), "{q}");
        assert_eq!(q.truth_turn_within_2_share, Some((1.0, 0.0)), "{q}");
        assert!(
            q.to_string().contains(
                "within 2° of the true poses' on 100.0 % of steps (the odometry's: 0.0 %)"
            ),
            "{q}"
        );
        // Without true poses there is no true turn.
        let q = quality_of(&log, false);
        assert_eq!(q.truth_turn_within_2_share, None);
    }
}
