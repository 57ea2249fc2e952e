//! Printing diagnostics for a person: miette's graphical report (path:line:column, the source
//! line, a caret under the span, a help line) for every problem of a file at once.

use crate::syntax::diagnostic::{Diagnostic, SourceFile};

/// Prints every diagnostic of `file` to stderr.
pub fn eprint(file: &SourceFile, diags: &[Diagnostic]) {
    for d in diags {
        eprintln!("{}", d.render_plain(file));
    }
}
