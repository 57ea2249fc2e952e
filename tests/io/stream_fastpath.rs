//! The JSON fast path of the stream reader agrees with the serde path: on random valid records
//! (random key orders, whitespace, number spellings, escapes, unknown keys and percepts) and on
//! mutated, hostile lines, a reader with the fast path gives exactly the same frame, meta data and
//! outcome — or the same rejection, word for word — as one without it, and neither panics.

use lplace::engine::{Engine, Frame, PerceptInstance};
use lplace::io::stream::{FrameMeta, ReadOutcome, Schema, StreamFormat, StreamReader};
use proptest::prelude::*;
use std::io::{BufRead, BufReader};

/// A JSON value as it will be spelled: numbers as raw text, strings optionally escaped.
#[derive(Debug, Clone)]
enum J {
    Raw(String),
    Str(String, bool),
    Arr(Vec<J>),
    Obj(Vec<(String, J)>),
}

const WS: [&str; 5] = ["", "", " ", "\t", " \r "];

/// Writes the next whitespace choice of `ws`.
fn pad(ws: &[u8], k: &mut usize, out: &mut String) {
    if !ws.is_empty() {
        out.push_str(WS[ws[*k % ws.len()] as usize % WS.len()]);
        *k += 1;
    }
}

/// Writes `j`, taking whitespace choices from `ws` in turn.
fn write(j: &J, ws: &[u8], k: &mut usize, out: &mut String) {
    match j {
        J::Raw(s) => out.push_str(s),
        J::Str(s, escaped) => out.push_str(&quote(s, *escaped)),
        J::Arr(items) => {
            out.push('[');
            for (i, x) in items.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                pad(ws, k, out);
                write(x, ws, k, out);
                pad(ws, k, out);
            }
            out.push(']');
        }
        J::Obj(members) => {
            out.push('{');
            for (i, (key, x)) in members.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                pad(ws, k, out);
                out.push_str(&quote(key, key.starts_with('t') && ws.len() % 3 == 0));
                pad(ws, k, out);
                out.push(':');
                pad(ws, k, out);
                write(x, ws, k, out);
                pad(ws, k, out);
            }
            out.push('}');
        }
    }
}

/// A JSON string by serde_json, or with its first character written as a `\u` escape.
fn quote(s: &str, escaped: bool) -> String {
    match s.chars().next() {
        Some(c) if escaped && c.is_ascii() => {
            format!(
                "\"\\u{:04x}{}",
                c as u32,
                &serde_json::to_string(s).unwrap()[2..]
            )
        }
        _ => serde_json::to_string(s).unwrap(),
    }
}

/// Number spellings: what the simulator writes, what serde_json writes for any float, and the
/// corners of the JSON grammar and of exact conversion.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (0u32..=1000).prop_map(|k| serde_json::to_string(&(f64::from(k) / 1000.0)).unwrap()),
        2 => (-100_000i64..100_000).prop_map(|k| serde_json::to_string(&(k as f64 / 1000.0)).unwrap()),
        2 => any::<f64>().prop_map(|f| serde_json::to_string(&f).unwrap()),
        1 => any::<i64>().prop_map(|i| i.to_string()),
        1 => prop::sample::select(vec![
            "0", "-0", "1", "1.0", "0.5", "-0.0", "1e0", "1E-3", "5e-1", "2.5e+1", "1e22", "1e23",
            "9007199254740992", "9007199254740993", "0.30000000000000004", "123456789012345.6",
            "1.7976931348623157e308", "1e400", "4.9e-324", "\"NaN\"", "\"inf\"", "\"-Infinity\"",
            "null", "01", "1.", ".5", "+1", "-", "1e", "0x1", "true", "\"1\"", "[]", "{}",
        ])
        .prop_map(str::to_string),
    ]
}

fn degree() -> impl Strategy<Value = String> {
    prop_oneof![
        6 => (0u32..=1000).prop_map(|k| serde_json::to_string(&(f64::from(k) / 1000.0)).unwrap()),
        1 => number(),
    ]
}

fn instances() -> (Vec<PerceptInstance>, Vec<String>) {
    let engine = Engine::office().expect("bundled office example loads");
    let places = engine
        .map()
        .places()
        .iter()
        .map(|p| p.name.clone())
        .collect();
    (engine.percepts().instances().to_vec(), places)
}

/// One percept object: a declared instance (mostly) or a made-up one, its members shuffled.
fn percept(insts: Vec<PerceptInstance>) -> impl Strategy<Value = J> {
    let n = insts.len();
    (
        0..n + 2,
        prop::option::of(number()),
        degree(),
        any::<bool>(),
        any::<u8>(),
        prop::collection::vec(any::<u32>(), 6),
    )
        .prop_map(move |(i, value, degree, escaped, extra, order)| {
            let (name, args) = match insts.get(i) {
                Some(p) => (p.name.clone(), p.args.clone()),
                None if i == n => ("bogus".to_string(), vec![]),
                None => (insts[0].name.clone(), vec!["Nowhere".to_string()]),
            };
            let mut m = vec![("name".to_string(), J::Str(name, escaped && extra % 4 == 0))];
            if !args.is_empty() || extra % 3 == 0 {
                let a = args.into_iter().map(|a| J::Str(a, false)).collect();
                m.push(("args".to_string(), J::Arr(a)));
            }
            if let Some(v) = value {
                m.push(("value".to_string(), J::Raw(v)));
            }
            if extra % 17 != 0 {
                m.push(("degree".to_string(), J::Raw(degree)));
            }
            if extra % 29 == 0 {
                m.push(("note".to_string(), J::Raw("[1,{\"a\":null}]".to_string())));
            }
            if extra % 31 == 0 {
                m.push(("degree".to_string(), J::Raw("0.5".to_string())));
            }
            shuffle(m, &order)
        })
}

fn shuffle(m: Vec<(String, J)>, order: &[u32]) -> J {
    let mut keyed: Vec<(u32, (String, J))> = m
        .into_iter()
        .enumerate()
        .map(|(i, x)| (order.get(i).copied().unwrap_or(0), x))
        .collect();
    keyed.sort_by_key(|(k, _)| *k);
    J::Obj(keyed.into_iter().map(|(_, x)| x).collect())
}

/// One record line.
fn record() -> impl Strategy<Value = String> {
    let (insts, places) = instances();
    (
        prop::collection::vec(percept(insts), 0..8),
        prop::option::of(prop::sample::select(vec!["1", "2", "1.0", "null", "01"])),
        prop::option::of(number()),
        prop::option::of((
            prop::option::of(number()),
            prop::option::of(number()),
            prop::option::of(number()),
        )),
        prop::option::of((
            prop::option::of(prop::option::of(0..places.len() + 1)),
            prop::option::of(prop::collection::vec(number(), 2..5)),
        )),
        (
            any::<u8>(),
            prop::collection::vec(any::<u32>(), 7),
            prop::option::of(number()),
        ),
        prop::collection::vec(any::<u8>(), 0..12),
    )
        .prop_map(
            move |(ps, version, t, odo, truth, (extra, order, heading), ws)| {
                let mut m = Vec::new();
                if extra % 23 != 0 {
                    m.push(("percepts".to_string(), J::Arr(ps)));
                }
                if let Some(v) = version {
                    m.push(("version".to_string(), J::Raw(v.to_string())));
                }
                if let Some(t) = t {
                    m.push(("t".to_string(), J::Raw(t)));
                }
                if let Some((dx, dy, dtheta)) = odo {
                    let o: Vec<(String, J)> = [("dx", dx), ("dy", dy), ("dtheta", dtheta)]
                        .into_iter()
                        .filter_map(|(k, v)| v.map(|v| (k.to_string(), J::Raw(v))))
                        .collect();
                    let o = if extra % 19 == 0 {
                        J::Raw("null".into())
                    } else {
                        J::Obj(o)
                    };
                    m.push(("odometry".to_string(), o));
                }
                if let Some(h) = heading {
                    let h = if extra % 13 == 0 {
                        "null".to_string()
                    } else {
                        h
                    };
                    m.push(("heading".to_string(), J::Raw(h)));
                }
                if let Some((place, pose)) = truth {
                    let mut tm = Vec::new();
                    if let Some(p) = place {
                        let v = match p {
                            None => J::Raw("null".into()),
                            Some(i) => J::Str(
                                places.get(i).cloned().unwrap_or_else(|| "P99".into()),
                                false,
                            ),
                        };
                        tm.push(("place".to_string(), v));
                    }
                    if let Some(pose) = pose {
                        tm.push((
                            "pose".to_string(),
                            J::Arr(pose.into_iter().map(J::Raw).collect()),
                        ));
                    }
                    m.push(("truth".to_string(), J::Obj(tm)));
                }
                if extra % 37 == 0 {
                    m.push(("comment".to_string(), J::Str("hi".into(), false)));
                }
                if extra % 41 == 0 {
                    m.push(("t".to_string(), J::Raw("3".into())));
                }
                let mut out = String::new();
                write(&shuffle(m, &order), &ws, &mut 0, &mut out);
                out
            },
        )
}

/// A record with a few bytes deleted, inserted, replaced or cut off.
fn hostile() -> impl Strategy<Value = Vec<u8>> {
    const BYTES: &[u8] = b"\"\\,:{}[]-+.eE0159 nul\t\r\n\x01\x7f\xc3\xa9\xff";
    (
        record(),
        prop::collection::vec(
            (
                0u8..4,
                any::<prop::sample::Index>(),
                any::<prop::sample::Index>(),
            ),
            1..4,
        ),
    )
        .prop_map(|(line, edits)| {
            let mut b = line.into_bytes();
            for (op, at, with) in edits {
                let c = BYTES[with.index(BYTES.len())];
                let i = if b.is_empty() { 0 } else { at.index(b.len()) };
                match op {
                    0 if !b.is_empty() => {
                        b.remove(i);
                    }
                    1 => b.insert(i, c),
                    2 if !b.is_empty() => b[i] = c,
                    _ => b.truncate(i),
                }
            }
            b
        })
}

/// Everything a reader produced for one stream, with floats compared by their bits. The fast
/// reader sees the whole input in one buffer (every line parsed where it lies); the serde reader
/// gets it through a tiny buffer, so that its lines are split across refills and copied.
fn read_all(bytes: &[u8], fast: bool) -> Vec<String> {
    let engine = Engine::office().expect("bundled office example loads");
    let schema = Schema::new(engine.percepts(), engine.map());
    let input: Box<dyn BufRead> = if fast {
        Box::new(bytes)
    } else {
        Box::new(BufReader::with_capacity(16, bytes))
    };
    let mut reader = StreamReader::new(input, schema, StreamFormat::JsonLines);
    reader.set_fast_path(fast);
    let mut frame = engine.new_frame();
    let mut meta = FrameMeta::default();
    let mut out = Vec::new();
    loop {
        match reader.next_frame(&mut frame, &mut meta) {
            Err(e) => {
                out.push(format!("io error {e}"));
                break;
            }
            Ok(ReadOutcome::End) => break,
            Ok(ReadOutcome::Rejected(e)) => out.push(format!("rejected {e:?}")),
            Ok(ReadOutcome::Frame) => out.push(describe(&frame, &meta)),
        }
    }
    out
}

fn describe(frame: &Frame, meta: &FrameMeta) -> String {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let o = meta.odometry;
    format!(
        "frame line={} t={:?} odo={:?} heading={:?} truth={} {:?} {:?} degree={:?} value={:?}",
        meta.line,
        meta.t.map(f64::to_bits),
        [o.dx.to_bits(), o.dy.to_bits(), o.dtheta.to_bits()],
        meta.heading.map(f64::to_bits),
        meta.truth_known,
        meta.truth_place,
        meta.truth_pose.map(|p| p.map(f64::to_bits)),
        bits(&frame.degree),
        bits(&frame.value),
    )
}

fn agree(bytes: &[u8]) -> Result<(), TestCaseError> {
    let fast = read_all(bytes, true);
    let slow = read_all(bytes, false);
    prop_assert_eq!(fast, slow, "stream:\n{}", String::from_utf8_lossy(bytes));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn valid_records_agree(lines in prop::collection::vec(record(), 1..6)) {
        agree(lines.join("\n").as_bytes())?;
    }

    #[test]
    fn hostile_lines_agree(
        lines in prop::collection::vec(
            prop_oneof![record().prop_map(String::into_bytes), hostile()],
            1..6,
        ),
    ) {
        agree(&lines.join(&b'\n'))?;
    }
}

/// The bundled recording (simulator output) reads the same on both paths.
#[test]
fn simulated_stream_agrees() {
    let text = include_str!("../../recordings/office.jsonl");
    let fast = read_all(text.as_bytes(), true);
    assert_eq!(fast, read_all(text.as_bytes(), false));
    assert!(fast.iter().all(|l| l.starts_with("frame")));
}
