//! Line wrapping for `explain`'s formulas: a call `f(a, b, c)` that does not fit the width is
//! printed with one argument per line, indented under it, recursively; what fits stays on one
//! line. Only whitespace is added, so removing whitespace gives back the original text.

use std::fmt::Write;

/// Columns `explain` wraps its formulas to.
pub const WIDTH: usize = 100;

/// `prefix` followed by `expr`, wrapped to `width` columns (a single token longer than the width
/// stays whole).
pub fn wrap(prefix: &str, expr: &str, width: usize) -> String {
    let mut out = String::from(prefix);
    layout(expr, 0, prefix.chars().count(), width, "", &mut out);
    out
}

/// Writes `expr` then `suffix`, the cursor `lead` columns into a line whose continuation lines
/// start at `indent`.
fn layout(expr: &str, indent: usize, lead: usize, width: usize, suffix: &str, out: &mut String) {
    let fits = lead + expr.chars().count() + suffix.chars().count() <= width;
    let Some((head, args)) = (!fits).then(|| split_call(expr)).flatten() else {
        out.push_str(expr);
        out.push_str(suffix);
        return;
    };
    out.push_str(head);
    out.push('(');
    let inner = indent + 2;
    for (i, arg) in args.iter().enumerate() {
        let comma = if i + 1 == args.len() { "" } else { "," };
        // Writing into a String cannot fail.
        let _ = write!(out, "\n{:inner$}", "");
        layout(arg, inner, inner, width, comma, out);
    }
    let _ = write!(out, "\n{:indent$}){suffix}", "");
}

/// `name(a, b, …)` as the name and its top-level arguments (trimmed), when the whole of `expr` is
/// one call; `None` otherwise (a bare atom, an operator expression, unbalanced brackets).
fn split_call(expr: &str) -> Option<(&str, Vec<&str>)> {
    let open = expr.find('(')?;
    let head = &expr[..open];
    if head.is_empty() || head.contains(char::is_whitespace) || !expr.ends_with(')') {
        return None;
    }
    let body = &expr[open + 1..expr.len() - 1];
    let mut args = Vec::new();
    let (mut depth, mut start) = (0i64, 0);
    for (i, c) in body.char_indices() {
        match c {
            '(' | '[' | '⟨' => depth += 1,
            ')' | ']' | '⟩' => depth -= 1,
            ',' if depth == 0 => {
                args.push(body[start..i].trim());
                start = i + 1;
            }
            _ => {}
        }
        // The call's own parenthesis closed before the end: `f(a) + g(b)` is not one call.
        if depth < 0 {
            return None;
        }
    }
    if depth != 0 {
        return None;
    }
    args.push(body[start..].trim());
    Some((head, args))
}
