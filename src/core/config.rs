//! Reading RON configuration files: one parser for every configuration of the crate, whose
//! errors say where (line, column) and, for a misspelt key, which key was meant.
//!
//! Every configuration struct denies unknown fields, so a typo is an error rather than a
//! silently ignored setting; this module turns RON's error for it into a message that names the
//! key, the nearest known key and the keys that exist.

use super::spelling::edit_distance;
use serde::de::DeserializeOwned;
use std::fmt;

/// A configuration text that is not valid for its type.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("line {line}, column {column}: {problem}")]
pub struct RonError {
    /// 1-based line of the problem.
    pub line: usize,
    /// 1-based column of the problem.
    pub column: usize,
    /// What is wrong there.
    pub problem: RonProblem,
}

/// What [`RonError`] found.
#[derive(Debug, Clone, PartialEq)]
pub enum RonProblem {
    /// A key the configuration does not have.
    UnknownKey {
        /// The key written.
        key: String,
        /// The struct it was written in, when RON names it.
        within: Option<String>,
        /// The known key nearest to it, when one is close.
        nearest: Option<&'static str>,
        /// Every key the struct has.
        known: &'static [&'static str],
    },
    /// Any other syntax or type error, as RON reports it.
    Other(ron::Error),
}

impl fmt::Display for RonProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RonProblem::UnknownKey {
                key,
                within,
                nearest,
                known,
            } => {
                write!(f, "unknown key `{key}`")?;
                if let Some(w) = within {
                    write!(f, " in `{w}`")?;
                }
                if let Some(n) = nearest {
                    write!(f, "; did you mean `{n}`?")?;
                }
                write!(f, " (known keys: {})", known.join(", "))
            }
            RonProblem::Other(e) => write!(f, "{e}"),
        }
    }
}

/// Parses `text` as a `T`.
///
/// # Errors
/// [`RonError`] with the line and column of the first problem.
pub fn from_ron<T: DeserializeOwned>(text: &str) -> Result<T, RonError> {
    ron::from_str(text).map_err(|e| {
        let problem = match e.code {
            ron::Error::NoSuchStructField {
                expected,
                found,
                outer,
            } => RonProblem::UnknownKey {
                nearest: nearest(&found, expected),
                key: found,
                within: outer,
                known: expected,
            },
            other => RonProblem::Other(other),
        };
        RonError {
            line: e.position.line,
            column: e.position.col,
            problem,
        }
    })
}

/// The candidate closest to `word` by edit distance, if it is within a third of the word's
/// length (at least 2 edits): far-off suggestions mislead more than they help.
fn nearest(word: &str, candidates: &'static [&'static str]) -> Option<&'static str> {
    let limit = (word.chars().count() / 3).max(2);
    candidates
        .iter()
        .map(|c| (edit_distance(word, c), *c))
        .filter(|(d, _)| *d <= limit)
        .min()
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize, PartialEq)]
    #[serde(default, deny_unknown_fields)]
    struct Demo {
        history_m: f64,
        stride: u32,
    }

    impl Default for Demo {
        fn default() -> Self {
            Demo {
                history_m: 8.0,
                stride: 1,
            }
        }
    }

    #[test]
    fn a_misspelt_key_is_named_with_its_nearest_and_its_place() {
        let e = from_ron::<Demo>("(\n  stride: 2,\n  histroy_m: 3.0,\n)").unwrap_err();
        assert_eq!(e.line, 3, "{e}");
        let text = e.to_string();
        assert!(text.contains("unknown key `histroy_m`"), "{text}");
        assert!(text.contains("did you mean `history_m`?"), "{text}");
        assert!(text.contains("known keys: history_m, stride"), "{text}");
    }

    #[test]
    fn a_key_far_from_every_known_one_gets_no_suggestion() {
        let e = from_ron::<Demo>("(totally_bogus_field: 1)").unwrap_err();
        let text = e.to_string();
        assert!(text.contains("unknown key `totally_bogus_field`"), "{text}");
        assert!(!text.contains("did you mean"), "{text}");
    }

    #[test]
    fn omitted_keys_take_defaults() {
        assert_eq!(
            from_ron::<Demo>("(stride: 3)").unwrap(),
            Demo {
                history_m: 8.0,
                stride: 3
            }
        );
    }
}
