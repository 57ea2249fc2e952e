//! The summary of an evaluated stream: how many frames, how many decided, why the others were
//! disoriented, what was rejected, and — when the stream carries ground truth — accuracy, the
//! per-place confusion matrix, the *confidently wrong* rate and kidnap recoveries.
//!
//! [`Tally`] is fed one frame at a time into counters sized at construction; the confusion
//! matrix ([`Confusion`]) keeps only the cells that were hit, so memory grows with the distinct
//! (truth, decision) pairs met — on a 10,000-place map a dense `(n + 1)²` table was 800 MB.
//! [`Tally::finish`] builds the serialisable [`Summary`].

use crate::io::stream::{FrameMeta, Rejection};
use crate::logic::{Decision, Disoriented};
use serde::ser::SerializeSeq;
use serde::{Serialize, Serializer};
use std::collections::BTreeMap;

/// Necessity at or above which a wrong decision counts as *confidently* wrong.
pub const CONFIDENT: f64 = 0.9;

/// A truth pose that moves more than this many metres beyond what odometry reports is a kidnap.
pub const KIDNAP_JUMP: f64 = 1.0;

/// At most this many kidnap events are listed one by one (all are counted).
const MAX_LISTED_KIDNAPS: usize = 64;

const REASONS: [&str; 4] = [
    "nothing_above_threshold",
    "too_close",
    "inconsistent",
    "no_places",
];

/// The reason name of a disoriented decision.
pub fn reason_name(d: &Disoriented) -> &'static str {
    match d {
        Disoriented::NothingAboveThreshold { .. } => REASONS[0],
        Disoriented::TooClose { .. } => REASONS[1],
        Disoriented::Inconsistent { .. } => REASONS[2],
        Disoriented::NoPlaces => REASONS[3],
    }
}

/// One kidnap (truth teleport) and how long the decisions took to be right again.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Kidnap {
    /// Line of the first frame after the jump.
    pub line: u64,
    /// Frames from that one (counted 1) to the first correct decision; `None` if never.
    pub recovered_after: Option<u64>,
    /// The same, counting only frames at a place: between places no decision can be right, so
    /// a robot dropped where it soon leaves a place is not slow to recover for that.
    pub recovered_after_at_place: Option<u64>,
}

/// Accuracy against ground truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthSummary {
    /// Frames whose truth is a place.
    pub at_place: u64,
    /// … decided for the true place.
    pub correct: u64,
    /// … decided for another place.
    pub wrong: u64,
    /// … disoriented.
    pub disoriented: u64,
    /// … wrong with necessity ≥ [`CONFIDENT`].
    pub confidently_wrong: u64,
    /// `correct / at_place`.
    pub accuracy: f64,
    /// `wrong / at_place`: the wrong-place rate.
    pub wrong_rate: f64,
    /// `confidently_wrong / at_place`.
    pub confidently_wrong_rate: f64,
    /// Frames whose truth is "between places".
    pub between_places: u64,
    /// … for which a place was nevertheless decided.
    pub between_decided: u64,
    /// Row labels: true places, then `none` (between places).
    pub confusion_rows: Vec<String>,
    /// Column labels: decided places, then `disoriented`.
    pub confusion_columns: Vec<String>,
    /// Frame counts by row and column; serialised as the dense `confusion[row][column]`.
    pub confusion: Confusion,
    /// Kidnaps detected from the truth poses.
    pub kidnaps: u64,
    /// The first kidnaps, each with its recovery time.
    pub kidnap_events: Vec<Kidnap>,
    /// Mean frames to recover over the kidnaps that recovered.
    pub mean_recovery_frames: Option<f64>,
    /// Worst recovery, frames.
    pub max_recovery_frames: Option<u64>,
}

/// A square table of frame counts that stores only its non-zero cells: rows are true places
/// then `none`, columns decided places then `disoriented` (both `side` long). It serialises as
/// the dense `side × side` array of arrays, written out row by row without building it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Confusion {
    side: usize,
    /// `(row, column) → count`, counts ≥ 1; ordered, so rows come out in order.
    cells: BTreeMap<(usize, usize), u64>,
}

impl Confusion {
    /// An all-zero `side × side` table.
    pub fn new(side: usize) -> Confusion {
        Confusion {
            side,
            cells: BTreeMap::new(),
        }
    }

    /// Rows (and columns).
    pub fn side(&self) -> usize {
        self.side
    }

    /// Counts one frame in a cell; a cell outside the table is ignored (as the dense table did).
    pub fn add(&mut self, row: usize, column: usize) {
        if row < self.side && column < self.side {
            *self.cells.entry((row, column)).or_insert(0) += 1;
        }
    }

    /// The count of one cell (0 outside the table).
    pub fn get(&self, row: usize, column: usize) -> u64 {
        self.cells.get(&(row, column)).copied().unwrap_or(0)
    }

    /// The non-zero cells of one row, in column order.
    pub fn row_cells(&self, row: usize) -> impl Iterator<Item = (usize, u64)> + '_ {
        self.cells
            .range((row, 0)..=(row, usize::MAX))
            .map(|(&(_, c), &n)| (c, n))
    }

    /// One row, dense: `side` counts in column order.
    pub fn row(&self, row: usize) -> impl Iterator<Item = u64> + '_ {
        let mut hits = self.row_cells(row).peekable();
        (0..self.side).map(move |c| match hits.peek() {
            Some(&(hc, n)) if hc == c => {
                hits.next();
                n
            }
            _ => 0,
        })
    }

    /// The sum of one row.
    pub fn row_total(&self, row: usize) -> u64 {
        self.row_cells(row).map(|(_, n)| n).sum()
    }
}

/// One dense row of a [`Confusion`], for serialising.
struct DenseRow<'a>(&'a Confusion, usize);

impl Serialize for DenseRow<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.0.row(self.1))
    }
}

impl Serialize for Confusion {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(self.side))?;
        for r in 0..self.side {
            seq.serialize_element(&DenseRow(self, r))?;
        }
        seq.end()
    }
}

/// Everything `lplace eval` reports about a stream.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Whether tracking over the map graph was on.
    pub tracking: bool,
    /// Frames evaluated (records accepted).
    pub frames: u64,
    /// Frames with a place chosen.
    pub decided: u64,
    /// Disoriented frames by reason.
    pub disoriented: BTreeMap<&'static str, u64>,
    /// Records rejected.
    pub rejected: u64,
    /// Rejected records by kind.
    pub rejected_by_kind: BTreeMap<&'static str, u64>,
    /// Accuracy, when some frame carried truth.
    pub truth: Option<TruthSummary>,
}

/// Running counters; see the module docs.
#[derive(Debug, Clone)]
pub struct Tally {
    places: Vec<String>,
    tracking: bool,
    frames: u64,
    decided: u64,
    disoriented: [u64; 4],
    rejected: u64,
    rejected_by_kind: BTreeMap<&'static str, u64>,
    with_truth: u64,
    correct: u64,
    wrong: u64,
    truth_disoriented: u64,
    confidently_wrong: u64,
    between: u64,
    between_decided: u64,
    /// `(n + 1) × (n + 1)`: rows true place or none, columns decided place or disoriented.
    confusion: Confusion,
    last_pose: Option<[f64; 3]>,
    kidnaps: u64,
    kidnap_events: Vec<Kidnap>,
    /// The current unrecovered kidnap, if any: its line, frames since, frames at a place since.
    pending_kidnap: Option<(u64, u64, u64)>,
    recovered_sum: u64,
    recovered_count: u64,
    recovered_max: Option<u64>,
}

impl Tally {
    /// Counters for a map with these places.
    pub fn new(places: Vec<String>, tracking: bool) -> Tally {
        let n = places.len();
        Tally {
            places,
            tracking,
            frames: 0,
            decided: 0,
            disoriented: [0; 4],
            rejected: 0,
            rejected_by_kind: BTreeMap::new(),
            with_truth: 0,
            correct: 0,
            wrong: 0,
            truth_disoriented: 0,
            confidently_wrong: 0,
            between: 0,
            between_decided: 0,
            confusion: Confusion::new(n + 1),
            last_pose: None,
            kidnaps: 0,
            kidnap_events: Vec::new(),
            pending_kidnap: None,
            recovered_sum: 0,
            recovered_count: 0,
            recovered_max: None,
        }
    }

    /// Counts a rejected record.
    pub fn reject(&mut self, why: &Rejection) {
        self.rejected += 1;
        *self.rejected_by_kind.entry(why.kind()).or_insert(0) += 1;
    }

    /// Counts one evaluated frame.
    pub fn record(&mut self, decision: Decision, meta: &FrameMeta) {
        self.frames += 1;
        let n = self.places.len();
        let chosen = match decision {
            Decision::Place { place, necessity } => {
                self.decided += 1;
                Some((place.min(n), necessity))
            }
            Decision::Disoriented(d) => {
                let r = REASONS
                    .iter()
                    .position(|x| *x == reason_name(&d))
                    .unwrap_or(0);
                self.disoriented[r] += 1;
                None
            }
        };
        self.detect_kidnap(meta);
        if !meta.truth_known {
            return;
        }
        let row = meta.truth_place.map_or(n, |p| p.min(n));
        let col = chosen.map_or(n, |(p, _)| p);
        self.confusion.add(row, col);
        match (meta.truth_place, chosen) {
            (Some(t), Some((p, nec))) => {
                self.with_truth += 1;
                if t == p {
                    self.correct += 1;
                } else {
                    self.wrong += 1;
                    if nec >= CONFIDENT {
                        self.confidently_wrong += 1;
                    }
                }
            }
            (Some(_), None) => {
                self.with_truth += 1;
                self.truth_disoriented += 1;
            }
            (None, c) => {
                self.between += 1;
                if c.is_some() {
                    self.between_decided += 1;
                }
            }
        }
        if let Some((line, frames, at_place)) = self.pending_kidnap {
            let frames = frames + 1;
            let at_place = at_place + u64::from(meta.truth_place.is_some());
            let right = matches!((meta.truth_place, chosen), (Some(t), Some((p, _))) if t == p);
            if right {
                self.recovered_sum += frames;
                self.recovered_count += 1;
                self.recovered_max = Some(self.recovered_max.map_or(frames, |m| m.max(frames)));
                if let Some(k) = self.kidnap_events.iter_mut().rev().find(|k| k.line == line) {
                    k.recovered_after = Some(frames);
                    k.recovered_after_at_place = Some(at_place);
                }
                self.pending_kidnap = None;
            } else {
                self.pending_kidnap = Some((line, frames, at_place));
            }
        }
    }

    fn detect_kidnap(&mut self, meta: &FrameMeta) {
        let Some(pose) = meta.truth_pose else {
            return;
        };
        if let Some(prev) = self.last_pose {
            let moved = (pose[0] - prev[0]).hypot(pose[1] - prev[1]);
            let odo = meta.odometry.dx.hypot(meta.odometry.dy);
            if moved > odo + KIDNAP_JUMP {
                self.kidnaps += 1;
                if self.kidnap_events.len() < MAX_LISTED_KIDNAPS {
                    self.kidnap_events.push(Kidnap {
                        line: meta.line,
                        recovered_after: None,
                        recovered_after_at_place: None,
                    });
                }
                self.pending_kidnap = Some((meta.line, 0, 0));
            }
        }
        self.last_pose = Some(pose);
    }

    /// The summary so far.
    pub fn finish(&self) -> Summary {
        let rate = |a: u64| {
            if self.with_truth == 0 {
                0.0
            } else {
                a as f64 / self.with_truth as f64
            }
        };
        let any_truth = self.with_truth + self.between > 0;
        let truth = any_truth.then(|| TruthSummary {
            at_place: self.with_truth,
            correct: self.correct,
            wrong: self.wrong,
            disoriented: self.truth_disoriented,
            confidently_wrong: self.confidently_wrong,
            accuracy: rate(self.correct),
            wrong_rate: rate(self.wrong),
            confidently_wrong_rate: rate(self.confidently_wrong),
            between_places: self.between,
            between_decided: self.between_decided,
            confusion_rows: self
                .places
                .iter()
                .cloned()
                .chain(std::iter::once("none".to_string()))
                .collect(),
            confusion_columns: self
                .places
                .iter()
                .cloned()
                .chain(std::iter::once("disoriented".to_string()))
                .collect(),
            confusion: self.confusion.clone(),
            kidnaps: self.kidnaps,
            kidnap_events: self.kidnap_events.clone(),
            mean_recovery_frames: (self.recovered_count > 0)
                .then(|| self.recovered_sum as f64 / self.recovered_count as f64),
            max_recovery_frames: self.recovered_max,
        });
        Summary {
            tracking: self.tracking,
            frames: self.frames,
            decided: self.decided,
            disoriented: REASONS
                .iter()
                .zip(self.disoriented)
                .map(|(r, c)| (*r, c))
                .collect(),
            rejected: self.rejected,
            rejected_by_kind: self.rejected_by_kind.clone(),
            truth,
        }
    }
}

impl Summary {
    /// Writes the summary for a person.
    pub fn write_text(&self, out: &mut impl std::io::Write) -> std::io::Result<()> {
        writeln!(
            out,
            "frames {}  decided {}  tracking {}",
            self.frames,
            self.decided,
            if self.tracking { "on" } else { "off" }
        )?;
        let dis: Vec<String> = self
            .disoriented
            .iter()
            .filter(|(_, c)| **c > 0)
            .map(|(r, c)| format!("{r} {c}"))
            .collect();
        writeln!(
            out,
            "disoriented {}{}",
            self.disoriented.values().sum::<u64>(),
            if dis.is_empty() {
                String::new()
            } else {
                format!(" ({})", dis.join(", "))
            }
        )?;
        if self.rejected > 0 {
            let kinds: Vec<String> = self
                .rejected_by_kind
                .iter()
                .map(|(k, c)| format!("{k} {c}"))
                .collect();
            writeln!(out, "rejected {} ({})", self.rejected, kinds.join(", "))?;
        }
        match &self.truth {
            Some(t) => t.write_text(out),
            None => Ok(()),
        }
    }
}

impl TruthSummary {
    /// Writes the scores against the truth for a person: accuracy, kidnap recoveries, and the
    /// confusion table.
    fn write_text(&self, out: &mut impl std::io::Write) -> std::io::Result<()> {
        let t = self;
        writeln!(
            out,
            "at a place {}: correct {} ({:.1}%)  wrong {} ({:.1}%)  disoriented {}  confidently wrong {} ({:.1}%)",
            t.at_place,
            t.correct,
            100.0 * t.accuracy,
            t.wrong,
            100.0 * t.wrong_rate,
            t.disoriented,
            t.confidently_wrong,
            100.0 * t.confidently_wrong_rate
        )?;
        // The figures a place recogniser is judged by, so that nobody works them out by hand.
        let decided = t.correct + t.wrong;
        let pct = |a: u64, b: u64| 100.0 * a as f64 / b.max(1) as f64;
        writeln!(
            out,
            "of {} at a place: decided {:.1}%  right of decided {:.1}%  confidently wrong {:.1}%",
            t.at_place,
            pct(decided, t.at_place),
            pct(t.correct, decided),
            pct(t.confidently_wrong, t.at_place)
        )?;
        writeln!(
            out,
            "between places {}: a place decided in {}",
            t.between_places, t.between_decided
        )?;
        if t.kidnaps > 0 {
            t.write_kidnaps(out)?;
        }
        write!(out, "confusion (rows truth, columns decided):\n{:>6}", "")?;
        for c in &t.confusion_columns {
            write!(out, " {:>5}", if c == "disoriented" { "dis" } else { c })?;
        }
        writeln!(out)?;
        for (i, r) in t.confusion_rows.iter().enumerate() {
            write!(out, "{r:>6}")?;
            for c in t.confusion.row(i) {
                write!(out, " {c:>5}")?;
            }
            writeln!(out)?;
        }
        Ok(())
    }

    /// The kidnap lines: mean and worst recovery, then each kidnap's.
    fn write_kidnaps(&self, out: &mut impl std::io::Write) -> std::io::Result<()> {
        let t = self;
        writeln!(
            out,
            "kidnaps {}: mean recovery {} frames, worst {}",
            t.kidnaps,
            t.mean_recovery_frames
                .map_or("-".to_string(), |m| format!("{m:.1}")),
            t.max_recovery_frames
                .map_or("never".to_string(), |m| m.to_string())
        )?;
        let each: Vec<String> = t
            .kidnap_events
            .iter()
            .map(|k| match (k.recovered_after, k.recovered_after_at_place) {
                (Some(f), Some(a)) => format!("line {}: {f} ({a} at a place)", k.line),
                _ => format!("line {}: never", k.line),
            })
            .collect();
        writeln!(out, "  frames to recover: {}", each.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logic::Disoriented;

    fn meta(line: u64, place: Option<usize>, x: f64) -> FrameMeta {
        FrameMeta {
            line,
            truth_known: true,
            truth_place: place,
            truth_pose: Some([x, 0.0, 0.0]),
            ..FrameMeta::default()
        }
    }

    #[test]
    fn kidnap_recovery_counts_all_frames_and_frames_at_a_place() {
        let mut t = Tally::new(vec!["A".into(), "B".into()], true);
        let lost = Decision::Disoriented(Disoriented::NothingAboveThreshold {
            best: 0,
            support: 0.0,
        });
        let at = |p| Decision::Place {
            place: p,
            necessity: 0.8,
        };
        // At A, then teleported 5 m with no odometry: line 2 is the kidnap. Lines 2–3 at B
        // (disoriented, then wrongly A), lines 4–5 between places, line 6 at B and right:
        // 5 frames, 3 of them at a place.
        t.record(at(0), &meta(1, Some(0), 0.0));
        t.record(lost, &meta(2, Some(1), 5.0));
        t.record(at(0), &meta(3, Some(1), 5.1));
        t.record(lost, &meta(4, None, 5.2));
        t.record(lost, &meta(5, None, 5.3));
        t.record(at(1), &meta(6, Some(1), 5.4));
        let s = t.finish();
        let truth = s.truth.expect("truth was given");
        assert_eq!(truth.kidnaps, 1);
        assert_eq!(
            truth.kidnap_events,
            vec![Kidnap {
                line: 2,
                recovered_after: Some(5),
                recovered_after_at_place: Some(3),
            }]
        );
        assert_eq!(truth.max_recovery_frames, Some(5));
    }

    /// A dense table, counted the obvious way, for the sparse one to be checked against.
    fn dense(n: usize, cells: &[(usize, usize)]) -> Vec<Vec<u64>> {
        let mut m = vec![vec![0u64; n + 1]; n + 1];
        for &(r, c) in cells {
            m[r][c] += 1;
        }
        m
    }

    #[test]
    fn sparse_confusion_prints_as_the_dense_table_on_random_runs() {
        let mut rng = crate::core::rng::SplitMix64::new(16);
        for trial in 0..40 {
            let n = 1 + rng.below(7);
            let places: Vec<String> = (0..n).map(|i| format!("Q{i}")).collect();
            let mut t = Tally::new(places.clone(), true);
            let mut hits = Vec::new();
            for line in 0..rng.below(60) as u64 {
                let truth = (!rng.chance(0.2)).then(|| rng.below(n));
                let decided = (!rng.chance(0.3)).then(|| rng.below(n));
                let d = match decided {
                    Some(p) => Decision::Place {
                        place: p,
                        necessity: 0.5,
                    },
                    None => Decision::Disoriented(Disoriented::NoPlaces),
                };
                t.record(d, &meta(line, truth, 0.0));
                hits.push((truth.unwrap_or(n), decided.unwrap_or(n)));
            }
            let want = dense(n, &hits);
            let Some(truth) = t.finish().truth else {
                assert!(hits.is_empty(), "trial {trial}");
                continue;
            };
            // JSON: the same array of arrays the dense table gave.
            assert_eq!(
                serde_json::to_value(&truth.confusion).expect("serialises"),
                serde_json::to_value(&want).expect("serialises"),
                "trial {trial}"
            );
            // Text: the table, written from the dense rows by hand.
            let mut text = Vec::new();
            truth.write_text(&mut text).expect("writes");
            let text = String::from_utf8(text).expect("UTF-8");
            let mut table = format!("confusion (rows truth, columns decided):\n{:>6}", "");
            for c in places.iter().map(String::as_str).chain(["dis"]) {
                table += &format!(" {c:>5}");
            }
            table += "\n";
            for (r, row) in places.iter().map(String::as_str).chain(["none"]).zip(&want) {
                table += &format!("{r:>6}");
                for c in row {
                    table += &format!(" {c:>5}");
                }
                table += "\n";
            }
            assert!(
                text.ends_with(&table),
                "trial {trial}:\n{text}\nwant\n{table}"
            );
            for (r, row) in want.iter().enumerate() {
                assert_eq!(truth.confusion.row_total(r), row.iter().sum::<u64>());
            }
        }
    }
}
