//! Printing diagnostics for a person: miette's graphical report (path:line:column, the source
//! line, a caret under the span, a help line) for every problem of a file at once. Colour only
//! when stderr is a terminal, so logs and CI output stay plain.
//!
//! Hostile files are bounded here: at most [`SHOWN_PER_KIND`] problems of one kind are printed
//! (then one "and K more" line), and a problem on a line longer than
//! [`EXCERPT_CHARS`](crate::syntax::diagnostic::EXCERPT_CHARS) is printed in the plain form with
//! an excerpt of the line around the span, never the whole line.

use crate::syntax::diagnostic::{Diagnostic, Report, SourceFile, EXCERPT_CHARS};
use miette::{GraphicalReportHandler, GraphicalTheme};
use std::fmt::Write;
use std::io::IsTerminal;
use std::mem::{discriminant, Discriminant};

/// How many diagnostics of one kind are printed before the rest are only counted.
pub const SHOWN_PER_KIND: usize = 10;

/// Renders `diags` of `file` as text (`colour` selects the theme).
pub fn render(file: &SourceFile, diags: &[Diagnostic], colour: bool) -> String {
    let (shown, hidden) = cap(diags);
    let (short, long): (Vec<Diagnostic>, Vec<Diagnostic>) = shown
        .into_iter()
        .cloned()
        .partition(|d| fits(&file.text, d));
    let mut out = String::new();
    if !short.is_empty() {
        out = graphical(file, &short, colour);
    }
    for d in &long {
        out.push_str(&d.render_plain(file));
    }
    for (d, more) in hidden {
        // Writing into a String cannot fail.
        let _ = writeln!(
            out,
            "{}: … and {more} more {} of this kind: {}",
            file.name, d.severity, d.kind
        );
    }
    out
}

/// miette's report for diagnostics whose lines all fit.
fn graphical(file: &SourceFile, diags: &[Diagnostic], colour: bool) -> String {
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
        // The graphical renderer refused: fall back to one plain block per problem, since a
        // report must never be lost.
        out = diags.iter().map(|d| d.render_plain(file) + "\n").collect();
    }
    out
}

/// The first [`SHOWN_PER_KIND`] diagnostics of each kind, in order, and per hidden kind its first
/// hidden diagnostic with how many of that kind were hidden (in order of first appearance).
fn cap(diags: &[Diagnostic]) -> (Vec<&Diagnostic>, Vec<(&Diagnostic, usize)>) {
    let mut seen: Vec<(Discriminant<_>, usize)> = Vec::new();
    let mut shown = Vec::new();
    let mut hidden: Vec<(&Diagnostic, usize)> = Vec::new();
    for d in diags {
        let key = discriminant(&d.kind);
        let slot = match seen.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                seen.push((key, 0));
                seen.len() - 1
            }
        };
        seen[slot].1 += 1;
        if seen[slot].1 <= SHOWN_PER_KIND {
            shown.push(d);
        } else if let Some(h) = hidden
            .iter_mut()
            .find(|(first, _)| discriminant(&first.kind) == key)
        {
            h.1 += 1;
        } else {
            hidden.push((d, 1));
        }
    }
    (shown, hidden)
}

/// True when the lines miette would print for `d` (its spans' lines and one line of context on
/// each side) are all short enough to print whole.
fn fits(text: &str, d: &Diagnostic) -> bool {
    let spans = std::iter::once(d.span).chain(d.related.map(|(s, _)| s));
    spans.into_iter().all(|s| {
        let start = s.start.min(text.len());
        let end = s.end.clamp(start, text.len());
        // From the start of the line before to the end of the line after.
        let from = line_start(text, line_start(text, start).saturating_sub(1));
        let to = line_end(text, line_end(text, end) + 1);
        text.as_bytes()[from..to]
            .split(|&b| b == b'\n')
            .all(|line| line.len() <= EXCERPT_CHARS)
    })
}

fn line_start(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())]
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1)
}

fn line_end(text: &str, at: usize) -> usize {
    let at = at.min(text.len());
    text.as_bytes()[at..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(text.len(), |i| at + i)
}

/// Prints every diagnostic of `file` to stderr.
pub fn eprint(file: &SourceFile, diags: &[Diagnostic]) {
    eprint!("{}", render(file, diags, std::io::stderr().is_terminal()));
}
