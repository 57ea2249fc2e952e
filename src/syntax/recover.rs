//! The error-recovering driver shared by both parsers: parse one top-level item at a time, and on
//! a syntax error report it, skip to just after the next top-level `;` or `}`, and go on — so a
//! file with three broken items gets three diagnostics. Also the nesting guard that rejects
//! hostile inputs (100 000 nested parentheses) before pest or the AST builders recurse on them.
//!
//! Depends on pest and `syntax::diagnostic`; the two grammars plug in their rule types.

use super::diagnostic::{Diagnostic, DiagnosticKind, Found, OneOf};
use super::span::Span;
use pest::error::Error as PestError;
use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::{Pair, Pairs};
use pest::{Parser, RuleType};
use std::sync::Mutex;

/// How deeply parentheses, braces, tuples, negations and nested `->` may nest. Real rule files
/// stay below 10; the limit keeps the recursive parser and every later recursive pass (checker,
/// compiler, `Drop`) far from the end of the stack even on a small thread stack.
pub const MAX_NESTING: usize = 32;

/// Returns a "too deeply nested" diagnostic if `text` nests deeper than [`MAX_NESTING`].
pub fn nesting_check(text: &str) -> Option<Diagnostic> {
    let bytes = text.as_bytes();
    // One entry per open bracket: the number of `->` seen at that level; entry 0 is the top.
    let mut arrows: Vec<usize> = vec![0];
    let mut bangs = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = skip_line_comment(bytes, i);
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i = skip_block_comment(bytes, i);
                continue;
            }
            b'"' => {
                i = skip_string(bytes, i);
                continue;
            }
            b'(' | b'{' | b'<' => arrows.push(0),
            // A chain of `->` ends with its rule or argument.
            b';' | b',' => {
                if let Some(top) = arrows.last_mut() {
                    *top = 0;
                }
            }
            b')' | b'}' if arrows.len() > 1 => {
                arrows.pop();
            }
            b'>' if i > 0 && bytes[i - 1] == b'-' => {
                if let Some(top) = arrows.last_mut() {
                    *top += 1;
                }
            }
            b'>' if arrows.len() > 1 => {
                arrows.pop();
            }
            _ => {}
        }
        if b == b'!' {
            bangs += 1;
        } else if !b.is_ascii_whitespace() {
            bangs = 0;
        }
        let depth = arrows.len() - 1 + bangs + arrows.last().copied().unwrap_or(0);
        if depth > MAX_NESTING {
            return Some(Diagnostic::error(
                DiagnosticKind::TooDeeplyNested { limit: MAX_NESTING },
                Span::new(i, i + 1),
            ));
        }
        i += 1;
    }
    None
}

fn skip_line_comment(bytes: &[u8], mut i: usize) -> usize {
    while i < bytes.len() && bytes[i] != b'\n' {
        i += 1;
    }
    i
}

fn skip_block_comment(bytes: &[u8], mut i: usize) -> usize {
    i += 2;
    while i < bytes.len() {
        if bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/') {
            return i + 2;
        }
        i += 1;
    }
    i
}

fn skip_string(bytes: &[u8], mut i: usize) -> usize {
    i += 1;
    while i < bytes.len() && bytes[i] != b'"' && bytes[i] != b'\n' {
        i += 1;
    }
    (i + 1).min(bytes.len())
}

/// How many syntax errors one file may report before the parser gives up on it: a binary or
/// corrupted file would otherwise cost a pest error (a copy of the rest of its line) per item.
pub const MAX_SYNTAX_ERRORS: usize = 100;

/// True when `bytes` holds nothing but what the grammars' `WHITESPACE` and `COMMENT` accept
/// (a block comment must be closed).
fn only_trivia(bytes: &[u8]) -> bool {
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b' ' | b'\t' | b'\r' | b'\n' => i += 1,
            b'/' if bytes.get(i + 1) == Some(&b'/') => i = skip_line_comment(bytes, i),
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                match bytes[i + 2..].windows(2).position(|w| w == b"*/") {
                    Some(k) => i += 2 + k + 2,
                    None => return false,
                }
            }
            _ => return false,
        }
    }
    true
}

/// Skips whitespace and comments from `i`.
fn skip_trivia(bytes: &[u8], mut i: usize) -> usize {
    loop {
        match bytes.get(i) {
            Some(b) if b.is_ascii_whitespace() => i += 1,
            Some(b'/') if bytes.get(i + 1) == Some(&b'/') => i = skip_line_comment(bytes, i),
            Some(b'/') if bytes.get(i + 1) == Some(&b'*') => i = skip_block_comment(bytes, i),
            _ => return i,
        }
    }
}

/// The position just after the item starting at or after `start`: after the first `;` outside
/// braces, or after the `}` that closes the outermost brace (and a `;` right after it).
/// Always greater than `start` unless `start` is the end of the text.
fn skip_item(text: &str, start: usize) -> usize {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = skip_trivia(bytes, start);
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = skip_line_comment(bytes, i);
                continue;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i = skip_block_comment(bytes, i);
                continue;
            }
            b'"' => {
                i = skip_string(bytes, i);
                continue;
            }
            b'{' => depth += 1,
            b'}' => {
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    let after = skip_trivia(bytes, i + 1);
                    return if bytes.get(after) == Some(&b';') {
                        after + 1
                    } else {
                        i + 1
                    };
                }
            }
            b';' if depth == 0 => return i + 1,
            _ => {}
        }
        i += 1;
    }
    // Keep to char boundaries: every byte that ends the loop above is ASCII or the end.
    bytes.len().max(start)
}

/// The label of a literal token of either grammar, for "expected …" messages.
fn token_label(token: &str) -> Option<&'static str> {
    Some(match token {
        ";" => "`;`",
        "," => "`,`",
        "(" => "`(`",
        ")" => "`)`",
        "{" => "`{`",
        "}" => "`}`",
        "<" => "`<`",
        ">" => "`>`",
        "=" => "`=`",
        ":" => "`:`",
        "~" => "`~`",
        "&" => "`&`",
        "*" => "`*`",
        "!" => "`!`",
        "(+)" => "`(+)`",
        "->" => "`->`",
        "|-" => "`|-`",
        "--" => "`--`",
        "\"" => "`\"`",
        _ => return None,
    })
}

/// Converts a pest error at offset `base` into a syntax diagnostic. pest records the rules it
/// tried at the furthest position in the error itself, and (with error detail on) the literal
/// tokens it tried there in its parse attempts; the further of the two wins, so that a missing
/// `;` is reported where the `;` should be, not at the start of the item.
pub fn syntax_error<R: RuleType>(
    text: &str,
    base: usize,
    err: &pest::error::Error<R>,
    label: fn(R) -> &'static str,
) -> Diagnostic {
    let rule_pos = match err.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    let mut rule_labels: Vec<&'static str> = Vec::new();
    if let ErrorVariant::ParsingError { positives, .. } = &err.variant {
        for r in positives {
            rule_labels.push(label(*r));
        }
    }
    let attempts = err.parse_attempts();
    let token_pos = attempts.as_ref().map_or(0, |a| a.max_position);
    let mut token_labels: Vec<&'static str> = Vec::new();
    for t in attempts.map(|a| a.expected_tokens()).unwrap_or_default() {
        // The token type is not exported by pest; its Display is the literal.
        if let Some(l) = token_label(&t.to_string()) {
            token_labels.push(l);
        }
    }
    let (pos, labels) = if token_pos > rule_pos && !token_labels.is_empty() {
        (token_pos, token_labels)
    } else if token_pos == rule_pos {
        (rule_pos, [rule_labels, token_labels].concat())
    } else {
        (rule_pos, rule_labels)
    };
    let mut expected: Vec<&'static str> = Vec::new();
    for l in labels {
        if !expected.contains(&l) {
            expected.push(l);
        }
    }
    let pos = (base + pos).min(text.len());
    let found = text.get(pos..).and_then(|s| s.chars().next());
    let end = pos + found.map_or(0, char::len_utf8);
    // What is missing belongs at the end of the previous line, like a forgotten `;`: point just
    // after the last token there rather than at the start of the next item.
    let before = text[..pos].trim_end();
    let span = if text[before.len()..pos].contains('\n')
        && !before.is_empty()
        && !before.ends_with("*/")
    {
        let last_line = before.rsplit('\n').next().unwrap_or("");
        if last_line.contains("//") {
            Span::new(pos, end)
        } else {
            Span::new(before.len(), before.len())
        }
    } else {
        Span::new(pos, end)
    };
    Diagnostic::error(
        DiagnosticKind::Syntax {
            expected: OneOf(expected),
            found: Found(found),
        },
        span,
    )
}

/// `P::parse(rule, text)`, and on failure the error with the literal tokens tried at the
/// furthest position too (what [`syntax_error`] lists as expected).
///
/// pest records those tries only while its process-wide error-detail switch is on, and doing
/// so halves the speed of every parse. So a text is parsed without them, and only a failed
/// one again with them, under a lock: the switch is on only inside it, so a detailed parse
/// never races another's switching off; a plain parse on another thread that meets the switch
/// on is merely slower (its result is the same).
pub(crate) fn parse_detailed<'i, P, R>(
    rule: R,
    text: &'i str,
) -> Result<Pairs<'i, R>, Box<PestError<R>>>
where
    P: Parser<R>,
    R: RuleType,
{
    static DETAIL: Mutex<()> = Mutex::new(());
    if let Ok(pairs) = P::parse(rule, text) {
        return Ok(pairs);
    }
    // A poisoned lock only means another detailed parse panicked; the switch is reset below.
    let _held = DETAIL.lock().unwrap_or_else(|e| e.into_inner());
    pest::set_error_detail(true);
    let result = P::parse(rule, text);
    pest::set_error_detail(false);
    result.map_err(Box::new)
}

/// Parses `text` item by item with grammar `P`: `entry` must match one item at the start of its
/// input (`SOI ~ item`); the file ends where only whitespace and comments are left. Each parsed
/// item is handed to `build` with the byte offset of the slice it was parsed from. Returns the
/// syntax diagnostics (empty when the whole file parsed); after [`MAX_SYNTAX_ERRORS`] the parse
/// stops with one more diagnostic saying so.
///
/// Time is linear in the text for files that parse: a failed pest parse copies the rest of its
/// line into the error, so neither the end-of-file test nor anything else per item may fail a
/// pest parse, and failures (which do) are capped.
pub fn parse_items<P, R>(
    text: &str,
    entry: R,
    label: fn(R) -> &'static str,
    mut build: impl FnMut(Pair<'_, R>, usize),
) -> Vec<Diagnostic>
where
    P: Parser<R>,
    R: RuleType,
{
    let mut diags = Vec::new();
    if let Some(d) = nesting_check(text) {
        diags.push(d);
        return diags;
    }
    let mut pos = 0;
    while pos < text.len() {
        let rest = &text[pos..];
        if only_trivia(rest.as_bytes()) {
            break;
        }
        if diags.len() == MAX_SYNTAX_ERRORS {
            diags.push(Diagnostic::error(
                DiagnosticKind::TooManySyntaxErrors {
                    count: MAX_SYNTAX_ERRORS,
                },
                Span::new(pos, skip_item(text, pos)),
            ));
            break;
        }
        match parse_detailed::<P, R>(entry, rest) {
            Ok(mut pairs) => {
                // `entry` is `SOI ~ item`: its only child is the item.
                let Some(item) = pairs.next().and_then(|e| e.into_inner().next()) else {
                    break;
                };
                let end = item.as_span().end();
                build(item, pos);
                if end == 0 {
                    break;
                }
                pos += end;
            }
            Err(e) => {
                diags.push(syntax_error(text, pos, &e, label));
                let next = skip_item(text, pos);
                if next <= pos {
                    break;
                }
                pos = next;
            }
        }
    }
    diags
}

/// The span of `p` in the whole file (`base` is where its item starts), without the trailing
/// whitespace that pest's implicit whitespace handling leaves inside rules ending in a repetition.
pub(crate) fn pair_span<R: RuleType>(base: usize, p: &Pair<'_, R>) -> Span {
    let s = p.as_span();
    let len = p.as_str().trim_end().len();
    Span::new(base + s.start(), base + s.start() + len)
}

/// A number token as a finite `f64`; anything else (overflow to infinity) is reported and read
/// as 0 so that building the AST can go on and find the file's other problems.
pub(crate) fn pair_number<R: RuleType>(
    base: usize,
    p: &Pair<'_, R>,
    diags: &mut Vec<Diagnostic>,
) -> crate::syntax::span::Spanned<f64> {
    use crate::syntax::span::Spanned;
    let span = pair_span(base, p);
    match p.as_str().parse::<f64>() {
        Ok(x) if x.is_finite() => Spanned::new(x, span),
        _ => {
            diags.push(Diagnostic::error(
                DiagnosticKind::NumberOutOfRange {
                    text: p.as_str().to_string(),
                },
                span,
            ));
            Spanned::new(0.0, span)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skip_item_stops_after_semicolon_or_closing_brace() {
        assert_eq!(skip_item("a b; c;", 0), 4);
        assert_eq!(skip_item("x { a; b; } y", 0), 11);
        assert_eq!(skip_item("x in {A; B}; y", 0), 12);
        assert_eq!(skip_item("// ; \n a;", 0), 9);
        assert_eq!(skip_item("no end", 0), 6);
    }

    #[test]
    fn nesting_guard_counts_brackets_bangs_and_arrows() {
        assert!(nesting_check(&"(".repeat(MAX_NESTING + 1)).is_some());
        assert!(nesting_check(&"(".repeat(MAX_NESTING)).is_none());
        assert!(nesting_check(&"!".repeat(MAX_NESTING + 1)).is_some());
        assert!(nesting_check(&"a -> ".repeat(MAX_NESTING + 1)).is_some());
        assert!(nesting_check(&"a -> b;\n".repeat(1000)).is_none());
        assert!(nesting_check(
            "// ((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((((\n"
        )
        .is_none());
    }
}
