//! One byte per cell, run-length encoded: how robots exchange object grids (paper 002 §4.1,
//! "we convert each cell value to one byte and treat the grid as a grey-scale image. We then
//! compress the grid using a simple run length encoding scheme").
//!
//! Format: an 8-byte header — columns and rows as little-endian `u32` — then runs of two bytes,
//! `count` (1–255) and `value`, in row-major order, covering exactly `columns · rows` cells. The
//! grid's origin and cell size are not sent: all robots share the global frame (paper 002 §2.3).
//! A byte `v` stands for the possibility `v / 255`; [`quantize`] rounds to the nearest byte, so a
//! round trip moves a value by at most 1/510.
//!
//! # Complexity
//!
//! Encoding and decoding are O(cells); the code is 8 + 2 · runs bytes.
//!
//! # Example
//!
//! ```
//! use lplace::coop::rle::{decode, encode};
//! let cells = [26u8, 26, 26, 255, 26];
//! let code = encode(5, 1, &cells).unwrap();
//! assert_eq!(&code[8..], &[3, 26, 1, 255, 1, 26]);
//! assert_eq!(decode(&code).unwrap(), (5, 1, cells.to_vec()));
//! assert!(decode(&code[..9]).is_err()); // a run cut in half
//! ```

use super::{GridGeometry, ObjectGrid};
use crate::grid::cells::MAX_CELLS;

/// Why bytes are not a valid run-length code (or cells cannot be encoded).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RleError {
    /// Fewer than the 8 header bytes.
    #[error("run-length code of {len} byte(s) is shorter than its 8-byte header")]
    ShortHeader {
        /// Bytes given.
        len: usize,
    },
    /// The header announces more cells than any grid may have.
    #[error("run-length header announces {nx}×{ny} cells, more than the limit of {limit}")]
    TooLarge {
        /// Columns announced.
        nx: u64,
        /// Rows announced.
        ny: u64,
        /// The limit ([`MAX_CELLS`]).
        limit: usize,
    },
    /// The code ends in the middle of a run.
    #[error("run-length code ends inside a run at byte {offset}")]
    CutRun {
        /// Offset of the lone count byte.
        offset: usize,
    },
    /// A run of length 0.
    #[error("run of length 0 at byte {offset}")]
    ZeroRun {
        /// Offset of the count byte.
        offset: usize,
    },
    /// The runs cover more cells than the header announces.
    #[error("run at byte {offset} goes past the {cells} cells the header announces")]
    Overrun {
        /// Offset of the count byte.
        offset: usize,
        /// Cells announced.
        cells: usize,
    },
    /// The runs cover fewer cells than the header announces.
    #[error("runs cover {found} cells, the header announces {expected}")]
    Underrun {
        /// Cells announced.
        expected: usize,
        /// Cells covered.
        found: usize,
    },
    /// Encoding: the number of cells is not `nx · ny`.
    #[error("{found} cells given for a {nx}×{ny} grid")]
    CellCount {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
        /// Cells given.
        found: usize,
    },
    /// Decoding into a grid: the code's size is not the receiver's grid.
    #[error("run-length code is {nx}×{ny} cells, the receiving grid {want_nx}×{want_ny}")]
    WrongSize {
        /// Columns in the code.
        nx: usize,
        /// Rows in the code.
        ny: usize,
        /// Columns expected.
        want_nx: usize,
        /// Rows expected.
        want_ny: usize,
    },
}

/// A possibility as one byte: `round(255 · v)`, clamped to [0, 1] (NaN → 0).
pub fn quantize(v: f32) -> u8 {
    if v.is_nan() {
        0
    } else {
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// The possibility a byte stands for: `b / 255`.
pub fn dequantize(b: u8) -> f32 {
    b as f32 / 255.0
}

/// Encodes `nx × ny` one-byte cells (row-major).
///
/// # Errors
/// [`RleError::CellCount`] when `cells.len() != nx · ny`, [`RleError::TooLarge`] beyond
/// [`MAX_CELLS`].
pub fn encode(nx: usize, ny: usize, cells: &[u8]) -> Result<Vec<u8>, RleError> {
    let fits = nx <= u32::MAX as usize && ny <= u32::MAX as usize;
    let n = nx.checked_mul(ny).filter(|&n| fits && n <= MAX_CELLS);
    let Some(n) = n else {
        return Err(RleError::TooLarge {
            nx: nx as u64,
            ny: ny as u64,
            limit: MAX_CELLS,
        });
    };
    if cells.len() != n {
        return Err(RleError::CellCount {
            nx,
            ny,
            found: cells.len(),
        });
    }
    let mut out = Vec::with_capacity(8 + 16);
    out.extend_from_slice(&(nx as u32).to_le_bytes());
    out.extend_from_slice(&(ny as u32).to_le_bytes());
    let mut k = 0;
    while k < n {
        let v = cells[k];
        let mut run = 1;
        while run < 255 && k + run < n && cells[k + run] == v {
            run += 1;
        }
        out.push(run as u8);
        out.push(v);
        k += run;
    }
    Ok(out)
}

/// Decodes a code made by [`encode`] into `(nx, ny, cells)`. Never panics; every malformed
/// input is an [`RleError`] saying where.
pub fn decode(code: &[u8]) -> Result<(usize, usize, Vec<u8>), RleError> {
    if code.len() < 8 {
        return Err(RleError::ShortHeader { len: code.len() });
    }
    let word = |k: usize| u32::from_le_bytes([code[k], code[k + 1], code[k + 2], code[k + 3]]);
    let (nx, ny) = (word(0) as u64, word(4) as u64);
    let n = nx * ny; // two u32 cannot overflow u64
    if n > MAX_CELLS as u64 {
        return Err(RleError::TooLarge {
            nx,
            ny,
            limit: MAX_CELLS,
        });
    }
    let n = n as usize;
    let mut cells = Vec::with_capacity(n.min(code.len().saturating_mul(128)));
    let mut offset = 8;
    while offset < code.len() {
        let Some(&value) = code.get(offset + 1) else {
            return Err(RleError::CutRun { offset });
        };
        let count = code[offset] as usize;
        if count == 0 {
            return Err(RleError::ZeroRun { offset });
        }
        if cells.len() + count > n {
            return Err(RleError::Overrun { offset, cells: n });
        }
        cells.resize(cells.len() + count, value);
        offset += 2;
    }
    if cells.len() != n {
        return Err(RleError::Underrun {
            expected: n,
            found: cells.len(),
        });
    }
    Ok((nx as usize, ny as usize, cells))
}

impl ObjectGrid {
    /// The grid as one byte per cell, run-length encoded (see the module docs).
    pub fn to_rle(&self) -> Vec<u8> {
        let g = self.geometry();
        let bytes: Vec<u8> = self.values().iter().map(|&v| quantize(v)).collect();
        // A grid's geometry always matches its values and respects MAX_CELLS (it comes from a
        // FuzzyGrid or was checked by `ObjectGrid::new`), so encoding cannot fail; fall back to
        // an empty code rather than panic.
        encode(g.nx, g.ny, &bytes).unwrap_or_default()
    }

    /// A grid received as a run-length code, placed in the receiver's `geometry`.
    ///
    /// # Errors
    /// Any [`decode`] error, or [`RleError::WrongSize`] when the code is not `geometry`'s size.
    pub fn from_rle(geometry: GridGeometry, code: &[u8]) -> Result<ObjectGrid, RleError> {
        let (nx, ny, cells) = decode(code)?;
        if nx != geometry.nx || ny != geometry.ny {
            return Err(RleError::WrongSize {
                nx,
                ny,
                want_nx: geometry.nx,
                want_ny: geometry.ny,
            });
        }
        let values = cells.into_iter().map(dequantize).collect();
        ObjectGrid::new(geometry, values).ok_or(RleError::WrongSize {
            nx,
            ny,
            want_nx: geometry.nx,
            want_ny: geometry.ny,
        })
    }
}
