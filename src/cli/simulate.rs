//! `lplace simulate`: a simulated robot's percept stream with ground truth (see [`crate::sim`]),
//! as JSON Lines or CSV, on stdout or into a file.

use super::args::{ArgError, SimulateArgs, StreamForm};
use super::{load_engine, CliError, EXIT_OK};
use crate::engine::{CompileOptions, PerceptSlot};
use crate::io::csv::CsvWriter;
use crate::sim::{SimConfig, Simulator};
use std::io::Write;

/// Checks the numeric flags before anything runs.
fn config(args: &SimulateArgs) -> Result<SimConfig, ArgError> {
    let prob = [
        ("p-missing", args.p_missing),
        ("p-occlude", args.p_occlude),
        ("p-mislabel", args.p_mislabel),
        ("p-spurious", args.p_spurious),
    ];
    for (flag, value) in prob {
        if !(0.0..=1.0).contains(&value) {
            return Err(ArgError::OutOfRange {
                flag,
                value,
                range: "[0, 1]",
            });
        }
    }
    let nonneg = [
        ("heading-noise", args.heading_noise.unwrap_or(0.0)),
        ("speed", args.speed),
        ("angle-noise", args.angle_noise),
        ("range-noise", args.range_noise),
        ("odometry-noise", args.odometry_noise),
    ];
    for (flag, value) in nonneg {
        if !(value.is_finite() && value >= 0.0) {
            return Err(ArgError::OutOfRange {
                flag,
                value,
                range: "finite, ≥ 0",
            });
        }
    }
    Ok(SimConfig {
        steps: args.steps,
        seed: args.seed,
        speed: args.speed,
        p_missing: args.p_missing,
        p_occlude: args.p_occlude,
        p_mislabel: args.p_mislabel,
        p_spurious: args.p_spurious,
        angle_noise: args.angle_noise,
        range_noise: args.range_noise,
        odometry_noise: args.odometry_noise,
        kidnap_at: args.kidnap_at.clone(),
        heading_noise: args.heading_noise,
        ..SimConfig::default()
    })
}

/// Runs `simulate`.
pub fn run(args: &SimulateArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let cfg = config(args)?;
    let engine = load_engine(&args.model, &CompileOptions::default())?;
    let sim = Simulator::for_engine(&engine, cfg);
    let mut file;
    let mut stdout_w;
    let w: &mut dyn Write = match &args.output {
        Some(p) => {
            file = std::io::BufWriter::new(std::fs::File::create(p).map_err(|source| {
                CliError::Read {
                    path: p.display().to_string(),
                    source,
                }
            })?);
            &mut file
        }
        None => {
            stdout_w = std::io::BufWriter::new(&mut *out);
            &mut stdout_w
        }
    };
    match args.format {
        StreamForm::Jsonl => {
            for rec in sim {
                serde_json::to_writer(&mut *w, &rec).map_err(std::io::Error::from)?;
                w.write_all(b"\n")?;
            }
        }
        StreamForm::Csv => {
            let csv = CsvWriter::new(engine.percepts(), |s: PerceptSlot| {
                sim.has_value(s.0 as usize)
            });
            csv.write_header(&mut &mut *w)?;
            for rec in sim {
                csv.write_row(&rec, &mut &mut *w)?;
            }
        }
    }
    w.flush()?;
    Ok(EXIT_OK)
}
