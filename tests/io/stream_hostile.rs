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

/// Issue 16 row 5: one byte that is not UTF-8 in an MRCLAM file skipped that line's reader
/// entirely (`stream did not contain valid UTF-8`, the whole run lost). Now the line alone is
/// skipped and reported with its number; the good rows survive.
#[test]
fn a_non_utf8_byte_in_an_mrclam_file_skips_only_its_line() {
    use lplace::io::mrclam::MrclamError;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("mrclam-not-utf8");
    std::fs::create_dir_all(&dir).expect("scratch");
    let files: [(&str, &[u8]); 4] = [
        ("Barcodes.dat", b"# header\n1 5\n6 63\n"),
        (
            "Robot1_Odometry.dat",
            b"10.0 0.1 0.0\n10.5 \xff 0.0\n11.0 0.0 0.0\n11.5 0.0 0.0\n",
        ),
        ("Robot1_Measurement.dat", b"10.5 63 2.0 0.1\n"),
        (
            "Robot1_Groundtruth.dat",
            b"10.0 0.0 0.0 0.0\n11.0 0.1 0.0 0.0\n",
        ),
    ];
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).expect("scratch");
    }
    let d = lplace::io::mrclam_dir::load(&dir, &[1]).expect("the dataset loads");
    assert_eq!(d.skipped.len(), 1);
    assert!(d.skipped[0].path.ends_with("Robot1_Odometry.dat"));
    assert!(matches!(
        d.skipped[0].error,
        MrclamError::Malformed { line: 2, .. }
    ));
}
