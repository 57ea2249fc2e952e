//! The fast path of the JSON Lines reader: a hand-written scanner for exactly the documented
//! record shape that writes a clean record straight into the engine's [`Frame`] and the
//! [`FrameMeta`], borrowing every string from the line (no copies, no allocation).
//!
//! It is deliberately partial. It accepts a record only when it can prove the serde path in
//! [`crate::io::stream`] would accept the same record with the same numbers; on anything else —
//! a string escape, an unknown or repeated key, a number it cannot convert exactly as serde_json
//! does, `"NaN"` strings, an undeclared percept, a degree out of range, a duplicate percept, a
//! version other than 1, an unknown truth place, malformed JSON — it answers "not mine" and the
//! caller re-reads the line with the serde path. Every rejection message, rejection rule and line
//! number therefore comes from one place, and this module only has to be right about the
//! records it accepts. The time and odometry checks that follow parsing are shared by both
//! paths. `tests/stream_fastpath.rs` checks the agreement on random and hostile lines.

use crate::engine::Frame;
use crate::io::record::{Odometry, FORMAT_VERSION};
use crate::io::stream::{FrameMeta, Schema, Scratch};

/// Most arguments a percept may have on the fast path (held on the stack); more falls back.
const MAX_ARGS: usize = 8;

/// Largest significand converted here: below 2^53 every integer is an exact `f64`, so one
/// multiplication or division by an exact power of ten (10^0..10^22 are exact) is correctly
/// rounded — the very operation serde_json performs, and the correctly rounded result its
/// `float_roundtrip` mode would give.
const MAX_SIGNIFICAND: u64 = 1 << 53;

/// 10^0 ..= 10^22, the powers of ten an `f64` holds exactly.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// A key of at most eight bytes packed into a word, so that matching a key is one integer
/// compare rather than a string compare per candidate. Keys cannot contain NUL (control
/// characters send the line to serde), so the zero padding makes the packing one-to-one; a
/// longer key packs to 0, which is no known key.
const fn word(k: &[u8]) -> u64 {
    if k.len() > 8 {
        return 0;
    }
    let mut w = 0u64;
    let mut i = 0;
    while i < k.len() {
        w |= (k[i] as u64) << (8 * i);
        i += 1;
    }
    w
}

const K_VERSION: u64 = word(b"version");
const K_T: u64 = word(b"t");
const K_ODOMETRY: u64 = word(b"odometry");
const K_HEADING: u64 = word(b"heading");
const K_PERCEPTS: u64 = word(b"percepts");
const K_TRUTH: u64 = word(b"truth");
const K_REGION: u64 = word(b"region");
const K_DX: u64 = word(b"dx");
const K_DY: u64 = word(b"dy");
const K_DTHETA: u64 = word(b"dtheta");
const K_NAME: u64 = word(b"name");
const K_ARGS: u64 = word(b"args");
const K_VALUE: u64 = word(b"value");
const K_DEGREE: u64 = word(b"degree");
const K_PLACE: u64 = word(b"place");
const K_POSE: u64 = word(b"pose");

/// Scans `line` (one JSON record, line ending removed) into `frame` and `meta`, which the caller
/// has reset (`frame` cleared, `meta` defaulted with its line number, `scratch` begun).
///
/// `true`: the record is well formed and every percept usable; `frame` and `meta` hold exactly
/// what the serde path would have produced. `false`: not handled here; `frame`, `meta` and
/// `scratch` may be partly written and must be reset before the serde path reads the line.
pub(crate) fn scan_record(
    line: &[u8],
    schema: &Schema,
    scratch: &mut Scratch,
    frame: &mut Frame,
    meta: &mut FrameMeta,
) -> bool {
    let mut cur = Cursor { b: line, i: 0 };
    record(&mut cur, schema, scratch, frame, meta).is_some() && cur.at_end()
}

/// A read position in the line. Every method returns `None` for "not handled here".
struct Cursor<'a> {
    b: &'a [u8],
    i: usize,
}

impl<'a> Cursor<'a> {
    /// Skips JSON whitespace (the four bytes serde_json skips).
    #[inline]
    fn ws(&mut self) {
        while let Some(b' ' | b'\t' | b'\n' | b'\r') = self.b.get(self.i) {
            self.i += 1;
        }
    }

    /// The next non-whitespace byte, not consumed.
    #[inline]
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.b.get(self.i).copied()
    }

    /// Consumes `c` after optional whitespace.
    #[inline]
    fn eat(&mut self, c: u8) -> Option<()> {
        (self.peek()? == c).then(|| self.i += 1)
    }

    /// True when only whitespace is left.
    fn at_end(&mut self) -> bool {
        self.ws();
        self.i == self.b.len()
    }

    /// Consumes `null` if it comes next; `false` (nothing consumed) otherwise.
    #[inline]
    fn null(&mut self) -> bool {
        self.ws();
        let hit = self.b.get(self.i..self.i + 4) == Some(b"null");
        if hit {
            self.i += 4;
        }
        hit
    }

    /// A string without escapes or control characters, borrowed from the line as raw bytes:
    /// they are only ever compared with valid names, and bytes equal to a valid name are valid
    /// UTF-8 themselves (a string that matches nothing goes to serde, which validates it).
    #[inline]
    fn str(&mut self) -> Option<&'a [u8]> {
        self.eat(b'"')?;
        let start = self.i;
        // Eight bytes at a time up to the first quote, backslash or control character, which
        // the byte loop below then judges.
        const LO: u64 = 0x0101_0101_0101_0101;
        const HI: u64 = 0x8080_8080_8080_8080;
        while let Some(chunk) = self.b.get(self.i..self.i + 8) {
            let mut w = [0u8; 8];
            w.copy_from_slice(chunk);
            let w = u64::from_le_bytes(w);
            let (q, bs) = (w ^ (LO * u64::from(b'"')), w ^ (LO * u64::from(b'\\')));
            // Per test, the lowest flagged byte is exact (false flags only sit above a true
            // one), so the lowest flag of the union is the first special byte.
            let hits = (q.wrapping_sub(LO) & !q)
                | (bs.wrapping_sub(LO) & !bs)
                | (w.wrapping_sub(LO * 0x20) & !w);
            let hits = hits & HI;
            if hits != 0 {
                self.i += (hits.trailing_zeros() / 8) as usize;
                break;
            }
            self.i += 8;
        }
        loop {
            match *self.b.get(self.i)? {
                b'"' => break,
                // Escapes need decoding and control characters are errors: serde's business.
                b'\\' | 0..=0x1f => return None,
                _ => self.i += 1,
            }
        }
        let s = &self.b[start..self.i];
        self.i += 1;
        Some(s)
    }

    /// An object key followed by its colon.
    #[inline]
    fn key(&mut self) -> Option<&'a [u8]> {
        let k = self.str()?;
        self.eat(b':')?;
        Some(k)
    }

    /// After a member or element: `true` if another follows (comma consumed), `false` if `close`
    /// ended the container (consumed).
    #[inline]
    fn more(&mut self, close: u8) -> Option<bool> {
        match self.peek()? {
            b',' => {
                self.i += 1;
                Some(true)
            }
            c if c == close => {
                self.i += 1;
                Some(false)
            }
            _ => None,
        }
    }

    /// Opens a container; `Some(false)` when it is empty (and already closed).
    #[inline]
    fn open(&mut self, open: u8, close: u8) -> Option<bool> {
        self.eat(open)?;
        if self.peek()? == close {
            self.i += 1;
            return Some(false);
        }
        Some(true)
    }

    /// A JSON number, converted exactly as serde_json converts it — only in the range where
    /// that conversion is one exact-operand operation (see [`MAX_SIGNIFICAND`]).
    fn num(&mut self) -> Option<f64> {
        self.ws();
        let b = self.b;
        let mut i = self.i;
        let neg = b.get(i) == Some(&b'-');
        if neg {
            i += 1;
        }
        let mut sig: u64 = 0;
        let mut exp: i32 = 0;
        match b.get(i) {
            Some(b'0') => {
                i += 1;
                // A leading zero followed by a digit is not JSON.
                if matches!(b.get(i), Some(b'0'..=b'9')) {
                    return None;
                }
            }
            Some(b'1'..=b'9') => {
                while let Some(&c @ b'0'..=b'9') = b.get(i) {
                    sig = sig * 10 + u64::from(c - b'0');
                    if sig > MAX_SIGNIFICAND {
                        return None;
                    }
                    i += 1;
                }
            }
            _ => return None,
        }
        if b.get(i) == Some(&b'.') {
            i += 1;
            let start = i;
            while let Some(&c @ b'0'..=b'9') = b.get(i) {
                sig = sig * 10 + u64::from(c - b'0');
                if sig > MAX_SIGNIFICAND {
                    return None;
                }
                exp -= 1;
                i += 1;
            }
            if i == start {
                return None;
            }
        }
        if let Some(b'e' | b'E') = b.get(i) {
            i += 1;
            let eneg = match b.get(i) {
                Some(b'-') => {
                    i += 1;
                    true
                }
                Some(b'+') => {
                    i += 1;
                    false
                }
                _ => false,
            };
            let start = i;
            let mut e: i32 = 0;
            while let Some(&c @ b'0'..=b'9') = b.get(i) {
                e = e * 10 + i32::from(c - b'0');
                if e > 1000 {
                    return None;
                }
                i += 1;
            }
            if i == start {
                return None;
            }
            exp += if eneg { -e } else { e };
        }
        let pow = *POW10.get(exp.unsigned_abs() as usize)?;
        let f = sig as f64;
        let f = if exp >= 0 { f * pow } else { f / pow };
        self.i = i;
        Some(if neg { -f } else { f })
    }

    /// A number or `null` (`None`).
    #[inline]
    fn opt_num(&mut self) -> Option<Option<f64>> {
        if self.null() {
            return Some(None);
        }
        self.num().map(Some)
    }
}

/// Marks key bit `bit` in `seen`; `None` if the key was already given (serde's last-wins or
/// duplicate-field rules are left to serde).
#[inline]
fn once(seen: &mut u8, bit: u8) -> Option<()> {
    if *seen & bit != 0 {
        return None;
    }
    *seen |= bit;
    Some(())
}

fn record(
    cur: &mut Cursor<'_>,
    schema: &Schema,
    scratch: &mut Scratch,
    frame: &mut Frame,
    meta: &mut FrameMeta,
) -> Option<()> {
    if !cur.open(b'{', b'}')? {
        return None; // `percepts` is required
    }
    let mut seen = 0u8;
    loop {
        match word(cur.key()?) {
            K_VERSION => {
                once(&mut seen, 1)?;
                version(cur)?;
            }
            K_T => {
                once(&mut seen, 2)?;
                meta.t = cur.opt_num()?;
            }
            K_ODOMETRY => {
                once(&mut seen, 4)?;
                meta.odometry = odometry(cur)?;
            }
            K_HEADING => {
                once(&mut seen, 32)?;
                meta.heading = cur.opt_num()?;
            }
            K_PERCEPTS => {
                once(&mut seen, 8)?;
                percepts(cur, schema, scratch, frame)?;
            }
            K_TRUTH => {
                once(&mut seen, 16)?;
                truth(cur, schema, meta)?;
            }
            K_REGION => {
                // An unknown name is the serde path's to reject with its reason.
                once(&mut seen, 64)?;
                meta.region = Some(schema.region(cur.str()?)?);
            }
            _ => return None,
        }
        if !cur.more(b'}')? {
            break;
        }
    }
    (seen & 8 != 0).then_some(())
}

/// `version`: an unsigned integer equal to [`FORMAT_VERSION`] (anything else is serde's to
/// reject or report).
fn version(cur: &mut Cursor<'_>) -> Option<()> {
    cur.ws();
    let start = cur.i;
    let mut v: u64 = 0;
    while let Some(&c @ b'0'..=b'9') = cur.b.get(cur.i) {
        v = v.checked_mul(10)?.checked_add(u64::from(c - b'0'))?;
        cur.i += 1;
    }
    let digits = cur.i - start;
    // No digits, or a leading zero, is serde's to report.
    if digits == 0 || (digits > 1 && cur.b[start] == b'0') {
        return None;
    }
    (v == u64::from(FORMAT_VERSION)).then_some(())
}

fn odometry(cur: &mut Cursor<'_>) -> Option<Odometry> {
    let mut o = Odometry::default();
    if cur.null() || !cur.open(b'{', b'}')? {
        return Some(o);
    }
    let mut seen = 0u8;
    loop {
        match word(cur.key()?) {
            K_DX => {
                once(&mut seen, 1)?;
                o.dx = cur.num()?;
            }
            K_DY => {
                once(&mut seen, 2)?;
                o.dy = cur.num()?;
            }
            K_DTHETA => {
                once(&mut seen, 4)?;
                o.dtheta = cur.num()?;
            }
            _ => return None,
        }
        if !cur.more(b'}')? {
            return Some(o);
        }
    }
}

fn percepts(
    cur: &mut Cursor<'_>,
    schema: &Schema,
    scratch: &mut Scratch,
    frame: &mut Frame,
) -> Option<()> {
    if !cur.open(b'[', b']')? {
        return Some(());
    }
    loop {
        percept(cur, schema, scratch, frame)?;
        if !cur.more(b']')? {
            return Some(());
        }
    }
}

fn percept(
    cur: &mut Cursor<'_>,
    schema: &Schema,
    scratch: &mut Scratch,
    frame: &mut Frame,
) -> Option<()> {
    if !cur.open(b'{', b'}')? {
        return None; // `name` and `degree` are required
    }
    let mut name = None;
    let mut args: [&[u8]; MAX_ARGS] = [&[]; MAX_ARGS];
    let mut nargs = 0;
    let mut value = None;
    let mut degree = None;
    let mut seen = 0u8;
    loop {
        match word(cur.key()?) {
            K_NAME => {
                once(&mut seen, 1)?;
                name = Some(cur.str()?);
            }
            K_ARGS => {
                once(&mut seen, 2)?;
                if cur.open(b'[', b']')? {
                    loop {
                        *args.get_mut(nargs)? = cur.str()?;
                        nargs += 1;
                        if !cur.more(b']')? {
                            break;
                        }
                    }
                }
            }
            K_VALUE => {
                once(&mut seen, 4)?;
                value = cur.opt_num()?;
            }
            K_DEGREE => {
                once(&mut seen, 8)?;
                degree = Some(cur.num()?);
            }
            _ => return None,
        }
        if !cur.more(b'}')? {
            break;
        }
    }
    let (name, degree) = (name?, degree?);
    let slot = schema.lookup_bytes(name, &args[..nargs])?;
    // Numbers read here are finite, so only the range and duplicate checks remain; a failure
    // of either is a rejection, which the serde path words.
    if !(0.0..=1.0).contains(&degree) || !scratch.mark(slot) {
        return None;
    }
    frame.set(slot, degree, value);
    Some(())
}

fn truth(cur: &mut Cursor<'_>, schema: &Schema, meta: &mut FrameMeta) -> Option<()> {
    if cur.null() {
        return Some(());
    }
    meta.truth_known = true;
    if !cur.open(b'{', b'}')? {
        return Some(());
    }
    let mut seen = 0u8;
    loop {
        match word(cur.key()?) {
            K_PLACE => {
                once(&mut seen, 1)?;
                meta.truth_place = if cur.null() {
                    None
                } else {
                    Some(schema.place_bytes(cur.str()?)?)
                };
            }
            K_POSE => {
                once(&mut seen, 2)?;
                meta.truth_pose = if cur.null() {
                    None
                } else {
                    cur.eat(b'[')?;
                    let x = cur.num()?;
                    cur.eat(b',')?;
                    let y = cur.num()?;
                    cur.eat(b',')?;
                    let th = cur.num()?;
                    cur.eat(b']')?;
                    Some([x, y, th])
                };
            }
            _ => return None,
        }
        if !cur.more(b'}')? {
            return Some(());
        }
    }
}
