//! Binary images (the beacon and structured-light cameras of paper 003) and a
//! reader for the two PBM encodings, P1 (ASCII) and P4 (packed bits).
//!
//! The reader takes bytes the caller already holds and does no I/O, so the
//! same code reads files, network frames and test fixtures. Depends on
//! `thiserror` only.
//!
//! Pixel `(u, v)`: `u` is the column (0 at the left), `v` the row (0 at the
//! top, growing downwards). In PBM a 1 bit is black; black pixels are the
//! paper's "on" pixels (`P(u, v) = 1`), as in its Fig. 2.

use thiserror::Error;

/// Largest image accepted, in pixels; protects against hostile headers.
pub const MAX_PIXELS: usize = 1 << 26;

/// Why bytes are not a PBM image.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PbmError {
    /// The magic number is neither `P1` nor `P4`.
    #[error("not a PBM image: magic {found:?} is neither P1 nor P4")]
    BadMagic {
        /// The first two bytes found.
        found: [u8; 2],
    },
    /// The width or height field is missing or not a decimal number.
    #[error("PBM header: {field} missing or not a number at byte {offset}")]
    BadHeader {
        /// `"width"` or `"height"`.
        field: &'static str,
        /// Byte offset where it was expected.
        offset: usize,
    },
    /// Zero or too many pixels.
    #[error("PBM size {width}×{height} is empty or exceeds {MAX_PIXELS} pixels")]
    BadSize {
        /// Declared width.
        width: usize,
        /// Declared height.
        height: usize,
    },
    /// The raster ended early.
    #[error("PBM raster truncated: {expected} pixels expected, {found} found")]
    Truncated {
        /// Pixels expected.
        expected: usize,
        /// Pixels found.
        found: usize,
    },
    /// A P1 raster holds something other than `0`, `1`, whitespace or comments.
    #[error("PBM P1 raster: unexpected byte {byte:#04x} at offset {offset}")]
    BadPixel {
        /// The byte.
        byte: u8,
        /// Its offset.
        offset: usize,
    },
}

/// A binary image, one byte per pixel for simple indexing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BinaryImage {
    width: usize,
    height: usize,
    pixels: Vec<bool>,
}

impl BinaryImage {
    /// An all-off image; `None` when empty or larger than [`MAX_PIXELS`].
    pub fn new(width: usize, height: usize) -> Option<Self> {
        let n = width.checked_mul(height)?;
        if n == 0 || n > MAX_PIXELS {
            return None;
        }
        Some(BinaryImage {
            width,
            height,
            pixels: vec![false; n],
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Pixel `(u, v)`; off outside the image.
    pub fn get(&self, u: usize, v: usize) -> bool {
        u < self.width && v < self.height && self.pixels[v * self.width + u]
    }

    /// Sets pixel `(u, v)`; ignored outside the image.
    pub fn set(&mut self, u: usize, v: usize, on: bool) {
        if u < self.width && v < self.height {
            self.pixels[v * self.width + u] = on;
        }
    }

    /// The "on" pixels `(u, v)` in row-major order.
    pub fn on_pixels(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let w = self.width;
        self.pixels
            .iter()
            .enumerate()
            .filter(|(_, &on)| on)
            .map(move |(i, _)| (i % w, i / w))
    }

    /// Number of "on" pixels.
    pub fn count_on(&self) -> usize {
        self.pixels.iter().filter(|&&p| p).count()
    }

    /// Parses a PBM image (P1 or P4) from bytes.
    ///
    /// # Errors
    /// [`PbmError`] on a bad magic number, header, size or raster.
    ///
    /// # Complexity
    /// `O(bytes + pixels)`.
    ///
    /// # Example
    /// ```
    /// use lplace::percept::image::BinaryImage;
    /// let img = BinaryImage::from_pbm(b"P1\n# two by two\n2 2\n1 0\n0 1\n").unwrap();
    /// assert!(img.get(0, 0) && img.get(1, 1) && !img.get(1, 0));
    /// ```
    pub fn from_pbm(bytes: &[u8]) -> Result<Self, PbmError> {
        let magic = [
            bytes.first().copied().unwrap_or(0),
            bytes.get(1).copied().unwrap_or(0),
        ];
        let ascii = match &magic {
            b"P1" => true,
            b"P4" => false,
            _ => return Err(PbmError::BadMagic { found: magic }),
        };
        let mut pos = 2;
        let width = header_number(bytes, &mut pos, "width")?;
        let height = header_number(bytes, &mut pos, "height")?;
        let mut img = BinaryImage::new(width, height).ok_or(PbmError::BadSize { width, height })?;
        let expected = width * height;
        if ascii {
            let mut k = 0;
            while k < expected {
                skip_space_and_comments(bytes, &mut pos);
                match bytes.get(pos) {
                    Some(b'0') => {}
                    Some(b'1') => img.pixels[k] = true,
                    Some(&byte) => return Err(PbmError::BadPixel { byte, offset: pos }),
                    None => return Err(PbmError::Truncated { expected, found: k }),
                }
                pos += 1;
                k += 1;
            }
        } else {
            // Exactly one whitespace byte separates the header from the raster.
            pos += 1;
            let row_bytes = width.div_ceil(8);
            let raster = bytes.get(pos..).unwrap_or(&[]);
            if raster.len() < row_bytes * height {
                let found = (raster.len() / row_bytes.max(1)) * width;
                return Err(PbmError::Truncated { expected, found });
            }
            for v in 0..height {
                let row = &raster[v * row_bytes..(v + 1) * row_bytes];
                for u in 0..width {
                    img.pixels[v * width + u] = row[u / 8] & (0x80 >> (u % 8)) != 0;
                }
            }
        }
        Ok(img)
    }
}

fn skip_space_and_comments(bytes: &[u8], pos: &mut usize) {
    while let Some(&b) = bytes.get(*pos) {
        if b == b'#' {
            while let Some(&c) = bytes.get(*pos) {
                if c == b'\n' || c == b'\r' {
                    break;
                }
                *pos += 1;
            }
        } else if b.is_ascii_whitespace() {
            *pos += 1;
        } else {
            break;
        }
    }
}

fn header_number(bytes: &[u8], pos: &mut usize, field: &'static str) -> Result<usize, PbmError> {
    skip_space_and_comments(bytes, pos);
    let start = *pos;
    let mut n: usize = 0;
    while let Some(&b) = bytes.get(*pos) {
        if !b.is_ascii_digit() {
            break;
        }
        n = n
            .checked_mul(10)
            .and_then(|n| n.checked_add(usize::from(b - b'0')))
            .ok_or(PbmError::BadHeader {
                field,
                offset: start,
            })?;
        *pos += 1;
    }
    if *pos == start {
        return Err(PbmError::BadHeader {
            field,
            offset: start,
        });
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p4_bits_are_msb_first_and_rows_padded() {
        // 10×2: row 0 = 1000000001 → bytes 0x80 0x40; row 1 = 0100000000 → 0x40 0x00.
        let mut bytes = b"P4\n10 2\n".to_vec();
        bytes.extend_from_slice(&[0x80, 0x40, 0x40, 0x00]);
        let img = BinaryImage::from_pbm(&bytes).unwrap();
        let on: Vec<_> = img.on_pixels().collect();
        assert_eq!(on, vec![(0, 0), (9, 0), (1, 1)]);
    }

    #[test]
    fn malformed_pbm_are_typed_errors() {
        assert!(matches!(
            BinaryImage::from_pbm(b"P2 1 1 0"),
            Err(PbmError::BadMagic { .. })
        ));
        assert!(matches!(
            BinaryImage::from_pbm(b"P1 x 1"),
            Err(PbmError::BadHeader { field: "width", .. })
        ));
        assert!(matches!(
            BinaryImage::from_pbm(b"P1 0 1"),
            Err(PbmError::BadSize { .. })
        ));
        assert!(matches!(
            BinaryImage::from_pbm(b"P1 99999999999 99999999999"),
            Err(PbmError::BadSize { .. })
        ));
        assert_eq!(
            BinaryImage::from_pbm(b"P1 2 2 1 0 1"),
            Err(PbmError::Truncated {
                expected: 4,
                found: 3
            })
        );
        assert!(matches!(
            BinaryImage::from_pbm(b"P1 1 1 7"),
            Err(PbmError::BadPixel { byte: b'7', .. })
        ));
        assert!(matches!(
            BinaryImage::from_pbm(b"P4 16 2\n\x00"),
            Err(PbmError::Truncated { .. })
        ));
        assert!(matches!(
            BinaryImage::from_pbm(b""),
            Err(PbmError::BadMagic { .. })
        ));
    }
}
