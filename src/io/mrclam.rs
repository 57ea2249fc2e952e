//! Reader for the UTIAS MRCLAM data set (dataset 7) and the merger that turns
//! one robot's files into a time-ordered stream of [`MetricFrame`]s.
//!
//! The reader does no I/O of its own: each `read_*` function takes any
//! [`BufRead`] the caller opened (a file, a `&[u8]` of text already in
//! memory, a decompressor). Lines starting with `#` and blank lines are
//! skipped; any other line must have the file's columns, else a
//! [`MrclamError::Malformed`] names the file kind, the 1-based line number
//! and what was wrong.
//!
//! Measurements carry *barcode* numbers, mapped to subject ids through
//! `Barcodes.dat`; a barcode in neither list (a misread) is dropped and
//! counted in [`Measurements::misread`].
//!
//! # Complexity
//!
//! Reading, lenient or not, is O(lines). [`merge`] is O((odometry + measurements) + frames ·
//! log truth).
//!
//! # Example
//!
//! ```
//! use lplace::io::mrclam::{read_barcodes, read_measurements, read_odometry, merge, MergeOptions};
//! let codes = read_barcodes("# header\n1 5\n6 63\n".as_bytes()).unwrap();
//! let odo = read_odometry("10.0 0.1 0.0\n10.5 0.1 0.0\n11.0 0.0 0.0\n".as_bytes()).unwrap();
//! let meas = read_measurements("10.5 63 2.0 0.1\n10.5 34 1.0 0.0\n".as_bytes(), &codes).unwrap();
//! assert_eq!(meas.misread, 1);
//! let frames = merge(&odo, &meas.rows, &[], &MergeOptions::default());
//! let f = frames.iter().find(|f| !f.observations.is_empty()).unwrap();
//! assert_eq!(f.observations[0].subject, 6);
//! assert!((f.t - 10.5).abs() < 1e-9);
//! ```

use crate::core::{Odometry, Pose2};
use crate::grid::LandmarkTruth;
use crate::io::time_order::{judge, TimePolicy, TimeVerdict};
use crate::localize::{interpolate_truth, LandmarkReading, MetricFrame, TruthRow};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::BufRead;

use super::line::{read_bounded, LineRead, MAX_LINE};

/// Which MRCLAM file a row came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FileKind {
    /// `Barcodes.dat`.
    Barcodes,
    /// `Landmark_Groundtruth.dat`.
    LandmarkGroundtruth,
    /// `RobotN_Odometry.dat`.
    Odometry,
    /// `RobotN_Measurement.dat`.
    Measurement,
    /// `RobotN_Groundtruth.dat`.
    Groundtruth,
}

/// Why a line was rejected.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum LineProblem {
    /// Wrong number of whitespace-separated fields.
    FieldCount {
        /// Fields the file kind has.
        expected: usize,
        /// Fields found.
        found: usize,
    },
    /// A field does not parse as a number of the right kind.
    NotANumber {
        /// 1-based column.
        column: usize,
        /// The field's text.
        text: String,
    },
    /// A field parses but is NaN or infinite.
    NonFinite {
        /// 1-based column.
        column: usize,
    },
    /// A range is negative.
    NegativeRange,
    /// The line is not UTF-8.
    NotUtf8 {
        /// 1-based byte column of the first bad byte.
        column: usize,
    },
    /// The line is longer than [`MAX_LINE`] bytes (dropped unread).
    TooLong,
    /// A time later than the next row's, which itself follows the previous row: this one
    /// time is out of place (a corrupt timestamp).
    TimeOutlier {
        /// This row's time.
        time: f64,
        /// The next row's time.
        next: f64,
    },
    /// A time is earlier than the previous row's.
    TimeGoesBack {
        /// Previous time.
        previous: f64,
        /// This row's time.
        time: f64,
    },
}

impl std::fmt::Display for LineProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LineProblem::FieldCount { expected, found } => {
                write!(f, "expected {expected} fields, found {found}")
            }
            LineProblem::NotANumber { column, text } => {
                write!(f, "column {column}: `{text}` is not a number")
            }
            LineProblem::NonFinite { column } => write!(f, "column {column}: not a finite number"),
            LineProblem::NegativeRange => write!(f, "negative range"),
            LineProblem::NotUtf8 { column } => write!(f, "column {column}: not UTF-8"),
            LineProblem::TooLong => write!(f, "longer than {MAX_LINE} bytes"),
            LineProblem::TimeOutlier { time, next } => write!(
                f,
                "time {time} is out of place (after it comes {next}, which follows the rows before)"
            ),
            LineProblem::TimeGoesBack { previous, time } => {
                write!(f, "time {time} is before the previous row's {previous}")
            }
        }
    }
}

/// Errors of the MRCLAM reader.
#[derive(Debug, thiserror::Error)]
pub enum MrclamError {
    /// A line that is neither a comment nor a valid row.
    #[error("{file:?} line {line}: {problem}")]
    Malformed {
        /// File kind.
        file: FileKind,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        problem: LineProblem,
    },
    /// The underlying reader failed (or the text is not UTF-8).
    #[error("{file:?} line {line}: read error: {source}")]
    Read {
        /// File kind.
        file: FileKind,
        /// 1-based number of the line being read.
        line: usize,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}

impl MrclamError {
    /// The 1-based line the error is about.
    pub fn line(&self) -> usize {
        match self {
            MrclamError::Malformed { line, .. } | MrclamError::Read { line, .. } => *line,
        }
    }
}

/// Barcode → subject id (`Barcodes.dat`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Barcodes {
    /// Barcode number → subject id.
    pub subject_of: BTreeMap<u32, u32>,
}

/// `time v ω` row of `RobotN_Odometry.dat`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OdometryRow {
    /// Time (s, Unix epoch).
    pub t: f64,
    /// Forward velocity (m/s).
    pub v: f64,
    /// Angular velocity (rad/s).
    pub w: f64,
}

/// A measurement with its barcode already mapped to a subject id.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeasurementRow {
    /// Time (s).
    pub t: f64,
    /// Subject id (1–5 robots, 6–20 landmarks).
    pub subject: u32,
    /// Range (m).
    pub range: f64,
    /// Bearing (rad, robot frame, CCW).
    pub bearing: f64,
}

/// The measurements of one robot and what was dropped.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Measurements {
    /// Rows with a known barcode, in file order.
    pub rows: Vec<MeasurementRow>,
    /// Number of rows dropped because their barcode is in no list.
    pub misread: usize,
    /// Those barcodes with their counts.
    pub misread_barcodes: BTreeMap<u32, usize>,
}

/// How [`merge`] cuts the stream into frames.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MergeOptions {
    /// Longest time without a frame: an odometry-only frame is emitted when
    /// no measurement arrives for this long (s). Default 0.5.
    pub max_frame_gap: f64,
    /// Truth is interpolated only between samples at most this far apart (s).
    /// Default 1.0.
    pub max_truth_gap: f64,
}

impl Default for MergeOptions {
    fn default() -> Self {
        MergeOptions {
            max_frame_gap: 0.5,
            max_truth_gap: 1.0,
        }
    }
}

/// What a lenient reader produced: the value built from the good lines and every bad line's
/// error, in line order.
#[derive(Debug)]
pub struct Lenient<T> {
    /// Built from the lines that were kept.
    pub value: T,
    /// One error per skipped line, in line order.
    pub skipped: Vec<MrclamError>,
}

impl<T> Lenient<T> {
    /// The value when no line was skipped, else the first skipped line's error.
    fn strict(self) -> Result<T, MrclamError> {
        match self.skipped.into_iter().next() {
            None => Ok(self.value),
            Some(e) => Err(e),
        }
    }
}

/// Parses every data line with `f`, in one pass: a line that does not parse is kept as an
/// error and the next line is read (so a bad line costs only itself). Returns the rows with
/// their 1-based line numbers and the errors. A UTF-8 byte-order mark before the first line is
/// ignored; a line that is not UTF-8 is a bad line.
fn parse_rows<R: BufRead, T>(
    mut r: R,
    file: FileKind,
    cols: usize,
    mut f: impl FnMut(&[f64], &[&str]) -> Result<T, LineProblem>,
) -> Result<Lenient<Vec<(usize, T)>>, MrclamError> {
    let mut buf = Vec::new();
    let mut line = 0usize;
    let mut nums = Vec::with_capacity(cols);
    let (mut rows, mut errors) = (Vec::new(), Vec::new());
    loop {
        buf.clear();
        line += 1;
        let too_long = match read_bounded(&mut r, &mut buf) {
            Ok(LineRead::End) => {
                return Ok(Lenient {
                    value: rows,
                    skipped: errors,
                })
            }
            Ok(LineRead::Line { .. }) => false,
            Ok(LineRead::TooLong { .. }) => true,
            Err(source) => return Err(MrclamError::Read { file, line, source }),
        };
        let bytes = match (line, buf.strip_prefix(b"\xEF\xBB\xBF")) {
            (1, Some(rest)) => rest,
            _ => &buf[..],
        };
        let parsed = (if too_long {
            Err(LineProblem::TooLong)
        } else {
            Ok(bytes)
        })
        .and_then(|bytes| {
            std::str::from_utf8(bytes).map_err(|e| LineProblem::NotUtf8 {
                column: e.valid_up_to() + 1,
            })
        })
        .and_then(|text| {
            let text = text.trim();
            if text.is_empty() || text.starts_with('#') {
                return Ok(None);
            }
            let toks: Vec<&str> = text.split_whitespace().collect();
            fields(&toks, cols, &mut nums)?;
            f(&nums, &toks).map(Some)
        });
        match parsed {
            Ok(Some(row)) => rows.push((line, row)),
            Ok(None) => {}
            Err(problem) => errors.push(MrclamError::Malformed {
                file,
                line,
                problem,
            }),
        }
    }
}

/// Parses a line's `cols` tokens into finite numbers.
fn fields(toks: &[&str], cols: usize, nums: &mut Vec<f64>) -> Result<(), LineProblem> {
    if toks.len() != cols {
        return Err(LineProblem::FieldCount {
            expected: cols,
            found: toks.len(),
        });
    }
    nums.clear();
    for (k, t) in toks.iter().enumerate() {
        let v: f64 = t.parse().map_err(|_| LineProblem::NotANumber {
            column: k + 1,
            text: (*t).to_string(),
        })?;
        if !v.is_finite() {
            return Err(LineProblem::NonFinite { column: k + 1 });
        }
        nums.push(v);
    }
    Ok(())
}

/// Keeps the rows whose time is in order, judging each against the previous kept row and the
/// next row ([`crate::io::time_order::judge`]: one corrupt time is the one row dropped); the
/// dropped rows' errors join `errors`, which is then put back in line order. Linear.
fn in_time_order<T>(
    rows: Vec<(usize, T)>,
    time: impl Fn(&T) -> f64,
    file: FileKind,
    mut errors: Vec<MrclamError>,
) -> Lenient<Vec<T>> {
    let times: Vec<f64> = rows.iter().map(|(_, r)| time(r)).collect();
    let mut kept = Vec::with_capacity(rows.len());
    let mut previous = None;
    let had_errors = !errors.is_empty();
    for (i, (line, row)) in rows.into_iter().enumerate() {
        let t = times[i];
        let problem = match judge(previous, t, times.get(i + 1).copied(), TimePolicy::Monotone) {
            TimeVerdict::Keep | TimeVerdict::Restart { .. } => {
                previous = Some(t);
                kept.push(row);
                continue;
            }
            TimeVerdict::Backwards { previous } => LineProblem::TimeGoesBack { previous, time: t },
            TimeVerdict::Outlier { next } => LineProblem::TimeOutlier { time: t, next },
        };
        errors.push(MrclamError::Malformed {
            file,
            line,
            problem,
        });
    }
    if had_errors {
        errors.sort_by_key(MrclamError::line);
    }
    Lenient {
        value: kept,
        skipped: errors,
    }
}

/// Parses a field that must be a non-negative integer id.
fn id(toks: &[&str], k: usize) -> Result<u32, LineProblem> {
    toks[k].parse().map_err(|_| LineProblem::NotANumber {
        column: k + 1,
        text: toks[k].to_string(),
    })
}

/// Reads `Barcodes.dat` (`subject barcode`), skipping bad lines.
///
/// # Errors
/// A read error of `r`.
pub fn read_barcodes_lenient<R: BufRead>(r: R) -> Result<Lenient<Barcodes>, MrclamError> {
    let Lenient {
        value: rows,
        skipped,
    } = parse_rows(r, FileKind::Barcodes, 2, |_, t| Ok((id(t, 0)?, id(t, 1)?)))?;
    let mut b = Barcodes::default();
    for (_, (subject, barcode)) in rows {
        b.subject_of.insert(barcode, subject);
    }
    Ok(Lenient { value: b, skipped })
}

/// Reads `Barcodes.dat`; the first bad line is an error.
///
/// # Errors
/// A read error or the first malformed line.
pub fn read_barcodes<R: BufRead>(r: R) -> Result<Barcodes, MrclamError> {
    read_barcodes_lenient(r)?.strict()
}

/// Reads `Landmark_Groundtruth.dat` (`subject x y x_std y_std`), skipping bad lines.
///
/// # Errors
/// A read error of `r`.
pub fn read_landmarks_lenient<R: BufRead>(
    r: R,
) -> Result<Lenient<Vec<LandmarkTruth>>, MrclamError> {
    let Lenient {
        value: rows,
        skipped,
    } = parse_rows(r, FileKind::LandmarkGroundtruth, 5, |n, t| {
        Ok(LandmarkTruth {
            subject: id(t, 0)?,
            x: n[1],
            y: n[2],
            x_std: n[3],
            y_std: n[4],
        })
    })?;
    let value = rows.into_iter().map(|(_, l)| l).collect();
    Ok(Lenient { value, skipped })
}

/// Reads `Landmark_Groundtruth.dat`; the first bad line is an error.
///
/// # Errors
/// A read error or the first malformed line.
pub fn read_landmarks<R: BufRead>(r: R) -> Result<Vec<LandmarkTruth>, MrclamError> {
    read_landmarks_lenient(r)?.strict()
}

/// Reads `RobotN_Odometry.dat` (`time v ω`), skipping bad lines and times out of order.
///
/// # Errors
/// A read error of `r`.
pub fn read_odometry_lenient<R: BufRead>(r: R) -> Result<Lenient<Vec<OdometryRow>>, MrclamError> {
    let Lenient {
        value: rows,
        skipped: errors,
    } = parse_rows(r, FileKind::Odometry, 3, |n, _| {
        Ok(OdometryRow {
            t: n[0],
            v: n[1],
            w: n[2],
        })
    })?;
    Ok(in_time_order(rows, |r| r.t, FileKind::Odometry, errors))
}

/// Reads `RobotN_Odometry.dat`; times must not decrease; the first bad line is an error.
///
/// # Errors
/// A read error or the first malformed line.
pub fn read_odometry<R: BufRead>(r: R) -> Result<Vec<OdometryRow>, MrclamError> {
    read_odometry_lenient(r)?.strict()
}

/// Reads `RobotN_Measurement.dat` (`time barcode range bearing`), mapping barcodes through
/// `codes` (unknown barcodes are dropped and counted), skipping bad lines and times out of
/// order.
///
/// # Errors
/// A read error of `r`.
pub fn read_measurements_lenient<R: BufRead>(
    r: R,
    codes: &Barcodes,
) -> Result<Lenient<Measurements>, MrclamError> {
    let Lenient {
        value: rows,
        skipped: errors,
    } = parse_rows(r, FileKind::Measurement, 4, |n, t| {
        let barcode = id(t, 1)?;
        if n[2] < 0.0 {
            return Err(LineProblem::NegativeRange);
        }
        Ok((barcode, n[0], n[2], n[3]))
    })?;
    let timed = in_time_order(rows, |r| r.1, FileKind::Measurement, errors);
    let mut m = Measurements::default();
    for (barcode, t, range, bearing) in timed.value {
        match codes.subject_of.get(&barcode) {
            Some(&subject) => m.rows.push(MeasurementRow {
                t,
                subject,
                range,
                bearing,
            }),
            None => {
                m.misread += 1;
                *m.misread_barcodes.entry(barcode).or_insert(0) += 1;
            }
        }
    }
    Ok(Lenient {
        value: m,
        skipped: timed.skipped,
    })
}

/// Reads `RobotN_Measurement.dat`; the first bad line is an error.
///
/// # Errors
/// A read error or the first malformed line.
pub fn read_measurements<R: BufRead>(r: R, codes: &Barcodes) -> Result<Measurements, MrclamError> {
    read_measurements_lenient(r, codes)?.strict()
}

/// Reads `RobotN_Groundtruth.dat` (`time x y θ`), skipping bad lines and times out of order.
///
/// # Errors
/// A read error of `r`.
pub fn read_groundtruth_lenient<R: BufRead>(r: R) -> Result<Lenient<Vec<TruthRow>>, MrclamError> {
    let Lenient {
        value: rows,
        skipped: errors,
    } = parse_rows(r, FileKind::Groundtruth, 4, |n, _| {
        Ok(TruthRow {
            t: n[0],
            x: n[1],
            y: n[2],
            theta: n[3],
        })
    })?;
    Ok(in_time_order(rows, |r| r.t, FileKind::Groundtruth, errors))
}

/// Reads `RobotN_Groundtruth.dat`; times must not decrease; the first bad line is an error.
///
/// # Errors
/// A read error or the first malformed line.
pub fn read_groundtruth<R: BufRead>(r: R) -> Result<Vec<TruthRow>, MrclamError> {
    read_groundtruth_lenient(r)?.strict()
}

/// Integrates unicycle motion (`v`, `ω` held for `dt`) onto a pose expressed
/// in the frame's start coordinates.
fn integrate(p: &mut Pose2, v: f64, w: f64, dt: f64) {
    if dt <= 0.0 {
        return;
    }
    if w.abs() < 1e-9 {
        p.x += v * dt * p.theta.cos();
        p.y += v * dt * p.theta.sin();
    } else {
        let th1 = p.theta + w * dt;
        p.x += v / w * (th1.sin() - p.theta.sin());
        p.y -= v / w * (th1.cos() - p.theta.cos());
        p.theta = th1;
    }
}

/// Most odometry-only frames inserted into one gap between measurements;
/// a longer gap (a corrupt timestamp) gets none.
const MAX_FILLERS: f64 = 100_000.0;

/// The frame times of [`merge`]: `t0`, every distinct measurement time in
/// `[t0, t1]`, `t1`, and fillers so that no gap exceeds `max_gap` (no fillers
/// when it is not a positive number).
fn frame_times(meas: &[MeasurementRow], (t0, t1): (f64, f64), max_gap: f64) -> Vec<f64> {
    let gap = if max_gap > 0.0 && max_gap.is_finite() {
        max_gap
    } else {
        f64::INFINITY
    };
    let mut times = vec![t0];
    let mut mi = meas.partition_point(|m| m.t < t0);
    let mut mt: Vec<f64> = Vec::new();
    while mi < meas.len() && meas[mi].t <= t1 {
        if mt.last() != Some(&meas[mi].t) {
            mt.push(meas[mi].t);
        }
        mi += 1;
    }
    mt.push(t1);
    for &t in &mt {
        let mut prev = *times.last().unwrap_or(&t0);
        // A corrupt time far in the future must not make millions of frames.
        let fillers = ((t - prev) / gap).floor();
        if fillers > MAX_FILLERS {
            prev = t - gap;
        }
        while t - prev > gap {
            prev += gap;
            times.push(prev);
        }
        if t > prev {
            times.push(t);
        }
    }
    times
}

/// Merges one robot's odometry, measurements and truth into frames.
///
/// Frames fall on every distinct measurement time within the odometry's time
/// span, plus odometry-only frames so that no two consecutive frames are more
/// than `max_frame_gap` apart; the first frame is at the first odometry time.
/// Each odometry row's `(v, ω)` holds until the next row (zero-order hold),
/// and the motion between consecutive frames is integrated exactly for a
/// unicycle. Measurements outside the odometry span are left out.
pub fn merge(
    odometry: &[OdometryRow],
    meas: &[MeasurementRow],
    truth: &[TruthRow],
    opts: &MergeOptions,
) -> Vec<MetricFrame> {
    let (Some(first), Some(last)) = (odometry.first(), odometry.last()) else {
        return Vec::new();
    };
    let (t0, t1) = (first.t, last.t);
    let times = frame_times(meas, (t0, t1), opts.max_frame_gap);
    // Walk the odometry along the frame times.
    let mut frames = Vec::with_capacity(times.len());
    let mut oi = 0usize; // current odometry row: odometry[oi].t <= now
    let mut now = t0;
    let mut mj = meas.partition_point(|m| m.t < t0);
    for &t in &times {
        let mut p = Pose2::default();
        while now < t {
            while oi + 1 < odometry.len() && odometry[oi + 1].t <= now {
                oi += 1;
            }
            let end = if oi + 1 < odometry.len() {
                odometry[oi + 1].t.min(t)
            } else {
                t
            };
            integrate(&mut p, odometry[oi].v, odometry[oi].w, end - now);
            now = end;
        }
        let dt = frames.last().map_or(0.0, |f: &MetricFrame| t - f.t);
        let mut observations = Vec::new();
        while mj < meas.len() && meas[mj].t <= t {
            if meas[mj].t == t {
                let m = meas[mj];
                observations.push(LandmarkReading {
                    subject: m.subject,
                    range: m.range,
                    bearing: m.bearing,
                });
            }
            mj += 1;
        }
        frames.push(MetricFrame {
            t,
            dt,
            odometry: Odometry {
                forward: p.x,
                left: p.y,
                turn: p.theta,
            },
            observations,
            truth: interpolate_truth(truth, t, opts.max_truth_gap),
        });
    }
    frames
}
