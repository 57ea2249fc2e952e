//! Reading ahead on a second thread hands the consumer exactly what reading on its own thread
//! does: the same frames, rejections and line numbers in the same order, a read error only after
//! every record before it, and an early stop when the consumer fails — on streams longer than
//! several batches, with rejections (even a run of nothing else) spread through them.

use lplace::engine::{Engine, Frame};
use lplace::io::stream::{
    read_records, FrameMeta, Record, Schema, StreamFormat, StreamReader, Threads,
};
use std::io::{BufRead, BufReader, Read};

/// A stream of `n` records from the bundled recording, with a bad line every `bad` lines
/// (malformed JSON, an unknown percept, a degree out of range, in turn) and a run of 600 bad
/// lines (more than a batch) in the middle.
fn stream(n: usize, bad: usize) -> Vec<u8> {
    let good: Vec<&str> = include_str!("../../recordings/office.jsonl")
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    let wrong = [
        "{not json",
        r#"{"percepts":[{"name":"no_such_percept","args":[],"degree":0.5}]}"#,
        r#"{"percepts":[{"name":"beacon_seen","args":[],"degree":7}]}"#,
    ];
    let mut out = String::new();
    for k in 0..n {
        if k % bad == bad - 1 || (n / 2..n / 2 + 600).contains(&k) {
            out.push_str(wrong[k % wrong.len()]);
        } else {
            out.push_str(good[k % good.len()]);
        }
        out.push('\n');
    }
    out.into_bytes()
}

fn describe(frame: &Frame, meta: &FrameMeta) -> String {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    format!(
        "frame {} {:?} {:?} {:?} {:?}",
        meta.line,
        meta.t.map(f64::to_bits),
        meta.truth_place,
        bits(&frame.degree),
        bits(&frame.value)
    )
}

/// Everything `read_records` handed over, and how it ended. `stop_after` makes the consumer
/// fail at that record.
fn collect(
    input: Box<dyn BufRead + Send>,
    threads: Threads,
    stop_after: Option<usize>,
) -> (Vec<String>, String) {
    let engine = Engine::office().expect("bundled office example loads");
    let schema = Schema::new(engine.percepts(), engine.map());
    let reader = StreamReader::new(input, schema, StreamFormat::JsonLines);
    let mut seen = Vec::new();
    let end = read_records(
        reader,
        threads,
        |_| {},
        |e| format!("read error: {e}"),
        |record| {
            seen.push(match record {
                Record::Frame(frame, meta) => describe(frame, meta),
                Record::Rejected(e) => format!("rejected {e}"),
            });
            if Some(seen.len()) == stop_after {
                return Err("consumer stopped".to_string());
            }
            Ok(())
        },
    );
    (seen, format!("{end:?}"))
}

#[test]
fn read_ahead_hands_over_the_same_records() {
    let bytes = stream(5000, 37);
    let one = collect(
        Box::new(std::io::Cursor::new(bytes.clone())),
        Threads::One,
        None,
    );
    let ahead = collect(
        Box::new(std::io::Cursor::new(bytes)),
        Threads::ReadAhead,
        None,
    );
    assert_eq!(one.1, "Ok(())");
    assert_eq!(one.0.len(), 5000);
    assert!(one.0.iter().filter(|r| r.starts_with("rejected")).count() > 600);
    assert!(one.0.iter().any(|r| r.starts_with("rejected 37:")));
    assert_eq!(one, ahead);
}

/// Input that yields `bytes` and then fails, as a disk or a pipe can.
struct FailingAfter {
    bytes: std::io::Cursor<Vec<u8>>,
}

impl Read for FailingAfter {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        match self.bytes.read(buf)? {
            0 => Err(std::io::Error::other("device gone")),
            n => Ok(n),
        }
    }
}

#[test]
fn read_error_comes_after_every_record_before_it() {
    // Cut in the middle of a line: the records before it are all consumed, then the error.
    let mut bytes = stream(1500, 50);
    bytes.truncate(bytes.len() * 2 / 3);
    let input = || -> Box<dyn BufRead + Send> {
        Box::new(BufReader::with_capacity(
            4096,
            FailingAfter {
                bytes: std::io::Cursor::new(bytes.clone()),
            },
        ))
    };
    let one = collect(input(), Threads::One, None);
    let ahead = collect(input(), Threads::ReadAhead, None);
    assert!(one.1.contains("device gone"), "{}", one.1);
    // More than two batches of records come before the error.
    assert!(
        one.0.len() > 600,
        "{} records before the error",
        one.0.len()
    );
    assert_eq!(one, ahead);
}

#[test]
fn consumer_error_stops_reading() {
    let bytes = stream(3000, 41);
    for stop in [1, 255, 256, 257, 1000] {
        let one = collect(
            Box::new(std::io::Cursor::new(bytes.clone())),
            Threads::One,
            Some(stop),
        );
        let ahead = collect(
            Box::new(std::io::Cursor::new(bytes.clone())),
            Threads::ReadAhead,
            Some(stop),
        );
        assert_eq!(one.0.len(), stop);
        assert_eq!(one.1, r#"Err("consumer stopped")"#);
        assert_eq!(one, ahead, "stop at {stop}");
    }
}

#[test]
fn empty_stream() {
    let one = collect(Box::new(&b""[..]), Threads::One, None);
    let ahead = collect(Box::new(&b""[..]), Threads::ReadAhead, None);
    assert_eq!(one, (Vec::new(), "Ok(())".to_string()));
    assert_eq!(one, ahead);
}
