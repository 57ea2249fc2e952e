//! Looks poses up in a map's place extents, as `lplace extract --map` labels its truth: the first
//! place (in map order) whose extent holds the point, boundary included.
//!
//! Reads `x y` per line on stdin (metres, the map's frame; anything after the second number is
//! ignored) and prints one line per input line: the place's name, or `-` outside every extent.
//! Used by `scripts/mrpt_side_by_side.py` to score another localizer's poses against the same
//! extents lplace is scored on.
//!
//! Run: `cargo run --release --example place_of_pose -- maps/intel.map < poses.txt`

use lplace::map::Map;
use lplace::syntax::parse_map;
use std::io::{BufRead, Write};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: place_of_pose MAP < poses (one `x y` per line)")?;
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{path}: {e}"))?;
    let problems = |d: Vec<lplace::syntax::diagnostic::Diagnostic>| {
        let first = d.first().map(|d| d.to_string()).unwrap_or_default();
        format!("{path}: {} problem(s), first: {first}", d.len())
    };
    let ast = parse_map(&text).map_err(problems)?;
    let map = Map::from_ast(&ast).map_err(problems)?;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    for (n, line) in std::io::stdin().lock().lines().enumerate() {
        let line = line?;
        let (x, y) = point(&line).ok_or_else(|| format!("stdin:{}: not `x y`: {line}", n + 1))?;
        let place = map.places().iter().find(|p| p.contains(x, y));
        writeln!(out, "{}", place.map_or("-", |p| p.name.as_str()))?;
    }
    out.flush()?;
    Ok(())
}

/// The two leading finite numbers of a line.
fn point(line: &str) -> Option<(f64, f64)> {
    let mut it = line.split_whitespace().map(str::parse::<f64>);
    let x = it.next()?.ok()?;
    let y = it.next()?.ok()?;
    (x.is_finite() && y.is_finite()).then_some((x, y))
}
