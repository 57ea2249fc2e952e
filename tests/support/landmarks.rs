//! The tiny landmark world the metric command tests share: three landmarks around a robot that
//! stands at (1, 1) facing +x and reads their ranges and bearings exactly.

use std::path::{Path, PathBuf};

/// The three landmarks, and optionally one place around the robot (`lplace grid` and the
/// pictures draw it; `lplace compare` needs landmarks only).
pub fn tiny_map(with_place: bool) -> String {
    let mut map = String::from(
        "map tiny;\n\
         landmark A at (0.0, 0.0) id 1;\n\
         landmark B at (3.0, 0.0) id 2;\n\
         landmark C at (0.0, 2.0) id 3;\n",
    );
    if with_place {
        map.push_str("place Middle spot at (1.0, 1.0) extent radius 0.5;\n");
    }
    map
}

/// A frame at `t` of the robot at (1, 1) reading the landmarks exactly; its truth says it
/// stands at `truth`, heading 0.
pub fn frame_at(t: f64, truth: (f64, f64)) -> String {
    let mut p = Vec::new();
    for (name, lx, ly) in [("A", 0.0f64, 0.0f64), ("B", 3.0, 0.0), ("C", 0.0, 2.0)] {
        let (dx, dy) = (lx - 1.0, ly - 1.0);
        p.push(format!(
            r#"{{"name":"landmark_range","args":["{name}"],"value":{},"degree":1.0}}"#,
            dx.hypot(dy)
        ));
        p.push(format!(
            r#"{{"name":"landmark_bearing","args":["{name}"],"value":{},"degree":1.0}}"#,
            dy.atan2(dx).to_degrees()
        ));
    }
    format!(
        r#"{{"version":1,"t":{t},"odometry":{{"dx":0,"dy":0,"dtheta":0}},"percepts":[{}],"truth":{{"pose":[{},{},0.0]}}}}"#,
        p.join(","),
        truth.0,
        truth.1
    )
}

/// [`frame_at`] with the truth where the robot is.
pub fn frame(t: f64) -> String {
    frame_at(t, (1.0, 1.0))
}

/// Writes `dir/tiny.map` ([`tiny_map`]) and `dir/s.jsonl` (`lines`); returns their paths.
pub fn write(dir: &Path, with_place: bool, lines: &[String]) -> (PathBuf, PathBuf) {
    let map = dir.join("tiny.map");
    std::fs::write(&map, tiny_map(with_place)).expect("scratch space is writable");
    let stream = dir.join("s.jsonl");
    std::fs::write(&stream, lines.join("\n") + "\n").expect("scratch space is writable");
    (map, stream)
}
