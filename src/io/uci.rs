//! Reader for the UCI "Wall-Following Robot Navigation" sonar files
//! (SCITOS G5, 24 ultrasonic sensors): `sensor_readings_24.data`
//! (`US1,…,US24,class`, optionally with a header line), and the simplified
//! `sensor_readings_4.data` (`front,left,right,back,class`) and
//! `sensor_readings_2.data` (`front,left,class`).
//!
//! Like every reader in `io`, it parses lines the caller supplies
//! ([`parse_line`]) or pulls them from a caller-supplied [`BufRead`]
//! ([`UciReader`]); malformed rows are [`UciError`]s with the 1-based line
//! number. Depends on `thiserror` only.
//!
//! Sensor geometry (a documented inference of the data README, not a
//! statement of the data set's creators): sensor `k` (1-based) points at
//! `(k − 13)·15°`, counter-clockwise from the heading, so US13 looks
//! forward, US19 left, US1 backwards and US7 right. Ranges are metres;
//! ~5.0 m means no echo.

use std::io::BufRead;

use thiserror::Error;

/// Why a UCI line was rejected.
#[derive(Debug, Error)]
pub enum UciError {
    /// The row has a number of fields that matches none of the three files.
    #[error("line {line}: {found} comma-separated fields; expected 25, 5 or 3")]
    FieldCount {
        /// 1-based line number.
        line: usize,
        /// Fields found.
        found: usize,
    },
    /// A range is not a finite number.
    #[error("line {line}: column {column} = {token:?} is not a finite number")]
    BadNumber {
        /// 1-based line number.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The offending text.
        token: String,
    },
    /// The class label is not one of the four.
    #[error("line {line}: unknown class label {token:?}")]
    UnknownClass {
        /// 1-based line number.
        line: usize,
        /// The label found.
        token: String,
    },
    /// The line is not valid UTF-8.
    #[error("line {line}: not valid UTF-8")]
    NotUtf8 {
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

impl UciError {
    /// The 1-based line number the error refers to.
    pub fn line(&self) -> usize {
        match self {
            UciError::FieldCount { line, .. }
            | UciError::BadNumber { line, .. }
            | UciError::UnknownClass { line, .. }
            | UciError::NotUtf8 { line }
            | UciError::Io { line, .. } => *line,
        }
    }
}

/// The navigation command recorded with each row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum UciClass {
    /// `Move-Forward`.
    MoveForward,
    /// `Sharp-Right-Turn`.
    SharpRightTurn,
    /// `Slight-Right-Turn`.
    SlightRightTurn,
    /// `Slight-Left-Turn`.
    SlightLeftTurn,
}

impl UciClass {
    fn parse(s: &str) -> Option<Self> {
        match s {
            "Move-Forward" => Some(UciClass::MoveForward),
            "Sharp-Right-Turn" => Some(UciClass::SharpRightTurn),
            "Slight-Right-Turn" => Some(UciClass::SlightRightTurn),
            "Slight-Left-Turn" => Some(UciClass::SlightLeftTurn),
            _ => None,
        }
    }
}

/// Which of the three files a row comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UciFormat {
    /// 24 raw sensors.
    Sensors24,
    /// front, left, right, back.
    Simplified4,
    /// front, left.
    Simplified2,
}

/// One row: ranges in metres and the class label.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UciRow {
    /// Which file layout.
    pub format: UciFormat,
    values: [f64; 24],
    len: usize,
    /// Navigation command.
    pub class: UciClass,
}

impl UciRow {
    /// The ranges in file order, metres.
    pub fn ranges(&self) -> &[f64] {
        &self.values[..self.len]
    }

    /// Sensor `US<k>`, `k` in 1..=24, metres (24-sensor rows only).
    pub fn sensor(&self, k: usize) -> Option<f64> {
        (self.format == UciFormat::Sensors24 && (1..=24).contains(&k)).then(|| self.values[k - 1])
    }

    /// Range to the left: US19 (+90°), or the simplified `SD_left`.
    pub fn left(&self) -> f64 {
        match self.format {
            UciFormat::Sensors24 => self.values[18],
            UciFormat::Simplified4 | UciFormat::Simplified2 => self.values[1],
        }
    }

    /// Range to the right: US7 (−90°), or `SD_right`; `None` in the 2-value file.
    pub fn right(&self) -> Option<f64> {
        match self.format {
            UciFormat::Sensors24 => Some(self.values[6]),
            UciFormat::Simplified4 => Some(self.values[2]),
            UciFormat::Simplified2 => None,
        }
    }
}

/// Bearing of sensor `US<k>`, radians CCW from the heading: `(k − 13)·15°`.
pub fn sensor_bearing(k: usize) -> Option<f64> {
    (1..=24)
        .contains(&k)
        .then(|| ((k as f64) - 13.0) * 15f64.to_radians())
}

/// What one line holds.
// A row is 200 bytes inline on purpose: boxing it would allocate per row.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UciLine {
    /// A data row.
    Row(UciRow),
    /// A header line (no field parses as a number), e.g. `S1,…,S24,OUTPUT`.
    Header,
    /// An empty line.
    Blank,
}

/// Parses one line; `line` is its 1-based number, used in errors.
///
/// # Errors
/// [`UciError`] on a wrong field count, a non-numeric range or an unknown class.
///
/// # Complexity
/// `O(length of the line)`, no allocation on success.
///
/// # Example
/// ```
/// use lplace::io::uci::{parse_line, UciClass, UciLine};
/// let UciLine::Row(r) = parse_line(1, "1.687,0.445,Slight-Right-Turn").unwrap() else { panic!() };
/// assert_eq!((r.ranges(), r.left(), r.class), (&[1.687, 0.445][..], 0.445, UciClass::SlightRightTurn));
/// assert_eq!(parse_line(4, "1.6,x,Move-Forward").unwrap_err().line(), 4);
/// ```
pub fn parse_line(line: usize, text: &str) -> Result<UciLine, UciError> {
    let text = text.trim();
    if text.is_empty() {
        return Ok(UciLine::Blank);
    }
    let found = text.split(',').count();
    let format = match found {
        25 => UciFormat::Sensors24,
        5 => UciFormat::Simplified4,
        3 => UciFormat::Simplified2,
        _ => {
            if text.split(',').all(|t| t.trim().parse::<f64>().is_err()) {
                return Ok(UciLine::Header);
            }
            return Err(UciError::FieldCount { line, found });
        }
    };
    if text.split(',').all(|t| t.trim().parse::<f64>().is_err()) {
        return Ok(UciLine::Header);
    }
    let mut values = [0.0; 24];
    let mut fields = text.split(',');
    for (i, slot) in values.iter_mut().take(found - 1).enumerate() {
        let token = fields.next().unwrap_or("").trim();
        match token.parse::<f64>() {
            Ok(v) if v.is_finite() => *slot = v,
            _ => {
                return Err(UciError::BadNumber {
                    line,
                    column: i + 1,
                    token: token.to_owned(),
                })
            }
        }
    }
    let label = fields.next().unwrap_or("").trim();
    let class = UciClass::parse(label).ok_or_else(|| UciError::UnknownClass {
        line,
        token: label.to_owned(),
    })?;
    Ok(UciLine::Row(UciRow {
        format,
        values,
        len: found - 1,
        class,
    }))
}

/// Streams `(line number, row)` from a caller-supplied reader, skipping
/// header and blank lines. A malformed row yields its error and reading
/// continues; an I/O error is yielded once and ends the iteration.
///
/// # Example
/// ```
/// use lplace::io::uci::UciReader;
/// let rows: Vec<_> = UciReader::new("SD_front,SD_left,OUTPUT\n1.0,0.5,Move-Forward\n".as_bytes())
///     .collect::<Result<_, _>>().unwrap();
/// assert_eq!(rows[0].0, 2);
/// ```
#[derive(Debug)]
pub struct UciReader<R> {
    source: R,
    buf: Vec<u8>,
    line: usize,
    done: bool,
}

impl<R: BufRead> UciReader<R> {
    /// Wraps a buffered source.
    pub fn new(source: R) -> Self {
        UciReader {
            source,
            buf: Vec::with_capacity(512),
            line: 0,
            done: false,
        }
    }
}

impl<R: BufRead> Iterator for UciReader<R> {
    type Item = Result<(usize, UciRow), UciError>;

    fn next(&mut self) -> Option<Self::Item> {
        while !self.done {
            self.buf.clear();
            let line = self.line + 1;
            match self.source.read_until(b'\n', &mut self.buf) {
                Ok(0) => self.done = true,
                Ok(_) => {
                    self.line = line;
                    // A UTF-8 byte-order mark before the first line is not part of it.
                    let bytes = match (line, self.buf.strip_prefix(b"\xEF\xBB\xBF")) {
                        (1, Some(rest)) => rest,
                        _ => &self.buf[..],
                    };
                    let Ok(text) = std::str::from_utf8(bytes) else {
                        return Some(Err(UciError::NotUtf8 { line }));
                    };
                    match parse_line(line, text) {
                        Ok(UciLine::Row(r)) => return Some(Ok((line, r))),
                        Ok(UciLine::Header | UciLine::Blank) => {}
                        Err(e) => return Some(Err(e)),
                    }
                }
                Err(source) => {
                    self.done = true;
                    return Some(Err(UciError::Io { line, source }));
                }
            }
        }
        None
    }
}
