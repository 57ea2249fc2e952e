//! Issue 16 row 7: a record's time is judged against both of its neighbours, so one corrupt
//! time is the one record rejected; concatenated logs read with `TimePolicy::Restart` keep every
//! record and mark each restart. Issue 21 item 6: a malformed line is described in our words.

use lplace::engine::Engine;
use lplace::io::stream::{
    FrameMeta, ReadOutcome, Rejection, Schema, StreamFormat, StreamReader, TimePolicy,
};

/// What the reader made of each record: `Ok(meta)` for a frame, `Err((line, rejection))`.
type Outcome = Result<FrameMeta, (u64, Rejection)>;

fn read(text: &str, policy: TimePolicy, fast: bool) -> Vec<Outcome> {
    let engine = Engine::office().expect("bundled office example loads");
    let schema = Schema::new(engine.percepts(), engine.map());
    let mut reader = StreamReader::new(text.as_bytes(), schema, StreamFormat::JsonLines)
        .with_time_policy(policy);
    reader.set_fast_path(fast);
    let mut frame = engine.new_frame();
    let mut meta = FrameMeta::default();
    let mut out = Vec::new();
    loop {
        match reader.next_frame(&mut frame, &mut meta).expect("in memory") {
            ReadOutcome::Frame => out.push(Ok(meta)),
            ReadOutcome::Rejected(e) => out.push(Err((e.line, e.reason))),
            ReadOutcome::End => return out,
        }
    }
}

fn record(t: f64) -> String {
    format!(
        r#"{{"t":{t},"odometry":{{"dx":0.1,"dy":0,"dtheta":0}},"percepts":[{{"name":"sonar_wall","args":["West"],"degree":0.8}}]}}"#
    )
}

fn stream(times: &[f64]) -> String {
    times.iter().map(|&t| record(t) + "\n").collect()
}

fn rejected_lines(out: &[Outcome]) -> Vec<u64> {
    out.iter()
        .filter_map(|o| o.as_ref().err().map(|e| e.0))
        .collect()
}

#[test]
fn a_time_far_ahead_on_line_2_is_the_one_record_rejected() {
    let mut times: Vec<f64> = (0..2500).map(|k| k as f64 * 0.1).collect();
    times[1] = 1e9;
    for fast in [true, false] {
        let out = read(&stream(&times), TimePolicy::Monotone, fast);
        assert_eq!(out.len(), 2500);
        assert_eq!(rejected_lines(&out), [2]);
        assert!(matches!(
            out[1],
            Err((2, Rejection::TimeOutlier { t, next })) if t == 1e9 && next == 0.2
        ));
        // Frames come out in line order, every good one kept.
        let lines: Vec<u64> = out
            .iter()
            .filter_map(|o| o.as_ref().ok())
            .map(|m| m.line)
            .collect();
        assert_eq!(lines.len(), 2499);
        assert!(lines.windows(2).all(|w| w[0] < w[1]));
    }
}

#[test]
fn a_time_far_behind_is_the_one_record_rejected() {
    let out = read(
        &stream(&[1.0, 2.0, -7.0, 3.0, 4.0]),
        TimePolicy::Monotone,
        true,
    );
    assert_eq!(rejected_lines(&out), [3]);
    assert!(matches!(out[2], Err((3, Rejection::TimeBackwards { .. }))));
}

#[test]
fn concatenated_logs_restart_only_when_asked() {
    let times = [0.0, 0.1, 0.2, 0.3, 0.0, 0.1, 0.2, 0.0, 0.1];
    let text = stream(&times);
    let strict = read(&text, TimePolicy::Monotone, true);
    assert_eq!(rejected_lines(&strict), [5, 6, 7, 8, 9]);
    let lenient = read(&text, TimePolicy::Restart, true);
    assert_eq!(rejected_lines(&lenient), Vec::<u64>::new());
    let restarts: Vec<(u64, f64)> = lenient
        .iter()
        .filter_map(|o| o.as_ref().ok())
        .filter_map(|m| m.restart_note().map(|n| (n.line, n.previous)))
        .collect();
    assert_eq!(restarts, [(5, 0.3), (8, 0.2)]);
    assert_eq!(
        lenient[4]
            .as_ref()
            .ok()
            .and_then(|m| m.restart_note())
            .map(|n| n.to_string()),
        Some("5: note: time starts again at t = 0 after t = 0.3 (--time restart)".to_string())
    );
}

/// Other rejections between a held record and the next come out after it: line order always.
#[test]
fn records_and_rejections_come_out_in_line_order() {
    let text = [
        record(1.0),
        record(2.0),
        "{x".to_string(),
        r#"{"percepts":[{"name":"radar","degree":0.5}]}"#.to_string(),
        record(3.0),
        "".to_string(),
        record(1e9),
        "not json".to_string(),
        record(4.0),
    ]
    .join("\n");
    let out = read(&text, TimePolicy::Monotone, true);
    let lines: Vec<u64> = out
        .iter()
        .map(|o| match o {
            Ok(m) => m.line,
            Err((l, _)) => *l,
        })
        .collect();
    assert_eq!(lines, [1, 2, 3, 4, 5, 7, 8, 9]);
    assert_eq!(rejected_lines(&out), [3, 4, 7, 8]);
}

#[test]
fn a_malformed_line_is_described_in_our_words_with_one_position() {
    let text = format!("{}\n{{x\n{}\n", record(1.0), record(2.0));
    let out = read(&text, TimePolicy::Monotone, false);
    let Err((line, reason)) = &out[1] else {
        panic!("line 2 is rejected: {out:?}");
    };
    let shown = lplace::io::stream::LineError {
        line: *line,
        reason: reason.clone(),
    }
    .to_string();
    assert_eq!(
        shown,
        "2:2: not JSON: an object key must be a quoted string"
    );
    assert!(!shown.contains("at line"), "{shown}");
}
