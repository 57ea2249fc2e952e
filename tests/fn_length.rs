//! Functions a reader can hold: no `fn` in `src/` spans more than [`LIMIT`] lines, counted from
//! the line of `fn` to the line of its closing brace. `#[cfg(test)]` items are not counted (tests
//! may be long tables of cases), nor are the listed [`TABLES`] (one `match` from each case to
//! its value). The scanner blanks comments and string/char literals first, so a brace inside
//! `"{"` or `// }` does not move a body's end.

#[path = "support/source_tree.rs"]
mod source_tree;
use source_tree::rust_files;
use std::fs;
use std::path::Path;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The longest function body a reader is asked to hold, in lines.
const LIMIT: usize = 80;

/// Tables, `path::name`: functions whose whole body is one `match` mapping each case to a value
/// (say, each diagnostic to its help line). Such a table reads best whole, and one match keeps
/// the compiler checking that every case has its row. Each entry must still be a long table.
const TABLES: &[&str] = &["src/syntax/diagnostic.rs::help"];

/// One measured function: its name, the 1-based line of `fn`, its length in lines, and whether
/// its body is a table (one `match`, after any `use`).
#[derive(Debug, PartialEq)]
struct Measured {
    name: String,
    line: usize,
    lines: usize,
    table: bool,
}

/// `src` with every comment, string literal and char literal replaced by spaces, newlines kept,
/// so that byte offsets and line numbers survive and only code braces remain.
fn blank_non_code(src: &str) -> Vec<u8> {
    let b = src.as_bytes();
    let mut out = b.to_vec();
    let mut i = 0;
    while i < b.len() {
        let end = match b[i] {
            b'/' if b.get(i + 1) == Some(&b'/') => line_comment_end(b, i),
            b'/' if b.get(i + 1) == Some(&b'*') => block_comment_end(b, i),
            b'"' => quoted_end(b, i, b'"'),
            b'\'' => char_literal_end(b, i),
            b'r' | b'b' | b'c' if !ident_byte_before(b, i) => raw_or_byte_string_end(b, i),
            _ => None,
        };
        match end {
            Some(e) => {
                for c in &mut out[i..e] {
                    if *c != b'\n' {
                        *c = b' ';
                    }
                }
                i = e;
            }
            None => i += 1,
        }
    }
    out
}

fn ident_byte_before(b: &[u8], i: usize) -> bool {
    i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')
}

fn line_comment_end(b: &[u8], i: usize) -> Option<usize> {
    Some(
        b[i..]
            .iter()
            .position(|&c| c == b'\n')
            .map_or(b.len(), |p| i + p),
    )
}

/// Block comments nest in Rust.
fn block_comment_end(b: &[u8], i: usize) -> Option<usize> {
    let (mut depth, mut j) = (0usize, i);
    while j + 1 < b.len() {
        match (b[j], b[j + 1]) {
            (b'/', b'*') => {
                depth += 1;
                j += 2;
            }
            (b'*', b'/') => {
                depth -= 1;
                j += 2;
                if depth == 0 {
                    return Some(j);
                }
            }
            _ => j += 1,
        }
    }
    Some(b.len())
}

/// A `"…"` (or `'…'`) literal with backslash escapes, from its opening quote.
fn quoted_end(b: &[u8], i: usize, quote: u8) -> Option<usize> {
    let mut j = i + 1;
    while j < b.len() {
        match b[j] {
            b'\\' => j += 2,
            c if c == quote => return Some(j + 1),
            _ => j += 1,
        }
    }
    Some(b.len())
}

/// `'x'`, `'\n'`, `'\u{7b}'` or `'é'` are literals; `'a` in `&'a str` or `'outer:` is a
/// lifetime or label and is left alone.
fn char_literal_end(b: &[u8], i: usize) -> Option<usize> {
    if b.get(i + 1) == Some(&b'\\') {
        return quoted_end(b, i, b'\'');
    }
    let width = match b.get(i + 1)? {
        c if *c < 0x80 => 1,
        c if *c >= 0xF0 => 4,
        c if *c >= 0xE0 => 3,
        _ => 2,
    };
    (b.get(i + 1 + width) == Some(&b'\'')).then_some(i + 2 + width)
}

/// `r"…"`, `r#"…"#`, `b"…"`, `br#"…"#`, `c"…"`, `b'x'`; `None` for an identifier such as `r#type`
/// or `bar`.
fn raw_or_byte_string_end(b: &[u8], i: usize) -> Option<usize> {
    let mut j = i;
    if matches!(b[j], b'b' | b'c') {
        j += 1;
        match b.get(j) {
            Some(b'"') => return quoted_end(b, j, b'"'),
            Some(b'\'') if b[i] == b'b' => return quoted_end(b, j, b'\''),
            Some(b'r') => {}
            _ => return None,
        }
    }
    j += 1; // past `r`
    let hashes = b[j..].iter().take_while(|&&c| c == b'#').count();
    if b.get(j + hashes) != Some(&b'"') {
        return None;
    }
    let close: Vec<u8> = std::iter::once(b'"')
        .chain(std::iter::repeat(b'#').take(hashes))
        .collect();
    let body = j + hashes + 1;
    Some(
        b[body..]
            .windows(close.len())
            .position(|w| w == close.as_slice())
            .map_or(b.len(), |p| body + p + close.len()),
    )
}

/// The offset just past the `}` matching the `{` at `open`.
fn matching_close(code: &[u8], open: usize) -> usize {
    let mut depth = 0usize;
    for (j, &c) in code.iter().enumerate().skip(open) {
        match c {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return j + 1;
                }
            }
            _ => {}
        }
    }
    code.len()
}

/// The first `{` or `;` at or after `from`; a `fn` or `mod` ends its signature there.
fn signature_end(code: &[u8], from: usize) -> Option<(usize, u8)> {
    code[from..]
        .iter()
        .position(|&c| c == b'{' || c == b';')
        .map(|p| (from + p, code[from + p]))
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The word starting at `at` when it is a whole word (not part of a longer identifier).
fn word_at(code: &[u8], at: usize, word: &[u8]) -> bool {
    code[at..].starts_with(word)
        && (at == 0 || !is_ident(code[at - 1]))
        && code.get(at + word.len()).map_or(true, |&c| !is_ident(c))
}

/// Every `fn` item with a body in `src`, outside `#[cfg(test)]` items, with its length in lines.
fn measure(src: &str) -> Vec<Measured> {
    let code = blank_non_code(src);
    let line_of = |at: usize| 1 + code[..at].iter().filter(|&&c| c == b'\n').count();
    let mut out = Vec::new();
    let mut i = 0;
    while i < code.len() {
        if code[i..].starts_with(b"#[cfg(test)]") {
            // Skip the whole test item (usually `mod tests { … }`).
            i = match signature_end(&code, i) {
                Some((open, b'{')) => matching_close(&code, open),
                Some((semi, _)) => semi + 1,
                None => code.len(),
            };
            continue;
        }
        if word_at(&code, i, b"fn") {
            let name_at = i
                + 2
                + code[i + 2..]
                    .iter()
                    .take_while(|c| c.is_ascii_whitespace())
                    .count();
            let name_len = code[name_at..].iter().take_while(|&&c| is_ident(c)).count();
            // `fn(u8) -> u8` is a type, not an item.
            if name_len > 0 {
                if let Some((open, b'{')) = signature_end(&code, name_at) {
                    let close = matching_close(&code, open);
                    let (first, last) = (line_of(i), line_of(close - 1));
                    out.push(Measured {
                        name: String::from_utf8_lossy(&code[name_at..name_at + name_len]).into(),
                        line: first,
                        lines: last - first + 1,
                        table: is_table(&code[open + 1..close - 1]),
                    });
                }
            }
            i += 2;
            continue;
        }
        i += 1;
    }
    out
}

/// Whether a function body (between its braces) is `use …;` lines followed by one `match`.
fn is_table(body: &[u8]) -> bool {
    let mut at = 0;
    loop {
        at += body[at..]
            .iter()
            .take_while(|c| c.is_ascii_whitespace())
            .count();
        if !word_at(body, at, b"use") {
            break;
        }
        match body[at..].iter().position(|&c| c == b';') {
            Some(p) => at += p + 1,
            None => return false,
        }
    }
    if !word_at(body, at, b"match") {
        return false;
    }
    match signature_end(body, at) {
        Some((open, b'{')) => {
            let end = matching_close(body, open);
            body[end..].iter().all(|c| c.is_ascii_whitespace())
        }
        _ => false,
    }
}

/// A function of `src/` over the limit.
struct Long {
    /// `path::name`.
    key: String,
    /// `path:line: `name` is N lines`.
    report: String,
    table: bool,
}

/// Every function of `src/` over the limit.
fn long_functions() -> Vec<Long> {
    let mut files = Vec::new();
    rust_files(&Path::new(ROOT).join("src"), &mut files);
    files.sort();
    assert!(files.len() > 10, "too few sources under src/: {files:?}");
    let mut long = Vec::new();
    for f in files {
        let text = fs::read_to_string(&f).expect("source readable");
        let rel = f.strip_prefix(ROOT).unwrap_or(&f).display().to_string();
        let rel = rel.replace('\\', "/");
        for m in measure(&text) {
            if m.lines > LIMIT {
                long.push(Long {
                    key: format!("{rel}::{}", m.name),
                    report: format!("{rel}:{}: `{}` is {} lines", m.line, m.name, m.lines),
                    table: m.table,
                });
            }
        }
    }
    long
}

#[test]
fn no_function_in_src_is_longer_than_the_limit() {
    let long = long_functions();
    let over: Vec<&str> = long
        .iter()
        .filter(|l| !(l.table && TABLES.contains(&l.key.as_str())))
        .map(|l| l.report.as_str())
        .collect();
    assert!(
        over.is_empty(),
        "functions over {LIMIT} lines (split them into helpers a reader can hold):\n{}",
        over.join("\n")
    );
}

#[test]
fn every_table_entry_is_still_a_long_table() {
    let long = long_functions();
    for table in TABLES {
        assert!(
            long.iter().any(|l| l.key == *table && l.table),
            "`{table}` is no longer a table over {LIMIT} lines: remove it from TABLES"
        );
    }
}

/// A function of `lines` lines in all, `fn` line and closing brace included.
fn synthetic_fn(name: &str, lines: usize) -> String {
    let mut s = format!("fn {name}() {{\n");
    for k in 0..lines - 2 {
        s.push_str(&format!("    let _x{k} = {k};\n"));
    }
    s.push_str("}\n");
    s
}

/// A function of `lines` lines whose body is one `match` (a table), followed by `after`.
fn synthetic_table(name: &str, lines: usize, after: &str) -> String {
    let mut s = format!("fn {name}(k: K) -> &'static str {{\n    use K as X;\n    match k {{\n");
    for k in 0..lines - 6 {
        s.push_str(&format!("        X::V{k} => \"{{ row {k}\",\n"));
    }
    s.push_str(&format!("    }}\n{after}\n}}\n"));
    s
}

fn measured(name: &str, line: usize, lines: usize, table: bool) -> Measured {
    let name = name.into();
    Measured {
        name,
        line,
        lines,
        table,
    }
}

#[test]
fn the_scanner_measures_a_long_and_a_short_function() {
    let src = format!(
        "{}\n{}",
        synthetic_fn("long", 100),
        synthetic_fn("short", 10)
    );
    let want = [
        measured("long", 1, 100, false),
        measured("short", 102, 10, false),
    ];
    assert_eq!(measure(&src), want);
}

#[test]
fn braces_in_literals_and_comments_do_not_move_a_body_end() {
    let src = concat!(
        "fn a<'l>(x: &'l str) -> char {\n",       // 1
        "    let _ = \"}}}\\\" }\";\n",           // 2: an escaped quote inside a string
        "    let _ = r#\"}\" }\"#;\n",            // 3: a raw string with a quote inside
        "    let _ = b'}'; let _ = '{';\n",       // 4
        "    // } a comment\n",                   // 5
        "    /* } /* nested } */ } */\n",         // 6
        "    'outer: loop { break 'outer; }\n",   // 7: a label, not a char literal
        "    '}'\n",                              // 8
        "}\n",                                    // 9
        "fn b(f: fn(u8) -> u8) -> u8 { f(1) }\n", // 10: `fn(u8)` is a type
        "trait T { fn c(&self); }\n",             // 11: no body
    );
    let want = [measured("a", 1, 9, false), measured("b", 10, 1, false)];
    assert_eq!(measure(src), want);
}

#[test]
fn a_table_is_one_match_and_nothing_after_it() {
    let src = format!(
        "{}{}",
        synthetic_table("table", 90, ""),
        synthetic_table("not_table", 90, "    ;")
    );
    let want = [
        measured("table", 1, 90, true),
        measured("not_table", 91, 90, false),
    ];
    assert_eq!(measure(&src), want);
}

#[test]
fn test_modules_are_not_counted() {
    let src = format!(
        "fn kept() {{}}\n#[cfg(test)]\nmod tests {{\n{}}}\nfn after() {{}}\n",
        synthetic_fn("long_test", 120)
    );
    let names: Vec<String> = measure(&src).into_iter().map(|m| m.name).collect();
    assert_eq!(names, ["kept", "after"]);
}
