//! Reads a percept stream with ground-truth places (e.g. `lplace extract --from carmen … --map
//! maps/intel.map`) and prints, per place, the median value of each valued percept over the
//! frames inside that place — how the `param` expectations of `maps/intel.map` are read off a
//! log. The output is one `param NAME(ARG) = V;` line per place and percept, to paste into the
//! map by hand.
//!
//! `cargo run --release --example fit_place_params -- STREAM.jsonl [PERCEPT=PARAM …]`
//! (e.g. `free_range=free`: the map parameter name for a percept; default: the percept name).

use lplace::io::record::FrameRecord;
use std::collections::BTreeMap;
use std::io::BufRead;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: fit_place_params STREAM [PERCEPT=PARAM …]")?;
    let rename: BTreeMap<String, String> = args
        .filter_map(|a| a.split_once('=').map(|(k, v)| (k.to_owned(), v.to_owned())))
        .collect();
    let file = std::io::BufReader::new(std::fs::File::open(&path)?);
    // place → (param, arg) → values
    let mut values: BTreeMap<String, BTreeMap<(String, String), Vec<f64>>> = BTreeMap::new();
    for (n, line) in file.lines().enumerate() {
        let line = line?;
        let rec = FrameRecord::parse(&line).map_err(|e| format!("{path}:{}: {e}", n + 1))?;
        let Some(place) = rec.truth.and_then(|t| t.place) else {
            continue;
        };
        for p in rec.percepts {
            let Some(v) = p.value.filter(|v| v.is_finite()) else {
                continue;
            };
            let name = rename.get(&p.name).cloned().unwrap_or(p.name);
            let arg = p.args.join(", ");
            values
                .entry(place.clone())
                .or_default()
                .entry((name, arg))
                .or_default()
                .push(v);
        }
    }
    for (place, params) in values {
        let mut line = format!("{place}:");
        for ((name, arg), mut v) in params {
            v.sort_by(f64::total_cmp);
            let m = v.len();
            let median = if m % 2 == 1 {
                v[m / 2]
            } else {
                0.5 * (v[m / 2 - 1] + v[m / 2])
            };
            let arg = if arg.is_empty() {
                String::new()
            } else {
                format!("({arg})")
            };
            line.push_str(&format!(" param {name}{arg} = {median:.2};"));
        }
        println!("{line}");
    }
    Ok(())
}
