//! Reads a percept stream with ground-truth places (e.g. `lplace extract --from carmen … --map
//! maps/intel.map`) and, per place, the values of the chosen valued percepts over the frames
//! inside that place — how the `param` expectations of `maps/intel.map` are read off a log.
//! Each expectation is the range from the `LO`-th to the `HI`-th quantile of the values (nearest
//! rank on the sorted values: index ⌊q·(n − 1)⌋; default 0.1 and 0.9), written
//! `param NAME(ARG) = lo .. hi;`.
//!
//! ```text
//! cargo run --release --example fit_place_params -- STREAM PERCEPT=PARAM… [--quantiles LO HI] [--map FILE]
//! ```
//!
//! `PERCEPT=PARAM` names the map parameter fitted from a percept (`free_range=free`). Without
//! `--map` the parameters are printed, one line per place; with it, the body `{ … }` of each
//! `place NAME … { … }` line of FILE whose place has frames is replaced by the fitted
//! parameters and the file is written back (a place must be declared on one line, as in
//! `maps/intel.map`). Places without frames keep their body.

use lplace::io::record::FrameRecord;
use std::collections::BTreeMap;
use std::io::BufRead;

/// place → (param, arg) → values
type Values = BTreeMap<String, BTreeMap<(String, String), Vec<f64>>>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let usage = "usage: fit_place_params STREAM PERCEPT=PARAM… [--quantiles LO HI] [--map FILE]";
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or(usage)?;
    let mut rename: BTreeMap<String, String> = BTreeMap::new();
    let (mut lo_q, mut hi_q) = (0.1, 0.9);
    let mut map_file: Option<String> = None;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--quantiles" => {
                lo_q = args.next().ok_or(usage)?.parse()?;
                hi_q = args.next().ok_or(usage)?.parse()?;
            }
            "--map" => map_file = Some(args.next().ok_or(usage)?),
            _ => {
                let (k, v) = a.split_once('=').ok_or(usage)?;
                rename.insert(k.to_owned(), v.to_owned());
            }
        }
    }
    if rename.is_empty() || !(0.0..=1.0).contains(&lo_q) || !(lo_q..=1.0).contains(&hi_q) {
        return Err(usage.into());
    }
    let file = std::io::BufReader::new(std::fs::File::open(&path)?);
    let mut values: Values = BTreeMap::new();
    for (n, line) in file.lines().enumerate() {
        let line = line?;
        let rec = FrameRecord::parse(&line).map_err(|e| format!("{path}:{}: {e}", n + 1))?;
        let Some(place) = rec.truth.and_then(|t| t.place) else {
            continue;
        };
        for p in rec.percepts {
            let (Some(v), Some(name)) = (p.value.filter(|v| v.is_finite()), rename.get(&p.name))
            else {
                continue;
            };
            values
                .entry(place.clone())
                .or_default()
                .entry((name.clone(), p.args.join(", ")))
                .or_default()
                .push(v);
        }
    }
    let mut bodies: BTreeMap<String, String> = BTreeMap::new();
    for (place, params) in values {
        let mut body = String::new();
        for ((name, arg), mut v) in params {
            v.sort_by(f64::total_cmp);
            let at = |q: f64| v[(q * (v.len() - 1) as f64).floor() as usize];
            let arg = if arg.is_empty() {
                String::new()
            } else {
                format!("({arg})")
            };
            body.push_str(&format!(
                " param {name}{arg} = {:.2} .. {:.2};",
                at(lo_q),
                at(hi_q)
            ));
        }
        bodies.insert(place, body);
    }
    match map_file {
        None => {
            for (place, body) in &bodies {
                println!("{place}:{body}");
            }
        }
        Some(m) => {
            let text = std::fs::read_to_string(&m)?;
            let mut out = String::with_capacity(text.len());
            for line in text.lines() {
                let name = line
                    .strip_prefix("place ")
                    .and_then(|rest| rest.split_whitespace().next());
                match (
                    name.and_then(|n| bodies.get(n)),
                    line.find('{'),
                    line.rfind('}'),
                ) {
                    (Some(body), Some(open), Some(close)) if open < close => {
                        out.push_str(&line[..=open]);
                        out.push_str(body);
                        out.push(' ');
                        out.push_str(&line[close..]);
                    }
                    _ => out.push_str(line),
                }
                out.push('\n');
            }
            std::fs::write(&m, out)?;
            eprintln!("{m}: fitted {} place(s)", bodies.len());
        }
    }
    Ok(())
}
