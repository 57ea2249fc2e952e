//! Judging a record's time against both of its neighbours, so that one corrupt timestamp costs
//! one record and not every record after it.
//!
//! A reader that compares each time only with the previous accepted one cannot tell a jump
//! forward that is wrong (`1, 2, 1e9, 3, 4`: the `1e9`) from a good time after it: it keeps the
//! `1e9` and then rejects every later record as "time goes backwards". Looking one record ahead
//! settles it: a time above its successor while the successor fits after the previous accepted
//! time is the outlier. Every reader of timed rows (percept streams, MRCLAM files) calls
//! [`judge`] once per row with the previous *accepted* time and the next row's time, so the
//! cost is linear and the verdicts are the same everywhere.
//!
//! Pure functions on numbers; no I/O.

/// How a time earlier than the previous accepted one is read.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TimePolicy {
    /// Time never decreases: an earlier time is a bad record.
    #[default]
    Monotone,
    /// Concatenated logs: a time earlier than the previous one starts a new clock when the
    /// record after it continues from it (each restart is accepted and reported as a note).
    Restart,
}

/// What [`judge`] decided about one record's time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeVerdict {
    /// In order.
    Keep,
    /// Earlier than the previous accepted time, and the clock restarts here
    /// ([`TimePolicy::Restart`] only).
    Restart {
        /// The previous accepted time.
        previous: f64,
    },
    /// Earlier than the previous accepted time: rejected.
    Backwards {
        /// The previous accepted time.
        previous: f64,
    },
    /// Later than the next record's time, which itself fits after the previous accepted time:
    /// this record is the one out of place, rejected.
    Outlier {
        /// The next record's time.
        next: f64,
    },
}

/// Judges time `t` given the previous accepted time and the next record's time (`None` when
/// unknown: first record, end of input, or a next record without a time). Times are finite.
pub fn judge(previous: Option<f64>, t: f64, next: Option<f64>, policy: TimePolicy) -> TimeVerdict {
    if let Some(p) = previous.filter(|&p| t < p) {
        // A restart needs the next record to go on from this one and to stay below the old
        // clock; otherwise this is a single low outlier (or the last record: no evidence).
        return match (policy, next) {
            (TimePolicy::Restart, Some(n)) if n >= t && n < p => {
                TimeVerdict::Restart { previous: p }
            }
            _ => TimeVerdict::Backwards { previous: p },
        };
    }
    // The first timed record has one neighbour only: between it and a lower second time there
    // is nothing to tell which is wrong, so the earlier is kept (and the second is "backwards").
    match (previous, next) {
        (Some(p), Some(n)) if n < t && n >= p => TimeVerdict::Outlier { next: n },
        _ => TimeVerdict::Keep,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use TimePolicy::*;

    /// Runs `judge` over a sequence the way a reader does; the indices kept.
    fn kept(ts: &[f64], policy: TimePolicy) -> Vec<usize> {
        let mut prev = None;
        let mut out = Vec::new();
        for (i, &t) in ts.iter().enumerate() {
            match judge(prev, t, ts.get(i + 1).copied(), policy) {
                TimeVerdict::Keep | TimeVerdict::Restart { .. } => {
                    prev = Some(t);
                    out.push(i);
                }
                _ => {}
            }
        }
        out
    }

    #[test]
    fn one_jump_forward_is_the_one_rejected() {
        assert_eq!(kept(&[1.0, 1e9, 3.0, 4.0], Monotone), [0, 2, 3]);
        // The first time has one neighbour: nothing tells which of the two is wrong.
        assert_eq!(kept(&[1e9, 1.0, 2.0], Monotone), [0]);
        assert_eq!(kept(&[1.0, 2.0, 1e9], Monotone), [0, 1, 2]);
    }

    #[test]
    fn one_jump_back_is_the_one_rejected() {
        assert_eq!(kept(&[1.0, 2.0, 0.5, 3.0], Monotone), [0, 1, 3]);
        assert_eq!(kept(&[1.0, 2.0, 0.5, 3.0], Restart), [0, 1, 3]);
    }

    #[test]
    fn a_restart_is_rejected_unless_asked_for() {
        let ts = [5.0, 6.0, 7.0, 0.0, 1.0, 2.0];
        assert_eq!(kept(&ts, Monotone), [0, 1, 2]);
        assert_eq!(kept(&ts, Restart), [0, 1, 2, 3, 4, 5]);
        assert_eq!(
            judge(Some(7.0), 0.0, Some(1.0), Restart),
            TimeVerdict::Restart { previous: 7.0 }
        );
    }

    #[test]
    fn equal_times_are_in_order() {
        assert_eq!(kept(&[1.0, 1.0, 1.0, 2.0], Monotone), [0, 1, 2, 3]);
    }
}
