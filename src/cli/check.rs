//! `lplace check`: parse and check map and rule files, printing every problem of every file.

use super::args::CheckArgs;
use super::{read_source, render, CliError, EXIT_OK};
use crate::engine::{compile, CompileOptions, OFFICE_MAP};
use crate::map::Map;
use crate::rules::{check_map_against_rules, check_rules, RuleSet};
use crate::syntax::diagnostic::{Diagnostic, SourceFile};
use crate::syntax::{parse_map, parse_rules};
use std::io::Write;
use std::path::Path;

fn is_map(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "map")
}

/// Loads a map file into a model, printing its diagnostics; `None` if it has errors.
fn load_map(file: &SourceFile, problems: &mut usize) -> Option<Map> {
    let result = parse_map(&file.text).and_then(|ast| Map::from_ast(&ast));
    match result {
        Ok(map) => Some(map),
        Err(d) => {
            *problems += report(file, &d);
            None
        }
    }
}

/// Prints `diags` for `file`; returns how many are errors.
fn report(file: &SourceFile, diags: &[Diagnostic]) -> usize {
    render::eprint(file, diags);
    diags.iter().filter(|d| d.is_error()).count()
}

/// The map to check rules against when no .map is among the files: --map, else the bundled
/// office map (said on stderr). When the given maps had errors, checking the rules against
/// another would mislead: stop.
fn fallback_map(args: &CheckArgs, no_maps: bool, errors: usize) -> Result<SourceFile, CliError> {
    match &args.map {
        Some(p) => read_source(p),
        None if no_maps => {
            eprintln!(
                "note: no map given: checking the rules against the bundled office map \
                 (maps/office.map); name your map among the files or with --map"
            );
            Ok(SourceFile::new("maps/office.map (bundled)", OFFICE_MAP))
        }
        None => Err(CliError::Diagnostics { count: errors }),
    }
}

/// Compiles checked rules over a map, printing the warnings (rules that never fire on this map);
/// the file's "ok" line, or the number of errors printed.
fn compile_rules(file: &SourceFile, checked: &RuleSet, map: &Map) -> Result<String, usize> {
    let c = compile(checked, map, &CompileOptions::default()).map_err(|d| report(file, &d))?;
    report(file, &c.warnings);
    let warnings = match c.warnings.len() {
        0 => String::new(),
        n => format!("; {n} warning(s) about this map"),
    };
    Ok(format!(
        "{}: ok ({} rules, {} percept instances, {} instructions{warnings})",
        file.name,
        checked.rules.len(),
        c.percepts.len(),
        c.tape.len(),
    ))
}

/// Runs `check`; exit 0 when every file is clean.
pub fn run(args: &CheckArgs, out: &mut impl Write) -> Result<u8, CliError> {
    let mut errors = 0usize;
    let (maps, rules): (Vec<_>, Vec<_>) = args.files.iter().partition(|p| is_map(p));
    // Each map with the count of problems the rules found in it: its "ok" line waits for the
    // rules, so that a file is never called ok and then blamed.
    let mut models = Vec::new();
    for path in &maps {
        let file = read_source(path)?;
        if let Some(m) = load_map(&file, &mut errors) {
            models.push((m, file, 0usize));
        }
    }
    if !rules.is_empty() && models.is_empty() {
        let file = fallback_map(args, maps.is_empty(), errors)?;
        match load_map(&file, &mut errors) {
            Some(m) => models.push((m, file, 0)),
            None => return Err(CliError::Diagnostics { count: errors }),
        }
    }
    let mut rule_lines = Vec::new();
    for path in &rules {
        let file = read_source(path)?;
        let ast = match parse_rules(&file.text) {
            Ok(ast) => ast,
            Err(d) => {
                errors += report(&file, &d);
                continue;
            }
        };
        for (map, map_file, map_errors) in &mut models {
            let checked = match check_rules(&ast, map) {
                Ok(c) => c,
                Err(d) => {
                    errors += report(&file, &d);
                    continue;
                }
            };
            let cross = check_map_against_rules(map, &checked);
            if !cross.is_empty() {
                let n = report(map_file, &cross);
                *map_errors += n;
                errors += n;
            }
            match compile_rules(&file, &checked, map) {
                Ok(line) => rule_lines.push(line),
                Err(n) => errors += n,
            }
        }
    }
    for (m, file, map_errors) in &models {
        if *map_errors == 0 && maps.iter().any(|p| p.display().to_string() == file.name) {
            writeln!(
                out,
                "{}: ok ({} places, {} rooms, {} landmarks, {} paths)",
                file.name,
                m.places().len(),
                m.rooms().len(),
                m.landmarks().len(),
                m.graph().edge_count()
            )?;
        }
    }
    for line in rule_lines {
        writeln!(out, "{line}")?;
    }
    if errors > 0 {
        Err(CliError::Diagnostics { count: errors })
    } else {
        Ok(EXIT_OK)
    }
}
