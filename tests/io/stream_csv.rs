//! Issue 16 row 11: CSV streams read with a real CSV reader (quoted cells), header problems
//! named by column, a UTF-8 byte-order mark accepted, and every line accounted for: frames +
//! rejected = lines, on any mix of good and bad lines (JSON Lines and CSV alike).

use lplace::engine::Engine;
use lplace::io::stream::{FrameMeta, ReadOutcome, Rejection, Schema, StreamFormat, StreamReader};
use proptest::prelude::*;

/// Frames read (line, degree of `sonar_wall(North)`) and rejections (line, reason), in order.
type Read = (Vec<(u64, f64)>, Vec<(u64, Rejection)>);

fn read(bytes: &[u8], format: StreamFormat) -> Read {
    let engine = Engine::office().expect("bundled office example loads");
    let schema = Schema::new(engine.percepts(), engine.map());
    let mut reader = StreamReader::new(bytes, schema, format);
    let slot = engine
        .percepts()
        .slot("sonar_wall", &["North"])
        .expect("declared");
    let mut frame = engine.new_frame();
    let mut meta = FrameMeta::default();
    let (mut frames, mut rejected) = (Vec::new(), Vec::new());
    loop {
        match reader.next_frame(&mut frame, &mut meta).expect("in memory") {
            ReadOutcome::Frame => frames.push((meta.line, frame.degree[slot.0 as usize])),
            ReadOutcome::Rejected(e) => rejected.push((e.line, e.reason)),
            ReadOutcome::End => return (frames, rejected),
        }
    }
}

#[test]
fn quoted_cells_are_read() {
    let text = "t,\"deg:sonar_wall(North)\",truth_place\n0,\"0.5\",\"P1\"\n0.1,0.25,\"\"\n";
    let (frames, rejected) = read(text.as_bytes(), StreamFormat::Csv);
    assert_eq!(rejected, []);
    assert_eq!(frames, [(2, 0.5), (3, 0.25)]);
}

#[test]
fn a_quote_left_open_is_that_row_rejected() {
    let text = "t,deg:sonar_wall(North)\n0,\"0.5\n0.1,0.25\n";
    let (frames, rejected) = read(text.as_bytes(), StreamFormat::Csv);
    assert_eq!(frames, [(3, 0.25)]);
    assert_eq!(rejected.len(), 1);
    assert_eq!(rejected[0].0, 2);
    assert!(
        rejected[0].1.to_string().contains("not closed"),
        "{:?}",
        rejected[0]
    );
}

#[test]
fn a_duplicate_column_is_an_error_naming_it() {
    let text = "t,deg:sonar_wall(North),t\n0,0.5,1\n0.1,0.25,2\n";
    let (frames, rejected) = read(text.as_bytes(), StreamFormat::Csv);
    assert_eq!(frames, []);
    let lines: Vec<u64> = rejected.iter().map(|r| r.0).collect();
    assert_eq!(lines, [1, 2, 3]);
    let header = rejected[0].1.to_string();
    assert!(header.contains("column `t`: given twice"), "{header}");
    assert_eq!(rejected[1].1, Rejection::NoCsvHeader);
    let text = "deg:sonar_wall(North),t,deg:sonar_wall(North)\n0.5,0,0.5\n";
    let (_, rejected) = read(text.as_bytes(), StreamFormat::Csv);
    assert!(rejected[0]
        .1
        .to_string()
        .contains("`deg:sonar_wall(North)`: given twice"));
}

#[test]
fn a_missing_header_is_an_error_not_a_frame_short() {
    let text = "0,0.5\n0.1,0.25\n0.2,0.3\n";
    let (frames, rejected) = read(text.as_bytes(), StreamFormat::Csv);
    assert_eq!(frames, []);
    assert_eq!(rejected.len(), 3);
    assert!(
        rejected[0].1.to_string().contains("is the header missing?"),
        "{:?}",
        rejected[0]
    );
}

#[test]
fn unknown_columns_are_one_report_and_ignored() {
    let text = "t,notes,deg:radar,deg:sonar_wall(North)\n0,hello,1,0.5\n";
    let (frames, rejected) = read(text.as_bytes(), StreamFormat::Csv);
    assert_eq!(frames, [(2, 0.5)]);
    assert_eq!(rejected.len(), 1);
    let msg = rejected[0].1.to_string();
    assert!(
        msg.contains("`notes`") && msg.contains("`deg:radar`"),
        "{msg}"
    );
}

#[test]
fn a_byte_order_mark_is_accepted() {
    let json = "\u{feff}{\"t\":0,\"percepts\":[{\"name\":\"sonar_wall\",\"args\":[\"North\"],\"degree\":0.5}]}\n";
    let (frames, rejected) = read(json.as_bytes(), StreamFormat::JsonLines);
    assert_eq!((frames.len(), rejected.len()), (1, 0), "{rejected:?}");
    let csv = "\u{feff}t,deg:sonar_wall(North)\n0,0.5\n";
    let (frames, rejected) = read(csv.as_bytes(), StreamFormat::Csv);
    assert_eq!((frames, rejected), (vec![(2, 0.5)], vec![]));
}

/// A good JSON line at time `t`, or one of several kinds of bad line.
fn json_line(kind: u8, t: f64) -> Vec<u8> {
    let good = format!(
        r#"{{"t":{t},"percepts":[{{"name":"sonar_wall","args":["North"],"degree":0.5}}]}}"#
    );
    match kind {
        0..=4 => good.into_bytes(),
        5 => b"{x".to_vec(),
        6 => br#"{"t":1,"percepts":[{"name":"radar","degree":0.5}]}"#.to_vec(),
        7 => format!(
            r#"{{"t":{t},"percepts":[{{"name":"sonar_wall","args":["North"],"degree":1.5}}]}}"#
        )
        .into_bytes(),
        8 => format!(r#"{{"t":{},"percepts":[]}}"#, t + 1e9).into_bytes(),
        9 => b"{\"t\":\xff,\"percepts\":[]}".to_vec(),
        _ => format!(r#"{{"t":{t},"percepts":[],"odometri":{{}}}}"#).into_bytes(),
    }
}

/// A good CSV row at time `t` (header `t,deg:sonar_wall(North),truth_place`), or a bad one.
fn csv_line(kind: u8, t: f64) -> Vec<u8> {
    match kind {
        0..=4 => format!("{t},0.5,P1").into_bytes(),
        5 => format!("{t},\"0.5,P1").into_bytes(),
        6 => format!("{t},0.5").into_bytes(),
        7 => format!("{t},1.5,P1").into_bytes(),
        8 => format!("{},0.5,P1", t + 1e9).into_bytes(),
        9 => [format!("{t},").into_bytes(), b"\xff0.5,P1".to_vec()].concat(),
        _ => format!("{t},abc,\"P1\"").into_bytes(),
    }
}

proptest! {
    #[test]
    fn frames_plus_rejected_is_lines(kinds in proptest::collection::vec(0u8..11, 0..60), csv in any::<bool>(), crlf in any::<bool>()) {
        let end: &[u8] = if crlf { b"\r\n" } else { b"\n" };
        let mut bytes = Vec::new();
        if csv {
            bytes.extend_from_slice(b"t,deg:sonar_wall(North),truth_place");
            bytes.extend_from_slice(end);
        }
        for (i, &k) in kinds.iter().enumerate() {
            let t = i as f64;
            bytes.extend(if csv { csv_line(k, t) } else { json_line(k, t) });
            bytes.extend_from_slice(end);
        }
        let format = if csv { StreamFormat::Csv } else { StreamFormat::JsonLines };
        let (frames, rejected) = read(&bytes, format);
        prop_assert_eq!(frames.len() + rejected.len(), kinds.len());
        // Kind 8 (a time 10⁹ s ahead) is the outlier when a good time follows it.
        if !kinds.contains(&8) {
            let good = kinds.iter().filter(|&&k| k <= 4).count();
            prop_assert_eq!(frames.len(), good);
        }
        // Every line once, in order.
        let header = u64::from(csv);
        let mut lines: Vec<u64> = frames.iter().map(|f| f.0).chain(rejected.iter().map(|r| r.0)).collect();
        lines.sort_unstable();
        prop_assert_eq!(lines, (1..=kinds.len() as u64).map(|l| l + header).collect::<Vec<_>>());
    }
}
