//! The module layers of ARCHITECTURE.md, enforced: every `crate::…` path in a module's sources
//! names a module listed above it in the table and in its "may depend on" column. A back-import
//! (a lower layer reaching up) or an undeclared dependency fails this test.

#[path = "support/source_tree.rs"]
mod source_tree;
use source_tree::rust_files;
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The layer table: module name → (position, declared dependencies), in table order.
fn layer_table() -> Vec<(String, BTreeSet<String>)> {
    let text =
        fs::read_to_string(Path::new(ROOT).join("ARCHITECTURE.md")).expect("ARCHITECTURE.md");
    let start = text
        .find("## Layers")
        .expect("ARCHITECTURE.md has a '## Layers' section");
    let mut rows = Vec::new();
    for line in text[start..].lines().skip(1) {
        if line.starts_with("## ") {
            break;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        // | `module` | responsibility | may depend on |
        if cells.len() < 5 || !cells[1].starts_with('`') {
            continue;
        }
        let name = cells[1].trim_matches('`').to_string();
        let deps = backticked(cells[3]);
        rows.push((name, deps));
    }
    assert!(
        rows.len() >= 5,
        "the layer table has too few rows: {rows:?}"
    );
    rows
}

/// The names in backticks of a table cell, cut at the first `::`.
fn backticked(cell: &str) -> BTreeSet<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(|s| s.split("::").next().unwrap_or(s).to_string())
        .collect()
}

/// The top-level crate modules named by `crate::…` paths in `src`, grouped `use crate::{a, b}`
/// included.
fn crate_paths(src: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = src;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        let before_ok = i == 0
            || !rest.as_bytes()[i - 1].is_ascii_alphanumeric() && rest.as_bytes()[i - 1] != b'_';
        if before_ok {
            if let Some(group) = after.strip_prefix('{') {
                let end = matching_brace(group);
                for item in split_top(&group[..end]) {
                    let id = ident(item.trim());
                    if !id.is_empty() && id != "self" {
                        out.insert(id.to_string());
                    }
                }
            } else {
                let id = ident(after);
                if !id.is_empty() {
                    out.insert(id.to_string());
                }
            }
        }
        rest = after;
    }
    out
}

fn ident(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

fn matching_brace(s: &str) -> usize {
    let mut depth = 0usize;
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 0 => return i,
            '}' => depth -= 1,
            _ => {}
        }
    }
    s.len()
}

fn split_top(s: &str) -> Vec<&str> {
    let (mut out, mut depth, mut from) = (Vec::new(), 0usize, 0usize);
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                out.push(&s[from..i]);
                from = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[from..]);
    out
}

/// Module → the crate modules its sources name.
fn actual_dependencies(modules: &[String]) -> BTreeMap<String, BTreeMap<String, PathBuf>> {
    let src = Path::new(ROOT).join("src");
    let mut deps = BTreeMap::new();
    for m in modules {
        let mut files = Vec::new();
        rust_files(&src.join(m), &mut files);
        let single = src.join(format!("{m}.rs"));
        if single.exists() {
            files.push(single);
        }
        assert!(
            !files.is_empty(),
            "module `{m}` of the layer table has no sources"
        );
        let mut used = BTreeMap::new();
        for f in files {
            let text = fs::read_to_string(&f).expect("source readable");
            for d in crate_paths(&text) {
                if &d != m {
                    used.entry(d).or_insert(f.clone());
                }
            }
        }
        deps.insert(m.clone(), used);
    }
    deps
}

type Table = Vec<(String, BTreeSet<String>)>;
type Used = BTreeMap<String, BTreeMap<String, PathBuf>>;

/// Every dependency that goes up, sideways, outside the table or undeclared.
fn violations(table: &Table, deps: &Used) -> Vec<String> {
    let names: Vec<&String> = table.iter().map(|(n, _)| n).collect();
    let mut problems = Vec::new();
    for (pos, (m, declared)) in table.iter().enumerate() {
        for (d, file) in deps.get(m).into_iter().flatten() {
            let at = file.strip_prefix(ROOT).unwrap_or(file).display();
            match names.iter().position(|n| *n == d) {
                None => problems.push(format!(
                    "{at}: `{m}` uses `crate::{d}`, not in the layer table"
                )),
                Some(p) if p >= pos => problems.push(format!(
                    "{at}: `{m}` uses `crate::{d}`, a layer above it (a back-import)"
                )),
                Some(_) if !declared.contains(d) => problems.push(format!(
                    "{at}: `{m}` uses `crate::{d}`, not in its 'may depend on' column"
                )),
                Some(_) => {}
            }
        }
        for d in declared {
            if !names.iter().take(pos).any(|n| *n == d) {
                problems.push(format!(
                    "ARCHITECTURE.md: `{m}` declares `{d}`, not a layer above it"
                ));
            }
        }
    }
    problems
}

#[test]
fn every_module_imports_only_layers_below_it_as_declared() {
    let table = layer_table();
    let names: Vec<String> = table.iter().map(|(n, _)| n.clone()).collect();
    let problems = violations(&table, &actual_dependencies(&names));
    assert!(
        problems.is_empty(),
        "layering violations:\n{}",
        problems.join("\n")
    );
}

#[test]
fn every_source_module_is_in_the_table() {
    let names: BTreeSet<String> = layer_table().into_iter().map(|(n, _)| n).collect();
    let lib = fs::read_to_string(Path::new(ROOT).join("src/lib.rs")).expect("lib.rs");
    for line in lib.lines() {
        if let Some(rest) = line
            .trim()
            .strip_prefix("pub mod ")
            .or_else(|| line.trim().strip_prefix("mod "))
        {
            let m = rest.trim_end_matches(';').trim();
            assert!(
                names.contains(m),
                "src/lib.rs declares `{m}`, missing from ARCHITECTURE.md's layer table"
            );
        }
    }
}

#[test]
fn the_scanner_sees_grouped_and_nested_imports() {
    let src = "use crate::{engine::Frame, io::{record, stream}};\nuse crate::map;\nfn f() { crate::logic::x(); }\nlet mycrate::grid = 1;";
    let got: Vec<String> = crate_paths(src).into_iter().collect();
    assert_eq!(got, ["engine", "io", "logic", "map"]);
}

#[test]
fn a_planted_back_import_and_an_undeclared_use_are_caught() {
    let set = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<BTreeSet<_>>();
    let table: Table = vec![
        ("core".into(), set(&[])),
        ("logic".into(), set(&["core"])),
        ("map".into(), set(&["logic"])),
        ("cli".into(), set(&["core", "logic", "map"])),
    ];
    let file = PathBuf::from("src/logic/ops.rs");
    let mut deps = Used::new();
    deps.insert("logic".into(), [("cli".to_string(), file.clone())].into());
    deps.insert("map".into(), [("core".to_string(), file.clone())].into());
    deps.insert("cli".into(), [("map".to_string(), file)].into());
    let problems = violations(&table, &deps);
    assert_eq!(problems.len(), 2, "{problems:?}");
    assert!(problems[0].contains("`logic` uses `crate::cli`, a layer above it"));
    assert!(problems[1].contains("`map` uses `crate::core`, not in its 'may depend on'"));
}
