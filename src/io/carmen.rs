//! Reader for CARMEN text logs (the Radish / GMapping "corrected" logs):
//! `FLASER`, `ODOM` and `PARAM` messages; every other message type (`NEFF`,
//! `RLASER`, `ROBOTLASER1`, `SYNC`, `TRUEPOS`, …) is skipped and counted.
//!
//! The reader does no I/O of its own: [`parse_line`] takes one line, and
//! [`CarmenReader`] pulls lines from a caller-supplied [`BufRead`], one at a
//! time, so a log is never loaded whole. Malformed lines are
//! [`CarmenError`]s carrying the 1-based line number and the reason; the
//! reader keeps going after one, so the caller decides whether to skip and
//! report or to stop. Depends on `crate::percept` for the pose and scan-view
//! types only.
//!
//! # Message layouts (whitespace separated)
//! ```text
//! FLASER n r_1 … r_n x y theta odom_x odom_y odom_theta ipc_ts [host logger_ts]
//! ODOM x y theta tv rv accel ipc_ts [host logger_ts]
//! PARAM name value [ts host ts]
//! ```
//! Units: metres, radians, seconds. `FLASER` beams sweep 180° from the
//! robot's right to its left: beam `i` has bearing `−π/2 + i·δ` with
//! `δ = π/n` for even `n` and `π/(n − 1)` for odd `n` (the convention the
//! data README verified on the maps).

use std::collections::BTreeMap;
use std::io::BufRead;

use super::line::{read_bounded, LineRead, MAX_LINE};

use thiserror::Error;

use crate::core::Pose2;
use crate::percept::scan::ScanView;

/// Why a line of a CARMEN log was rejected.
#[derive(Debug, Error)]
pub enum CarmenError {
    /// The message ends before a required field.
    #[error("line {line}: {kind} message too short: missing {field} (field {index})")]
    MissingField {
        /// 1-based line number.
        line: usize,
        /// Message type.
        kind: &'static str,
        /// Name of the missing field.
        field: &'static str,
        /// 0-based index of the field after the message keyword.
        index: usize,
    },
    /// A numeric field does not hold a finite number.
    #[error(
        "line {line}: {kind} field {field} (field {index}) = {token:?} is not a finite number"
    )]
    BadNumber {
        /// 1-based line number.
        line: usize,
        /// Message type.
        kind: &'static str,
        /// Name of the field.
        field: &'static str,
        /// 0-based index of the field after the message keyword.
        index: usize,
        /// The offending text.
        token: String,
    },
    /// The declared beam count is not a count, or more beams are declared
    /// than the line holds.
    #[error("line {line}: FLASER declares {declared:?} beams but the line holds {available} fields after it")]
    BeamCount {
        /// 1-based line number.
        line: usize,
        /// The declared count as written.
        declared: String,
        /// Fields after the count.
        available: usize,
    },
    /// The line is not valid UTF-8.
    #[error("line {line}: not valid UTF-8")]
    NotUtf8 {
        /// 1-based line number.
        line: usize,
    },
    /// The line is longer than [`MAX_LINE`] bytes (dropped unread).
    #[error("line {line}: longer than {MAX_LINE} bytes")]
    TooLong {
        /// 1-based line number.
        line: usize,
    },
    /// The underlying reader failed.
    #[error("line {line}: read error: {source}")]
    Io {
        /// 1-based number of the line being read.
        line: usize,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}

impl CarmenError {
    /// The 1-based line number the error refers to.
    pub fn line(&self) -> usize {
        match self {
            CarmenError::MissingField { line, .. }
            | CarmenError::BadNumber { line, .. }
            | CarmenError::BeamCount { line, .. }
            | CarmenError::NotUtf8 { line }
            | CarmenError::TooLong { line }
            | CarmenError::Io { line, .. } => *line,
        }
    }
}

/// One front-laser scan (`FLASER`).
#[derive(Debug, Clone, PartialEq)]
pub struct LaserScan {
    /// Ranges, metres, from the robot's right to its left.
    pub ranges: Vec<f64>,
    /// Robot pose at scan time (SLAM-corrected in the corrected logs).
    pub pose: Pose2,
    /// Odometry pose as logged (equal to `pose` in the corrected logs).
    pub odom_pose: Pose2,
    /// `ipc_ts`, seconds.
    pub timestamp: f64,
}

impl LaserScan {
    /// Bearing of beam 0, radians: −π/2.
    pub fn first_bearing(&self) -> f64 {
        -std::f64::consts::FRAC_PI_2
    }

    /// Angular step between beams, radians: π/n for even n, π/(n−1) for odd n.
    pub fn bearing_step(&self) -> f64 {
        beam_step(self.ranges.len())
    }

    /// A borrowed view for [`crate::percept::ScanExtractor`]; `laser_offset_x`
    /// is `PARAM robot_frontlaser_offset` (see [`CarmenReader::laser_offset`]).
    pub fn view(&self, laser_offset_x: f64) -> ScanView<'_> {
        ScanView {
            pose: self.pose,
            ranges: &self.ranges,
            first_bearing: self.first_bearing(),
            bearing_step: self.bearing_step(),
            laser_offset_x,
        }
    }
}

/// The FLASER angular step for `n` beams over 180°.
pub fn beam_step(n: usize) -> f64 {
    let pi = std::f64::consts::PI;
    match n {
        0 | 1 => pi,
        n if n % 2 == 0 => pi / n as f64,
        n => pi / (n - 1) as f64,
    }
}

/// One odometry reading (`ODOM`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Odom {
    /// Pose, metres and radians.
    pub pose: Pose2,
    /// Translational velocity, m/s.
    pub tv: f64,
    /// Rotational velocity, rad/s.
    pub rv: f64,
    /// Acceleration, m/s².
    pub accel: f64,
    /// `ipc_ts`, seconds.
    pub timestamp: f64,
}

/// A message the reader understands.
#[derive(Debug, Clone, PartialEq)]
pub enum CarmenMessage {
    /// `FLASER`.
    Laser(LaserScan),
    /// `ODOM`.
    Odom(Odom),
    /// `PARAM name value`.
    Param {
        /// Parameter name.
        name: String,
        /// Its value as written.
        value: String,
    },
}

/// What one line holds.
#[derive(Debug, Clone, PartialEq)]
pub enum CarmenLine<'a> {
    /// A message the reader understands.
    Message(CarmenMessage),
    /// A `#` comment.
    Comment,
    /// An empty or whitespace-only line.
    Blank,
    /// A message type this reader skips; its keyword.
    Other(&'a str),
}

struct Fields<'a> {
    it: std::str::SplitAsciiWhitespace<'a>,
    index: usize,
    line: usize,
    kind: &'static str,
}

impl<'a> Fields<'a> {
    fn token(&mut self, field: &'static str) -> Result<&'a str, CarmenError> {
        let index = self.index;
        self.index += 1;
        self.it.next().ok_or(CarmenError::MissingField {
            line: self.line,
            kind: self.kind,
            field,
            index,
        })
    }

    fn num(&mut self, field: &'static str) -> Result<f64, CarmenError> {
        let index = self.index;
        let token = self.token(field)?;
        match token.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(CarmenError::BadNumber {
                line: self.line,
                kind: self.kind,
                field,
                index,
                token: token.to_owned(),
            }),
        }
    }

    fn pose(&mut self, names: [&'static str; 3]) -> Result<Pose2, CarmenError> {
        Ok(Pose2 {
            x: self.num(names[0])?,
            y: self.num(names[1])?,
            theta: self.num(names[2])?,
        })
    }
}

/// Parses one line of a CARMEN log; `line` is its 1-based number, used in errors.
///
/// # Errors
/// [`CarmenError`] when a known message is malformed. Unknown message
/// types are not errors: they come back as [`CarmenLine::Other`].
///
/// # Complexity
/// `O(length of the line)`; allocates the range vector of a scan.
///
/// # Example
/// ```
/// use lplace::io::carmen::{parse_line, CarmenLine, CarmenMessage};
/// let l = parse_line(7, "ODOM 1 2 0.5 0 0 0 3.25 pippo 3.25").unwrap();
/// let CarmenLine::Message(CarmenMessage::Odom(o)) = l else { panic!() };
/// assert_eq!((o.pose.x, o.pose.theta, o.timestamp), (1.0, 0.5, 3.25));
/// assert!(matches!(parse_line(8, "NEFF 14.8"), Ok(CarmenLine::Other("NEFF"))));
/// assert_eq!(parse_line(9, "ODOM 1 2").unwrap_err().line(), 9);
/// ```
pub fn parse_line(line: usize, text: &str) -> Result<CarmenLine<'_>, CarmenError> {
    let trimmed = text.trim_start();
    if trimmed.is_empty() {
        return Ok(CarmenLine::Blank);
    }
    if trimmed.starts_with('#') {
        return Ok(CarmenLine::Comment);
    }
    let mut it = trimmed.split_ascii_whitespace();
    let keyword = it.next().unwrap_or("");
    let mut f = Fields {
        it,
        index: 0,
        line,
        kind: "",
    };
    match keyword {
        "FLASER" => {
            f.kind = "FLASER";
            let declared = f.token("num_readings")?;
            // Counting the remaining fields first bounds the allocation by the
            // line's length, whatever count a corrupt line declares.
            let available = f.it.clone().count();
            let n = match declared.parse::<usize>() {
                Ok(n) if n.saturating_add(7) <= available => n,
                _ => {
                    return Err(CarmenError::BeamCount {
                        line,
                        declared: declared.to_owned(),
                        available,
                    })
                }
            };
            let mut ranges = Vec::with_capacity(n);
            for _ in 0..n {
                ranges.push(f.num("range")?);
            }
            let pose = f.pose(["x", "y", "theta"])?;
            let odom_pose = f.pose(["odom_x", "odom_y", "odom_theta"])?;
            let timestamp = f.num("ipc_timestamp")?;
            Ok(CarmenLine::Message(CarmenMessage::Laser(LaserScan {
                ranges,
                pose,
                odom_pose,
                timestamp,
            })))
        }
        "ODOM" => {
            f.kind = "ODOM";
            let pose = f.pose(["x", "y", "theta"])?;
            let tv = f.num("tv")?;
            let rv = f.num("rv")?;
            let accel = f.num("accel")?;
            let timestamp = f.num("ipc_timestamp")?;
            Ok(CarmenLine::Message(CarmenMessage::Odom(Odom {
                pose,
                tv,
                rv,
                accel,
                timestamp,
            })))
        }
        "PARAM" => {
            f.kind = "PARAM";
            let name = f.token("name")?.to_owned();
            let value = f.token("value")?.to_owned();
            Ok(CarmenLine::Message(CarmenMessage::Param { name, value }))
        }
        other => Ok(CarmenLine::Other(other)),
    }
}

/// Counts of what a [`CarmenReader`] has seen.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CarmenStats {
    /// Lines read.
    pub lines: u64,
    /// `FLASER` scans parsed.
    pub lasers: u64,
    /// `ODOM` readings parsed.
    pub odoms: u64,
    /// `PARAM` lines parsed.
    pub params: u64,
    /// Comment lines.
    pub comments: u64,
    /// Blank lines.
    pub blanks: u64,
    /// Lines rejected with an error.
    pub errors: u64,
    /// Skipped message types and how many lines of each.
    pub skipped: BTreeMap<String, u64>,
}

/// Streams the messages of a CARMEN log from a caller-supplied reader.
///
/// Yields `(line number, message)` for `FLASER`, `ODOM` and `PARAM`;
/// comments, blanks and other message types are only counted (see
/// [`CarmenReader::stats`]). A malformed line yields its error and reading
/// continues with the next line; an I/O error is yielded once and ends the
/// iteration.
///
/// # Complexity
/// `O(1)` memory besides the current line; one pass.
///
/// # Example
/// ```
/// use lplace::io::carmen::{CarmenMessage, CarmenReader};
/// let log = "PARAM robot_frontlaser_offset 0.1 nohost 0\nNEFF 3\nFLASER 2 1 1 0 0 0 0 0 0 5 h 5\n";
/// let mut rd = CarmenReader::new(log.as_bytes());
/// let msgs: Vec<_> = rd.by_ref().collect::<Result<_, _>>().unwrap();
/// assert_eq!(msgs.len(), 2);
/// assert_eq!(rd.laser_offset(), 0.1);
/// assert_eq!(rd.stats().skipped["NEFF"], 1);
/// ```
#[derive(Debug)]
pub struct CarmenReader<R> {
    source: R,
    buf: Vec<u8>,
    line: usize,
    stats: CarmenStats,
    laser_offset: f64,
    done: bool,
}

impl<R: BufRead> CarmenReader<R> {
    /// Wraps a buffered source.
    pub fn new(source: R) -> Self {
        CarmenReader {
            source,
            buf: Vec::with_capacity(4096),
            line: 0,
            stats: CarmenStats::default(),
            laser_offset: 0.0,
            done: false,
        }
    }

    /// What has been read so far.
    pub fn stats(&self) -> &CarmenStats {
        &self.stats
    }

    /// `PARAM robot_frontlaser_offset` as last seen (metres), 0 before any.
    pub fn laser_offset(&self) -> f64 {
        self.laser_offset
    }
}

impl<R: BufRead> Iterator for CarmenReader<R> {
    type Item = Result<(usize, CarmenMessage), CarmenError>;

    fn next(&mut self) -> Option<Self::Item> {
        while !self.done {
            self.buf.clear();
            let line = self.line + 1;
            match read_bounded(&mut self.source, &mut self.buf) {
                Ok(LineRead::End) => {
                    self.done = true;
                    return None;
                }
                Ok(LineRead::Line { .. }) => {}
                Ok(LineRead::TooLong { .. }) => {
                    self.line = line;
                    self.stats.lines += 1;
                    self.stats.errors += 1;
                    return Some(Err(CarmenError::TooLong { line }));
                }
                Err(source) => {
                    self.done = true;
                    self.stats.errors += 1;
                    return Some(Err(CarmenError::Io { line, source }));
                }
            }
            self.line = line;
            self.stats.lines += 1;
            // A UTF-8 byte-order mark before the first line is not part of it.
            let bytes = match (line, self.buf.strip_prefix(b"\xEF\xBB\xBF")) {
                (1, Some(rest)) => rest,
                _ => &self.buf[..],
            };
            let Ok(text) = std::str::from_utf8(bytes) else {
                self.stats.errors += 1;
                return Some(Err(CarmenError::NotUtf8 { line }));
            };
            match parse_line(line, text) {
                Err(e) => {
                    self.stats.errors += 1;
                    return Some(Err(e));
                }
                Ok(CarmenLine::Blank) => self.stats.blanks += 1,
                Ok(CarmenLine::Comment) => self.stats.comments += 1,
                Ok(CarmenLine::Other(kind)) => match self.stats.skipped.get_mut(kind) {
                    Some(c) => *c += 1,
                    None => {
                        self.stats.skipped.insert(kind.to_owned(), 1);
                    }
                },
                Ok(CarmenLine::Message(m)) => {
                    match &m {
                        CarmenMessage::Laser(_) => self.stats.lasers += 1,
                        CarmenMessage::Odom(_) => self.stats.odoms += 1,
                        CarmenMessage::Param { name, value } => {
                            self.stats.params += 1;
                            if name == "robot_frontlaser_offset" {
                                if let Ok(v) = value.parse::<f64>() {
                                    if v.is_finite() {
                                        self.laser_offset = v;
                                    }
                                }
                            }
                        }
                    }
                    return Some(Ok((line, m)));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn beam_step_follows_the_readme() {
        let d = std::f64::consts::PI / 180.0;
        assert!((beam_step(180) - d).abs() < 1e-15);
        assert!((beam_step(181) - d).abs() < 1e-15);
        assert!((beam_step(360) - d / 2.0).abs() < 1e-15);
        assert!((beam_step(361) - d / 2.0).abs() < 1e-15);
    }
}
