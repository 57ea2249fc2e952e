//! `lplace eval --frame JSON`: evaluate one frame and print the decision.

use super::args::{ArgError, EvalArgs, Format};
use super::{load_engine, CliError, EXIT_OK};
use crate::engine::CompileOptions;
use crate::io::record::FrameRecord;
use std::io::Write;

/// Runs `eval` on one frame. A frame with any unusable percept is rejected whole (exit 2): on
/// the command line, a typo should not quietly change the answer.
pub fn run(args: &EvalArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let opts = CompileOptions {
        trace: args.trace,
        ..CompileOptions::default()
    };
    let mut engine = load_engine(&args.model, &opts)?;
    let record = FrameRecord::parse(&args.frame).map_err(ArgError::Frame)?;
    let mut frame = engine.new_frame();
    let mut rejected = Vec::new();
    record.fill(engine.percepts(), &mut frame, &mut rejected);
    if let Some(first) = rejected.into_iter().next() {
        return Err(ArgError::Frame(first).into());
    }
    engine.step(&frame);
    let outcome = engine.outcome();
    match args.format {
        Format::Json => {
            serde_json::to_writer_pretty(&mut *out, &outcome).map_err(std::io::Error::from)?;
            writeln!(out)?;
        }
        Format::Table => {
            match (&outcome.place, outcome.reason) {
                (Some(p), _) => writeln!(
                    out,
                    "place {p} (N = {:.3})",
                    outcome.necessity.unwrap_or(0.0)
                )?,
                (None, Some(r)) => {
                    writeln!(out, "disoriented: {r} {}", outcome.candidates.join(" vs "))?
                }
                (None, None) => writeln!(out, "disoriented")?,
            }
            writeln!(out, "Inc = {:.3}", outcome.inconsistency)?;
            writeln!(
                out,
                "{:<8} {:>7} {:>7} {:>7} {:>7}",
                "place", "support", "exclude", "Π", "N"
            )?;
            for p in &outcome.places {
                writeln!(
                    out,
                    "{:<8} {:>7.3} {:>7.3} {:>7.3} {:>7.3}",
                    p.place, p.support, p.exclusion, p.possibility, p.necessity
                )?;
            }
            for r in &outcome.rooms {
                writeln!(
                    out,
                    "room {:<3} support {:.3}  Π {:.3}  N {:.3}",
                    r.room, r.support, r.possibility, r.necessity
                )?;
            }
            for f in &outcome.fired {
                writeln!(
                    out,
                    "  rule {} @{} [{}] ⊢ {} = {:.3}",
                    f.rule,
                    f.context,
                    f.binding.join(" "),
                    f.head,
                    f.degree
                )?;
            }
        }
    }
    Ok(EXIT_OK)
}
