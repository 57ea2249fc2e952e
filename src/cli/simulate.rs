//! `lplace simulate`: a simulated robot's percept stream with ground truth (see [`crate::sim`]),
//! as JSON Lines or CSV, on stdout or into a file.

use super::args::{ArgError, ModelArgs, SimulateArgs, StreamForm};
use super::output::{self, Output};
use super::{load_engine, CliError, EXIT_OK};
use crate::engine::{CompileOptions, Engine, PerceptSlot};
use crate::io::csv::CsvWriter;
use crate::sim::{SimConfig, Simulator};
use std::io::Write;
use std::path::Path;

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

/// Runs `simulate`. The output file (`-o`) is checked before anything runs and written
/// atomically.
pub fn run(args: &SimulateArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let cfg = config(args)?;
    if let Some(p) = &args.output {
        output::check(&[Output::file("--output", p)], &model_inputs(&args.model))?;
    }
    let engine = load_engine(&args.model, &CompileOptions::default())?;
    let sim = Simulator::for_engine(&engine, cfg);
    let write = |w: &mut dyn Write| write_stream(args.format, &engine, sim, w);
    match &args.output {
        Some(p) => output::write_atomic(p, write)?,
        None => {
            let mut w = std::io::BufWriter::new(&mut *out);
            write(&mut w)?;
            w.flush()?;
        }
    }
    Ok(EXIT_OK)
}

/// The `--map`/`--rules` files, as inputs no output may overwrite.
pub(super) fn model_inputs(model: &ModelArgs) -> Vec<(&'static str, &Path)> {
    let map = model.map.as_deref().map(|p| ("--map", p));
    let rules = model.rules.as_deref().map(|p| ("--rules", p));
    map.into_iter().chain(rules).collect()
}

fn write_stream(
    form: StreamForm,
    engine: &Engine,
    sim: Simulator,
    w: &mut dyn Write,
) -> std::io::Result<()> {
    match form {
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
    Ok(())
}
