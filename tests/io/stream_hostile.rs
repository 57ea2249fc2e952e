//! Issue 16 row 12: a misspelt or repeated key in a JSON record is a rejected record (with the
//! key named), never a value silently dropped or silently overwritten — on both reading paths.

use lplace::engine::Engine;
use lplace::io::stream::{FrameMeta, ReadOutcome, Rejection, Schema, StreamFormat, StreamReader};

/// The outcome of each line of `text`: `None` for a frame, else the rejection.
fn outcomes(text: &str, fast: bool) -> Vec<Option<Rejection>> {
    let engine = Engine::office().expect("bundled office example loads");
    let schema = Schema::new(engine.percepts(), engine.map());
    let mut reader = StreamReader::new(text.as_bytes(), schema, StreamFormat::JsonLines);
    reader.set_fast_path(fast);
    let mut frame = engine.new_frame();
    let mut meta = FrameMeta::default();
    let mut out = Vec::new();
    loop {
        match reader.next_frame(&mut frame, &mut meta) {
            Ok(ReadOutcome::Frame) => out.push(None),
            Ok(ReadOutcome::Rejected(e)) => out.push(Some(e.reason)),
            Ok(ReadOutcome::End) | Err(_) => break,
        }
    }
    out
}

const GOOD: &str = r#"{"version":1,"t":0,"odometry":{"dx":0.1,"dy":0,"dtheta":0},"percepts":[{"name":"sonar_wall","args":["West"],"degree":0.8}],"truth":{"place":"P4","pose":[5.5,2.0,0.0]}}"#;

fn key(k: &str, within: &'static str, twice: bool) -> Option<Rejection> {
    let key = k.to_string();
    Some(if twice {
        Rejection::DuplicateKey { key, within }
    } else {
        Rejection::UnknownKey { key, within }
    })
}

#[test]
fn misspelt_and_repeated_keys_are_rejected_records() {
    let lines = [
        GOOD.to_string(),
        GOOD.replace("\"odometry\"", "\"odometri\""),
        GOOD.replace("{\"version\":1,", "{\"version\":1,\"version\":1,"),
        GOOD.replace("\"degree\":0.8", "\"degree\":0.8,\"degre\":0.9"),
        GOOD.replace("\"degree\":0.8", "\"degree\":0.8,\"degree\":0.9"),
        GOOD.replace("\"place\":\"P4\"", "\"place\":\"P4\",\"plase\":\"P3\""),
        GOOD.replace("\"t\":0,", "\"t\":0,\"t\":1,"),
    ];
    let text = lines.join("\n") + "\n";
    let want = vec![
        None,
        key("odometri", "record", false),
        key("version", "record", true),
        key("degre", "percept", false),
        key("degree", "percept", true),
        key("plase", "truth", false),
        key("t", "record", true),
    ];
    assert_eq!(outcomes(&text, false), want);
    assert_eq!(outcomes(&text, true), want);
}

#[test]
fn an_unknown_odometry_component_is_malformed() {
    let line = GOOD.replace("\"dtheta\":0", "\"dtheta\":0,\"dz\":1") + "\n";
    for fast in [false, true] {
        let got = outcomes(&line, fast);
        assert!(
            matches!(got.as_slice(), [Some(Rejection::Malformed { .. })]),
            "{got:?}"
        );
    }
}
