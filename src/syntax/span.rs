//! Byte spans into a source text, and the line/column arithmetic that turns them into positions a
//! person can find in an editor. Everything the parsers produce carries a [`Span`], so that every
//! later stage (checker, compiler, `explain`) can point back at the text that caused it.

use serde::{Deserialize, Serialize};

/// A half-open byte range `start..end` into one source text.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
pub struct Span {
    /// First byte of the range.
    pub start: usize,
    /// One past the last byte of the range.
    pub end: usize,
}

impl Span {
    /// The span `start..end`.
    pub const fn new(start: usize, end: usize) -> Self {
        Span { start, end }
    }

    /// The smallest span covering both `self` and `other`.
    pub fn join(self, other: Span) -> Span {
        Span::new(self.start.min(other.start), self.end.max(other.end))
    }

    /// Number of bytes covered.
    pub fn len(&self) -> usize {
        self.end.saturating_sub(self.start)
    }

    /// True for an empty range (used for "missing here" diagnostics at end of input).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// 1-based line and column (in characters) of `self.start` within `text`.
    ///
    /// Offsets past the end of `text`, or inside a multi-byte character, are clamped rather than
    /// rejected: a position is for humans, and a slightly-off caret beats a panic.
    pub fn line_col(&self, text: &str) -> (usize, usize) {
        let mut at = self.start.min(text.len());
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        let before = &text[..at];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let col = before[line_start..].chars().count() + 1;
        (line, col)
    }
}

/// A value together with the span of the text it was read from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Spanned<T> {
    /// The value.
    pub node: T,
    /// Where it was written.
    pub span: Span,
}

impl<T> Spanned<T> {
    /// Pairs `node` with `span`.
    pub fn new(node: T, span: Span) -> Self {
        Spanned { node, span }
    }
}

/// An identifier as written, with its span.
pub type Ident = Spanned<String>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_col_counts_from_one_and_in_characters() {
        let text = "ab\nçd e\n";
        // 'e' is byte 7: line 2 starts at byte 3; "çd " is 3 characters (4 bytes).
        assert_eq!(Span::new(7, 8).line_col(text), (2, 4));
        assert_eq!(Span::new(0, 1).line_col(text), (1, 1));
        // Past the end: clamped to the end, which is line 3, column 1.
        assert_eq!(Span::new(100, 101).line_col(text), (3, 1));
        // Inside 'ç' (bytes 3..5): clamped back to its start.
        assert_eq!(Span::new(4, 5).line_col(text), (2, 1));
    }
}
