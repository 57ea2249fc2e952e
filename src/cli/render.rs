//! Printing diagnostics for a person: miette's graphical report (path:line:column, the source
//! line, a caret under the span, a help line) for every problem of a file at once. Colour only
//! when stderr is a terminal, so logs and CI output stay plain.

use crate::syntax::diagnostic::{Diagnostic, Report, SourceFile};
use miette::{GraphicalReportHandler, GraphicalTheme};
use std::io::IsTerminal;

/// Renders `diags` of `file` as text (`colour` selects the theme).
pub fn render(file: &SourceFile, diags: &[Diagnostic], colour: bool) -> String {
    let theme = if colour {
        GraphicalTheme::unicode()
    } else {
        GraphicalTheme::unicode_nocolor()
    };
    let handler = GraphicalReportHandler::new_themed(theme).with_width(100);
    let mut out = String::new();
    if handler
        .render_report(&mut out, &Report::new(file, diags))
        .is_err()
    {
        // The graphical renderer refused (it cannot fail on our spans, but a report must
        // never be lost): fall back to one line per problem.
        out = diags.iter().map(|d| d.render_plain(file) + "\n").collect();
    }
    out
}

/// Prints every diagnostic of `file` to stderr.
pub fn eprint(file: &SourceFile, diags: &[Diagnostic]) {
    eprint!("{}", render(file, diags, std::io::stderr().is_terminal()));
}
