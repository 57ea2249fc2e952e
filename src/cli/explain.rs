//! `lplace explain`: print each place's closed-form degree function, or one derived predicate's
//! (`--atom`), or how Π and N of a set of places are computed (`--query`).

use super::args::{ArgError, ExplainArgs};
use super::wrap::{wrap, WIDTH};
use super::{load_engine, CliError, EXIT_OK};
use crate::engine::tape::Op;
use crate::engine::{CompileOptions, Engine};
use std::io::Write;

/// Writes `lhs = rhs` wrapped to [`WIDTH`] columns.
fn line(out: &mut impl Write, lhs: &str, rhs: &str) -> std::io::Result<()> {
    writeln!(out, "{}", wrap(&format!("{lhs} = "), rhs, WIDTH))
}

/// Runs `explain`.
pub fn run(args: &ExplainArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let opts = CompileOptions {
        derived: args.atom.iter().cloned().collect(),
        ..CompileOptions::default()
    };
    let engine = load_engine(&args.model, &opts)?;
    let logic = engine.rules().logic;
    writeln!(
        out,
        "// t-norm {}, implication {}, normalisation {}; `x ~sim θ` compares percept x's value with θ",
        logic.tnorm.name(),
        logic.implication.name(),
        logic.normalisation.name()
    )?;
    if let Some(name) = &args.atom {
        return explain_atom(&engine, name, args.dissimilarity, out);
    }
    if let Some(q) = &args.query {
        return explain_query(&engine, q, out);
    }
    explain_places(&engine, args, out)
}

fn explain_places(
    engine: &Engine,
    args: &ExplainArgs,
    out: &mut impl Write,
) -> Result<u8, CliError> {
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
    for k in chosen {
        let name = &places[k].name;
        line(
            out,
            &format!("at_place({name})"),
            &c.tape.render(c.support[k], &c.percepts),
        )?;
        let ex = c.exclusion[k];
        if c.tape.ops.get(ex as usize) != Some(&Op::Const(0.0)) {
            line(
                out,
                &format!("!at_place({name})"),
                &c.tape.render(ex, &c.percepts),
            )?;
        }
        if args.dissimilarity {
            line(
                out,
                &format!("  δ at_place({name})"),
                &c.tape.render_dissimilarity(c.support[k], &c.percepts),
            )?;
        }
    }
    if args.place.is_none() {
        for (r, room) in engine.map().rooms().iter().enumerate() {
            line(
                out,
                &format!("in_room({})", room.name),
                &c.tape.render(c.rooms[r], &c.percepts),
            )?;
        }
        for (g, (region, _)) in engine.rules().regions.iter().enumerate() {
            if let Some(&reg) = c.regions.get(g) {
                line(
                    out,
                    &format!("in_region({region})"),
                    &c.tape.render(reg, &c.percepts),
                )?;
            }
        }
        for h in &c.set_heads {
            let neg = if h.negated { "!" } else { "" };
            let cap = if h.negated { "inside" } else { "outside" };
            writeln!(
                out,
                "// {neg}{} caps π of every place {cap} it at 1 − its degree",
                h.atom
            )?;
        }
    }
    Ok(EXIT_OK)
}

/// A derived predicate on its own: its degree function in each place context where it is not
/// the constant 0 (the `_i` parameters differ by context), as `max` over contexts otherwise.
fn explain_atom(
    engine: &Engine,
    name: &str,
    dissimilarity: bool,
    out: &mut impl Write,
) -> Result<u8, CliError> {
    let rules = engine.rules();
    if !rules.predicates.contains_key(name) {
        let known = rules
            .predicates
            .keys()
            .cloned()
            .collect::<Vec<_>>()
            .join(", ");
        return Err(ArgError::UnknownPredicate {
            name: name.to_string(),
            known,
        }
        .into());
    }
    let c = engine.compiled();
    let places = engine.map().places();
    for (atom, ctx, reg) in &c.derived_in_context {
        if c.tape.ops.get(*reg as usize) == Some(&Op::Const(0.0)) {
            continue;
        }
        let at = places.get(*ctx).map_or("?", |p| p.name.as_str());
        let atom = engine.atom_text(atom);
        line(
            out,
            &format!("{atom} @{at}"),
            &c.tape.render(*reg, &c.percepts),
        )?;
        if dissimilarity {
            line(
                out,
                &format!("  δ {atom} @{at}"),
                &c.tape.render_dissimilarity(*reg, &c.percepts),
            )?;
        }
    }
    Ok(EXIT_OK)
}

/// Π and N of a set of places, written out over the places' normalised possibilities π'.
fn explain_query(engine: &Engine, q: &str, out: &mut impl Write) -> Result<u8, CliError> {
    let set = engine.query_set(q).map_err(|error| ArgError::Query {
        query: q.to_string(),
        error,
    })?;
    let places = engine.map().places();
    let list = |inside: bool| {
        let terms: Vec<String> = (0..places.len())
            .filter(|&k| set.contains(k) == inside)
            .map(|k| format!("π'({})", places[k].name))
            .collect();
        if terms.is_empty() {
            "0".to_string()
        } else {
            format!("max({})", terms.join(", "))
        }
    };
    let members: Vec<&str> = set.indices().map(|k| places[k].name.as_str()).collect();
    writeln!(out, "{q} = {{{}}}", members.join(", "))?;
    writeln!(out, "Π({q}) = {}", list(true))?;
    writeln!(out, "N({q}) = 1 - {}", list(false))?;
    Ok(EXIT_OK)
}
