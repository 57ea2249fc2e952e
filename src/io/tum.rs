//! TUM trajectory format (`t x y z qx qy qz qw`, one pose per line), the
//! format `evo_ape` scores. Planar poses are written with `z = 0` and the yaw
//! as a rotation about z; reading back takes the yaw from the quaternion.
//! Writer and parser work on caller-supplied `Write`/`BufRead` handles.
//!
//! # Example
//!
//! ```
//! use lplace::io::tum::{read_tum, write_tum, TumPose};
//! let poses = [TumPose { t: 1.5, x: 1.0, y: 2.0, yaw: 0.5 }];
//! let mut out = Vec::new();
//! write_tum(&mut out, &poses).unwrap();
//! let back = read_tum(out.as_slice()).unwrap();
//! assert!((back[0].yaw - 0.5).abs() < 1e-9);
//! ```

use serde::{Deserialize, Serialize};
use std::io::{BufRead, Write};

/// A timestamped planar pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TumPose {
    /// Time (s).
    pub t: f64,
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Yaw (rad).
    pub yaw: f64,
}

/// Errors reading a TUM file.
#[derive(Debug, thiserror::Error)]
pub enum TumError {
    /// A line without 8 numeric fields.
    #[error(
        "line {line}: expected 8 numbers, found {found} fields (first bad field: {bad_field:?})"
    )]
    Malformed {
        /// 1-based line.
        line: usize,
        /// Fields found.
        found: usize,
        /// 1-based index of the first field that is not a finite number.
        bad_field: Option<usize>,
    },
    /// The reader failed.
    #[error("line {line}: read error: {source}")]
    Read {
        /// 1-based line.
        line: usize,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// Writes poses, one per line, with enough digits to round-trip times in
/// Unix seconds at microsecond precision.
pub fn write_tum<W: Write>(mut w: W, poses: &[TumPose]) -> std::io::Result<()> {
    for p in poses {
        let (s, c) = (0.5 * p.yaw).sin_cos();
        writeln!(
            w,
            "{:.6} {:.6} {:.6} 0 0 0 {:.9} {:.9}",
            p.t, p.x, p.y, s, c
        )?;
    }
    Ok(())
}

/// Reads a TUM file; `#` comments and blank lines are skipped.
pub fn read_tum<R: BufRead>(r: R) -> Result<Vec<TumPose>, TumError> {
    let mut out = Vec::new();
    for (k, line) in r.lines().enumerate() {
        let line_no = k + 1;
        let text = line.map_err(|source| TumError::Read {
            line: line_no,
            source,
        })?;
        let text = text.trim_start_matches('\u{feff}').trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let toks: Vec<&str> = text.split_whitespace().collect();
        let mut v = [0.0f64; 8];
        let mut bad = None;
        for (i, t) in toks.iter().enumerate().take(8) {
            match t.parse::<f64>() {
                Ok(x) if x.is_finite() => v[i] = x,
                _ => {
                    bad = Some(i + 1);
                    break;
                }
            }
        }
        if toks.len() != 8 || bad.is_some() {
            return Err(TumError::Malformed {
                line: line_no,
                found: toks.len(),
                bad_field: bad,
            });
        }
        let (qx, qy, qz, qw) = (v[4], v[5], v[6], v[7]);
        let yaw = (2.0 * (qw * qz + qx * qy)).atan2(1.0 - 2.0 * (qy * qy + qz * qz));
        out.push(TumPose {
            t: v[0],
            x: v[1],
            y: v[2],
            yaw,
        });
    }
    Ok(out)
}
