//! Spelling help for unknown names: the edit distance between two names, and from a list of
//! the names that are known, either the one close enough to be the intended spelling ("did you
//! mean `sonar_wall`?") or, when none is, the known names themselves (capped, so a map with
//! thousands of places does not flood the terminal).
//!
//! The distance itself is `core::spelling`'s (configuration keys use it too); the checker (`rules`) attaches the result to its diagnostics.

use std::fmt;

/// How many known names a [`Suggestion::KnownAre`] lists before saying "and N more".
pub const MAX_LISTED: usize = 8;

/// What to tell the author about a name that is not known.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Suggestion {
    /// A known name close to the one written.
    DidYouMean(String),
    /// Nothing is close: the first known names, in their declaration order, and how many more
    /// there are.
    KnownAre {
        /// At most [`MAX_LISTED`] names.
        names: Vec<String>,
        /// How many were left out.
        more: usize,
    },
}

impl fmt::Display for Suggestion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Suggestion::DidYouMean(name) => write!(f, "did you mean `{name}`?"),
            Suggestion::KnownAre { names, more } => {
                f.write_str("known: ")?;
                for (i, n) in names.iter().enumerate() {
                    if i > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "`{n}`")?;
                }
                if *more > 0 {
                    write!(f, " and {more} more")?;
                }
                Ok(())
            }
        }
    }
}

pub use crate::core::spelling::edit_distance;

/// The largest distance at which a known name still counts as a misspelling of `written`: about
/// a third of the longer name (rustc's rule of thumb), so `Nord` → `North` (2 edits in 5) and
/// `sonar_wal` → `sonar_wall` qualify while `Nord` → `West` does not; never the whole name.
fn limit(written: &str, known: &str) -> usize {
    let (w, k) = (written.chars().count(), known.chars().count());
    let third = w.max(k).div_ceil(3);
    third.min(w.min(k).saturating_sub(1)).max(1)
}

/// Help for the unknown name `written` among the `known` names (in declaration order): the
/// closest known name within about a third of the longer name's length (see `limit`) when there
/// is only one (a name differing only in letter case counts as closest), else the known names,
/// at most [`MAX_LISTED`]. `None` when nothing is known.
pub fn suggest<'a>(written: &str, known: impl IntoIterator<Item = &'a str>) -> Option<Suggestion> {
    // A name may come from two tables (declared and defined): list it once.
    let mut known: Vec<&str> = known.into_iter().filter(|k| *k != written).collect();
    let mut seen = std::collections::BTreeSet::new();
    known.retain(|k| seen.insert(*k));
    if known.is_empty() {
        return None;
    }
    let lower = written.to_lowercase();
    let close: Vec<(usize, &str)> = known
        .iter()
        .map(|k| {
            let d = if k.to_lowercase() == lower {
                0
            } else {
                edit_distance(written, k)
            };
            (d, *k)
        })
        .filter(|(d, k)| *d <= limit(written, k))
        .collect();
    let best = close.iter().map(|(d, _)| *d).min();
    let mut closest = close.iter().filter(|(d, _)| Some(*d) == best);
    // Only a single closest name is a suggestion: `P9` is as close to `P0` as to `P7`, and
    // picking one of them would be a guess.
    Some(match (closest.next(), closest.next()) {
        (Some((_, k)), None) => Suggestion::DidYouMean(k.to_string()),
        _ => Suggestion::KnownAre {
            names: known
                .iter()
                .take(MAX_LISTED)
                .map(|s| s.to_string())
                .collect(),
            more: known.len().saturating_sub(MAX_LISTED),
        },
    })
}
