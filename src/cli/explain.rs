//! `lplace explain`: print each place's closed-form degree function.

use super::args::{ArgError, ExplainArgs};
use super::{load_engine, CliError, EXIT_OK};
use crate::engine::CompileOptions;
use std::io::Write;

/// Runs `explain`.
pub fn run(args: &ExplainArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let engine = load_engine(&args.model, &CompileOptions::default())?;
    let places = engine.map().places();
    let chosen: Vec<usize> = match &args.place {
        None => (0..places.len()).collect(),
        Some(name) => match places.iter().position(|p| &p.name == name) {
            Some(k) => vec![k],
            None => {
                let known = places
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ");
                return Err(ArgError::UnknownPlace {
                    name: name.clone(),
                    known,
                }
                .into());
            }
        },
    };
    let c = engine.compiled();
    let logic = engine.rules().logic;
    writeln!(
        out,
        "// t-norm {}, implication {}, normalisation {}; `x ~sim θ` compares percept x's value with θ",
        logic.tnorm.name(),
        logic.implication.name(),
        logic.normalisation.name()
    )?;
    for k in chosen {
        let name = &places[k].name;
        writeln!(
            out,
            "at_place({name}) = {}",
            c.tape.render(c.support[k], &c.percepts)
        )?;
        let ex = c.exclusion[k];
        if c.tape.ops.get(ex as usize) != Some(&crate::engine::tape::Op::Const(0.0)) {
            writeln!(
                out,
                "!at_place({name}) = {}",
                c.tape.render(ex, &c.percepts)
            )?;
        }
        if args.dissimilarity {
            writeln!(
                out,
                "  δ at_place({name}) = {}",
                c.tape.render_dissimilarity(c.support[k], &c.percepts)
            )?;
        }
    }
    if args.place.is_none() {
        for (r, room) in engine.map().rooms().iter().enumerate() {
            writeln!(
                out,
                "in_room({}) = {}",
                room.name,
                c.tape.render(c.rooms[r], &c.percepts)
            )?;
        }
    }
    Ok(EXIT_OK)
}
