//! One line of a text input, read with a bound on its length: the percept-stream reader and the
//! CARMEN and MRCLAM log readers hold at most [`MAX_LINE`] bytes of a line, so a file with no
//! line breaks (or one hostile line) costs bounded memory; an overlong line is drained in
//! bounded pieces and reported, never held.
//!
//! # Complexity
//!
//! O(length of the line) time, O(min(length, [`MAX_LINE`])) memory.

use std::io::{BufRead, Read};

/// The longest line any reader holds, in bytes (line ending included).
pub const MAX_LINE: usize = 1 << 20;

/// What [`read_bounded`] read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineRead {
    /// The input has ended; nothing was read.
    End,
    /// A line is in the buffer (with its line ending, if it had one); `bytes` were consumed.
    Line {
        /// Bytes consumed from the input.
        bytes: usize,
    },
    /// A line longer than [`MAX_LINE`] was consumed and dropped (the buffer is empty).
    TooLong {
        /// Bytes consumed from the input.
        bytes: usize,
    },
}

/// Reads one line of `input` into `buf` (cleared first), holding at most [`MAX_LINE`] bytes.
///
/// # Errors
/// The input's own read errors.
pub fn read_bounded(input: &mut impl BufRead, buf: &mut Vec<u8>) -> std::io::Result<LineRead> {
    buf.clear();
    let n = input.take(MAX_LINE as u64 + 1).read_until(b'\n', buf)?;
    if n == 0 {
        return Ok(LineRead::End);
    }
    if buf.len() <= MAX_LINE || buf.last() == Some(&b'\n') {
        return Ok(LineRead::Line { bytes: n });
    }
    let mut bytes = n;
    loop {
        buf.clear();
        let m = input.take(MAX_LINE as u64).read_until(b'\n', buf)?;
        bytes += m;
        if m == 0 || buf.last() == Some(&b'\n') {
            break;
        }
    }
    buf.clear();
    Ok(LineRead::TooLong { bytes })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(text: &[u8]) -> Vec<(LineRead, Vec<u8>)> {
        let mut input = text;
        let mut buf = Vec::new();
        let mut out = Vec::new();
        loop {
            let r = read_bounded(&mut input, &mut buf).expect("reading memory");
            if r == LineRead::End {
                return out;
            }
            out.push((r, buf.clone()));
        }
    }

    #[test]
    fn lines_up_to_the_bound_are_kept_and_longer_ones_dropped_whole() {
        let exact = vec![b'x'; MAX_LINE - 1];
        let long = vec![b'y'; 3 * MAX_LINE + 5];
        let mut text = b"a\n".to_vec();
        text.extend_from_slice(&exact);
        text.push(b'\n');
        text.extend_from_slice(&long);
        text.extend_from_slice(b"\nb");
        let got = all(&text);
        assert_eq!(got.len(), 4);
        assert_eq!(got[0], (LineRead::Line { bytes: 2 }, b"a\n".to_vec()));
        assert_eq!(got[1].0, LineRead::Line { bytes: MAX_LINE });
        assert_eq!(got[1].1.len(), MAX_LINE);
        // The long line and its newline are consumed, nothing of it kept.
        assert_eq!(
            got[2],
            (
                LineRead::TooLong {
                    bytes: long.len() + 1
                },
                Vec::new()
            )
        );
        // The last line has no line ending.
        assert_eq!(got[3], (LineRead::Line { bytes: 1 }, b"b".to_vec()));
    }

    #[test]
    fn a_line_one_byte_over_without_ending_is_too_long() {
        let text = vec![b'z'; MAX_LINE + 1];
        let got = all(&text);
        assert_eq!(
            got,
            vec![(
                LineRead::TooLong {
                    bytes: MAX_LINE + 1
                },
                Vec::new()
            )]
        );
    }
}
