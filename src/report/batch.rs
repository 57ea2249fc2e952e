//! The table of a batch run (`lplace eval A.jsonl B.jsonl …` or a folder): one row per stream
//! from its [`Summary`], and a total whose rates are recomputed from the summed counts (not
//! averaged over streams, so a long stream weighs as many frames as it has).

use crate::report::Summary;
use serde::Serialize;
use std::io::Write;

/// One stream's row (or the total's).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BatchRow {
    /// The stream as named on the command line, or `total`.
    pub stream: String,
    /// Frames evaluated.
    pub frames: u64,
    /// Frames with a place decided.
    pub decided: u64,
    /// Records rejected.
    pub rejected: u64,
    /// Frames whose truth is a place (0 without truth).
    pub at_place: u64,
    /// … decided for the true place.
    pub correct: u64,
    /// … decided for another place.
    pub wrong: u64,
    /// … wrong with necessity ≥ [`crate::report::summary::CONFIDENT`].
    pub confidently_wrong: u64,
    /// `correct / at_place`; `None` without frames at a place.
    pub accuracy: Option<f64>,
    /// `wrong / at_place`.
    pub wrong_rate: Option<f64>,
}

impl BatchRow {
    /// The row of one stream.
    pub fn new(stream: impl Into<String>, s: &Summary) -> BatchRow {
        let t = s.truth.as_ref();
        let count = |f: fn(&crate::report::summary::TruthSummary) -> u64| t.map_or(0, f);
        let mut row = BatchRow {
            stream: stream.into(),
            frames: s.frames,
            decided: s.decided,
            rejected: s.rejected,
            at_place: count(|t| t.at_place),
            correct: count(|t| t.correct),
            wrong: count(|t| t.wrong),
            confidently_wrong: count(|t| t.confidently_wrong),
            accuracy: None,
            wrong_rate: None,
        };
        row.rates();
        row
    }

    /// The total of `rows`: counts summed, rates from the sums.
    pub fn total(rows: &[BatchRow]) -> BatchRow {
        let sum = |f: fn(&BatchRow) -> u64| rows.iter().map(f).sum();
        let mut row = BatchRow {
            stream: "total".into(),
            frames: sum(|r| r.frames),
            decided: sum(|r| r.decided),
            rejected: sum(|r| r.rejected),
            at_place: sum(|r| r.at_place),
            correct: sum(|r| r.correct),
            wrong: sum(|r| r.wrong),
            confidently_wrong: sum(|r| r.confidently_wrong),
            accuracy: None,
            wrong_rate: None,
        };
        row.rates();
        row
    }

    fn rates(&mut self) {
        let n = self.at_place;
        let rate = |k: u64| (n > 0).then(|| k as f64 / n as f64);
        self.accuracy = rate(self.correct);
        self.wrong_rate = rate(self.wrong);
    }
}

const COLUMNS: [&str; 10] = [
    "stream",
    "frames",
    "decided",
    "rejected",
    "at_place",
    "correct",
    "wrong",
    "confidently_wrong",
    "accuracy",
    "wrong_rate",
];

fn rate(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.4}"))
}

fn counts(r: &BatchRow) -> [u64; 7] {
    [
        r.frames,
        r.decided,
        r.rejected,
        r.at_place,
        r.correct,
        r.wrong,
        r.confidently_wrong,
    ]
}

/// An aligned table: the stream column as wide as its longest name, the total last.
pub fn write_table(
    rows: &[BatchRow],
    total: &BatchRow,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    let w = rows
        .iter()
        .chain([total])
        .map(|r| r.stream.chars().count())
        .max()
        .unwrap_or(0)
        .max(COLUMNS[0].len());
    write!(out, "{:<w$}", COLUMNS[0])?;
    for c in &COLUMNS[1..] {
        write!(out, " {c:>8}")?;
    }
    writeln!(out)?;
    for r in rows.iter().chain([total]) {
        write!(out, "{:<w$}", r.stream)?;
        for (c, v) in COLUMNS[1..8].iter().zip(counts(r)) {
            write!(out, " {v:>width$}", width = c.len().max(8))?;
        }
        writeln!(out, " {:>8} {:>10}", rate(r.accuracy), rate(r.wrong_rate))?;
    }
    Ok(())
}

/// CSV with a header; the stream name quoted when it holds a comma or a quote.
pub fn write_csv(rows: &[BatchRow], total: &BatchRow, out: &mut dyn Write) -> std::io::Result<()> {
    writeln!(out, "{}", COLUMNS.join(","))?;
    for r in rows.iter().chain([total]) {
        let name = if r.stream.contains([',', '"', '\n']) {
            format!("\"{}\"", r.stream.replace('"', "\"\""))
        } else {
            r.stream.clone()
        };
        write!(out, "{name}")?;
        for v in counts(r) {
            write!(out, ",{v}")?;
        }
        let opt = |x: Option<f64>| x.map_or_else(String::new, |v| v.to_string());
        writeln!(out, ",{},{}", opt(r.accuracy), opt(r.wrong_rate))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(name: &str, at_place: u64, correct: u64, wrong: u64) -> BatchRow {
        let mut r = BatchRow {
            stream: name.into(),
            frames: at_place + 1,
            decided: correct + wrong,
            rejected: 1,
            at_place,
            correct,
            wrong,
            confidently_wrong: 0,
            accuracy: None,
            wrong_rate: None,
        };
        r.rates();
        r
    }

    #[test]
    fn total_rates_weigh_frames_not_streams() {
        // 9 of 10 and 0 of 30: averaging the streams would give 0.45; the frames give 9/40.
        let rows = [row("a", 10, 9, 1), row("b", 30, 0, 0)];
        let t = BatchRow::total(&rows);
        assert_eq!(
            (t.frames, t.at_place, t.correct, t.rejected),
            (42, 40, 9, 2)
        );
        assert_eq!(t.accuracy, Some(9.0 / 40.0));
        assert_eq!(t.wrong_rate, Some(1.0 / 40.0));
        assert_eq!(row("none", 0, 0, 0).accuracy, None);
    }

    #[test]
    fn csv_quotes_names_and_leaves_missing_rates_empty() {
        let rows = [row("a,b", 0, 0, 0)];
        let mut out = Vec::new();
        write_csv(&rows, &BatchRow::total(&rows), &mut out).expect("writes to a Vec");
        let text = String::from_utf8(out).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[1], "\"a,b\",1,0,1,0,0,0,0,,");
        assert_eq!(lines[2], "total,1,0,1,0,0,0,0,,");
    }
}
