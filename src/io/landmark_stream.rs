//! Landmark percept streams — what `lplace extract --from mrclam` writes and `lplace grid` and
//! `lplace compare` read — read through the one stream reader ([`StreamReader`]), so that they
//! are validated, reported and counted exactly as `lplace eval`'s streams are.
//!
//! A landmark stream has no rule file to declare its percepts; its [`Schema`] is built from the
//! map instead ([`schema`]): `landmark_range(NAME)` and `landmark_bearing(NAME)` for every name a
//! subject can carry ([`subject_names`]) — the map's landmarks, and the names `extract` gives to
//! the MRCLAM subjects the map does not name ([`subject_name`]: the other robots, whose sightings
//! are in every robot's stream). Truth places are the map's places. A record naming anything else
//! is rejected with its line number, as `eval` rejects a percept its rule file does not declare.
//!
//! Frames are converted by [`RecordReader::convert_parts`], in the order the record wrote its
//! percepts ([`StreamReader::percept_order`]): the grid applies a frame's sightings one after the
//! other, so their order is part of the result.
//!
//! Depends on `engine::frame` (the reader's frame), `io::stream`, `io::mrclam_stream` and `map`;
//! it reads only the `BufRead` it is given.

use crate::engine::{Frame, PerceptInstance};
use crate::io::mrclam_stream::{robot_name, Reading, RecordReader, BEARING, RANGE, ROBOTS};
use crate::io::stream::{FrameMeta, LineError, ReadOutcome, Schema, StreamReader, TimeRestart};
use crate::localize::MetricFrame;
use crate::map::Map;
use std::collections::BTreeMap;
use std::io::BufRead;

/// MRCLAM's subject ids: 1–5 are the robots ([`ROBOTS`]), 6–20 the landmarks (the data set's
/// README).
const SUBJECTS: std::ops::RangeInclusive<u32> = 1..=20;

/// The name of MRCLAM subject `id` in a stream: the map's name for it (`names`: map landmark
/// ids to names), else `Robot{id}` for a robot, else `S{id}`.
pub fn subject_name(names: &BTreeMap<u32, String>, id: u32) -> String {
    match names.get(&id) {
        Some(n) => n.clone(),
        None if ROBOTS.contains(&id) => robot_name(id),
        None => format!("S{id}"),
    }
}

/// The map's landmark ids and names.
pub fn landmark_names(map: &Map) -> BTreeMap<u32, String> {
    map.landmarks()
        .iter()
        .filter_map(|l| Some((u32::try_from(l.id?).ok()?, l.name.clone())))
        .collect()
}

/// Every subject name a landmark stream over `map` may carry: the map's landmarks (with an id
/// or not), then the [`subject_name`]s of the MRCLAM subjects the map does not name.
pub fn subject_names(map: &Map) -> Vec<String> {
    let mut out: Vec<String> = map.landmarks().iter().map(|l| l.name.clone()).collect();
    let named = landmark_names(map);
    for id in SUBJECTS {
        let name = subject_name(&named, id);
        if !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// The schema of a landmark stream over `map` (see the module docs).
pub fn schema(map: &Map) -> Schema {
    let mut instances = Vec::new();
    for name in subject_names(map) {
        for percept in [RANGE, BEARING] {
            instances.push(PerceptInstance {
                name: percept.to_string(),
                args: vec![name.clone()],
            });
        }
    }
    let places = map.places().iter().map(|p| p.name.clone()).collect();
    Schema::from_instances(instances, places)
}

/// What [`read_frames`] reports besides the frames.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// A rejected record.
    Rejected(LineError),
    /// A record where the clock starts again (a reader with `TimePolicy::Restart`).
    Restart(TimeRestart),
}

/// Reads every record of `reader` (built with [`schema`]) and converts each frame with `conv`;
/// every rejected record and every clock restart goes to `report`, in stream order.
///
/// # Errors
/// A read error of the input.
pub fn read_frames<R: BufRead>(
    mut reader: StreamReader<R>,
    conv: &mut RecordReader,
    mut report: impl FnMut(Event),
) -> std::io::Result<Vec<MetricFrame>> {
    let mut frame = Frame::new(reader.schema().slots());
    let mut meta = FrameMeta::default();
    let mut frames = Vec::new();
    loop {
        match reader.next_frame(&mut frame, &mut meta)? {
            ReadOutcome::End => return Ok(frames),
            ReadOutcome::Rejected(e) => report(Event::Rejected(e)),
            ReadOutcome::Frame => {
                if let Some(n) = meta.restart_note() {
                    report(Event::Restart(n));
                }
                let schema = reader.schema();
                let percepts = reader.percept_order().iter().filter_map(|&slot| {
                    let instance = schema.instance(slot)?;
                    let i = slot.0 as usize;
                    Some(Reading {
                        name: &instance.name,
                        subject: instance.args.first().map(String::as_str),
                        // The frame's NaN means "no value"; the stream reader rejects NaN values.
                        value: frame.value.get(i).copied().filter(|v| !v.is_nan()),
                        degree: frame.degree.get(i).copied().unwrap_or(0.0),
                    })
                });
                frames.push(conv.convert_parts(meta.t, meta.odometry, meta.truth_pose, percepts));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::stream::{Rejection, StreamFormat};

    fn map() -> Map {
        let src = "landmark A at (0, 0) id 6;\nlandmark B at (1, 0);\n\
                   place P spot at (0, 1) extent radius 1;";
        let ast = crate::syntax::parse_map(src).expect("test map parses");
        Map::from_ast(&ast).expect("test map builds")
    }

    #[test]
    fn names_cover_the_map_the_robots_and_the_unnamed_landmark_ids() {
        let names = subject_names(&map());
        // A and B from the map; Robot1–5; S7–S20 (id 6 is A).
        assert_eq!(names.len(), 2 + 5 + 14);
        assert_eq!(&names[..3], ["A", "B", "Robot1"]);
        assert!(names.contains(&"S7".to_string()) && !names.contains(&"S6".to_string()));
        assert_eq!(names.last().map(String::as_str), Some("S20"));
    }

    #[test]
    fn frames_keep_the_record_order_and_bad_records_are_rejected_by_line() {
        let text = concat!(
            r#"{"t":1,"percepts":[{"name":"landmark_bearing","args":["B"],"value":90,"degree":1},"#,
            r#"{"name":"landmark_range","args":["A"],"value":2,"degree":1},"#,
            r#"{"name":"landmark_bearing","args":["A"],"value":0,"degree":1},"#,
            r#"{"name":"landmark_range","args":["B"],"value":1,"degree":1}]}"#,
            "\n",
            r#"{"t":2,"percepts":[{"name":"landmark_range","args":["A"],"value":2,"degree":1.5}]}"#,
            "\n",
            r#"{"t":0.5,"percepts":[]}"#,
            "\n",
            r#"{"t":3,"percepts":[{"name":"landmark_range","args":["Z"],"value":2,"degree":1}]}"#,
            "\n",
        );
        let reader = StreamReader::new(text.as_bytes(), schema(&map()), StreamFormat::JsonLines);
        let mut conv = RecordReader::new([("A".to_string(), 6), ("B".to_string(), 9)]);
        let mut bad = Vec::new();
        let frames = read_frames(reader, &mut conv, |e| match e {
            Event::Rejected(e) => bad.push(e),
            Event::Restart(n) => panic!("no restart asked for: {n}"),
        })
        .expect("in memory");
        assert_eq!(frames.len(), 1);
        // B was written first (its bearing), so its sighting comes first.
        let subjects: Vec<u32> = frames[0].observations.iter().map(|o| o.subject).collect();
        assert_eq!(subjects, [9, 6]);
        assert_eq!(frames[0].observations[0].range, 1.0);
        let lines: Vec<(u64, &str)> = bad.iter().map(|e| (e.line, e.reason.kind())).collect();
        assert_eq!(
            lines,
            [
                (2, "degree_out_of_range"),
                (3, "time_backwards"),
                (4, "unknown_percept")
            ]
        );
        assert!(matches!(
            &bad[2].reason,
            Rejection::UnknownPercept { instance } if instance == "landmark_range(Z)"
        ));
    }
}
