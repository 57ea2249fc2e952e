//! Writes a JSON Lines percept stream as lplace's CSV stream, the form the C example
//! (`examples/c/controller.c`) reads, since C has no JSON parser at hand.
//!
//! `cargo run --release -p lplace-c --example stream_to_csv -- [STREAM.jsonl [MAP RULES]]`
//! (default: `recordings/office.jsonl` with the bundled office map and rules). Every percept
//! instance of the rules gets a degree and a value column; percepts the rules do not declare
//! are left out; a malformed line stops the conversion with its line number.

use std::io::{BufRead, BufReader, BufWriter, Write};

use lplace::engine::Engine;
use lplace::io::csv::CsvWriter;
use lplace::io::record::FrameRecord;
use lplace::syntax::SourceFile;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let stream = args.first().cloned().unwrap_or_else(|| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../recordings/office.jsonl").to_owned()
    });
    let engine = match (args.get(1), args.get(2)) {
        (Some(m), Some(r)) => Engine::load(
            &SourceFile::new(m.as_str(), std::fs::read_to_string(m)?),
            &SourceFile::new(r.as_str(), std::fs::read_to_string(r)?),
        )?,
        _ => Engine::office()?,
    };
    let csv = CsvWriter::new(engine.percepts(), |_| true);
    let mut out = BufWriter::new(std::io::stdout().lock());
    csv.write_header(&mut out)?;
    for (i, line) in BufReader::new(std::fs::File::open(&stream)?)
        .lines()
        .enumerate()
    {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let rec = FrameRecord::parse(&line).map_err(|e| format!("{stream}:{}: {e}", i + 1))?;
        csv.write_row(&rec, &mut out)?;
    }
    out.flush()?;
    Ok(())
}
