//! Percept streams: a log of frames read one line at a time, straight into the engine's dense
//! [`Frame`], with every bad record turned into a typed [`Rejection`] carrying its line number.
//!
//! Two wire forms carry the same content (see `docs/streams.md` for the schema):
//! - **JSON Lines** — one [`crate::io::record::FrameRecord`] object per line;
//! - **CSV** — a header naming the columns, then one frame per row (see [`crate::io::csv`]).
//!
//! The reader ([`StreamReader`]) pulls lines from a caller-supplied [`BufRead`]: it never holds
//! more than one line, reuses its line buffer, name buffers and the caller's frame, and looks
//! percept names up in a [`Schema`] built once. A JSON line is first tried by a hand-written
//! scanner for exactly the documented record shape (`io::fast_record`), which borrows its strings
//! from the line and writes straight into the frame; whatever it does not vouch for (escapes,
//! unknown keys, unusual numbers, anything to reject) is read again by a hand-written serde seed
//! that writes each percept into its slot as it is parsed and words every rejection. Either way
//! the steady state allocates nothing per frame (only a rejected record allocates, to describe
//! itself), and both paths give the same frame or the same rejection.
//!
//! # What is rejected (each reported, counted; the whole record is skipped)
//! A line that is not a record of the right shape, a format version other than
//! [`FORMAT_VERSION`], a percept the rule file does not declare, a NaN (JSON has no NaN, so the
//! strings `"NaN"`/`"nan"` are read as NaN in order to *report* them; CSV `nan` likewise), a degree
//! outside `[0, 1]`, an infinite value, a percept given twice, a key the format does not define or
//! a key given twice (in the record, a percept, the truth or the odometry: a misspelt
//! `odometri` must not silently drop the odometry), a time earlier than the previous
//! accepted record's, non-finite odometry, an unknown truth place, and lines longer than
//! [`MAX_LINE`]. A skipped record contributes nothing — not even its odometry. Blank lines are
//! ignored (they are not records).
//!
//! # Reading ahead
//! [`read_records`] hands every record, in stream order, to a consumer. With
//! [`Threads::ReadAhead`] the reading and parsing run on a second thread, a few batches of frames
//! ahead of the consumer: the batches are allocated once and passed back and forth through two
//! bounded channels, so memory stays flat, and the consumer sees exactly the sequence it would
//! see reading itself ([`Threads::One`]) — the same frames, rejections and line numbers, and a
//! read error only after every record before it.
//!
//! Depends on `engine::frame` (the target), `io::record` (the wire types), `map` (truth place
//! names) and serde/serde_json; nothing here does I/O beyond reading the given `BufRead`.

use super::line::{read_bounded, LineRead};
use crate::engine::frame::InstanceIndex;
use crate::engine::{Frame, PerceptInstance, PerceptSlot, PerceptTable};
use crate::io::csv::CsvLayout;
use crate::io::fast_record;
use crate::io::record::{Odometry, FORMAT_VERSION};
pub use crate::io::time_order::TimePolicy;
use crate::io::time_order::{judge, TimeVerdict};
use crate::map::Map;
use serde::de::{self, DeserializeSeed, IgnoredAny, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use std::fmt;
use std::io::BufRead;
use std::sync::mpsc;

/// Longest line accepted, in bytes; a longer line is rejected (and skipped) without being held in
/// memory, so that memory stays flat on any input.
pub use super::line::MAX_LINE;

/// The wire form of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StreamFormat {
    /// One JSON record per line.
    JsonLines,
    /// A header row, then one frame per row.
    Csv,
}

impl StreamFormat {
    /// The form a path's extension suggests: `.csv` is CSV, anything else JSON Lines.
    pub fn from_path(path: &std::path::Path) -> StreamFormat {
        match path.extension().and_then(|e| e.to_str()) {
            Some(e) if e.eq_ignore_ascii_case("csv") => StreamFormat::Csv,
            _ => StreamFormat::JsonLines,
        }
    }
}

/// Names a stream may use, resolved once: percept instances to slots (through a hash index that
/// takes borrowed strings), truth places to indices.
#[derive(Debug, Clone)]
pub struct Schema {
    instances: Vec<PerceptInstance>,
    index: InstanceIndex,
    places: Vec<String>,
    slots: usize,
    /// Names a record's `region` field may take (see [`Schema::with_regions`]).
    regions: Vec<String>,
}

impl Schema {
    /// The schema of an engine's percept table and map.
    pub fn new(table: &PerceptTable, map: &Map) -> Schema {
        let places = map.places().iter().map(|p| p.name.clone()).collect();
        Schema::from_parts(table, places)
    }

    /// The schema of a percept table and a list of place names.
    pub fn from_parts(table: &PerceptTable, places: Vec<String>) -> Schema {
        Schema {
            instances: table.instances().to_vec(),
            index: table.lookup().clone(),
            places,
            slots: table.len(),
            regions: Vec::new(),
        }
    }

    /// The schema of a list of percept instances (slots in list order) and place names, for a
    /// stream read without a rule file (the landmark readings of `lplace grid`).
    pub fn from_instances(instances: Vec<PerceptInstance>, places: Vec<String>) -> Schema {
        let index = InstanceIndex::new(&instances);
        Schema {
            slots: instances.len(),
            instances,
            index,
            places,
            regions: Vec::new(),
        }
    }

    /// The percept instance in `slot`.
    pub fn instance(&self, slot: PerceptSlot) -> Option<&PerceptInstance> {
        self.instances.get(slot.0 as usize)
    }

    /// The same schema, accepting these names in a record's `region` field (the region known
    /// from outside that the engine conditions on; `engine::query::set_names` lists an
    /// engine's). Without it every `region` field is rejected as unknown.
    pub fn with_regions(mut self, names: Vec<String>) -> Schema {
        self.regions = names;
        self
    }

    /// Index of a `region` name (into the names given to [`Schema::with_regions`]).
    pub fn region(&self, name: &[u8]) -> Option<u32> {
        let i = self.regions.iter().position(|r| r.as_bytes() == name)?;
        u32::try_from(i).ok()
    }

    /// The `region` name of an index [`Schema::region`] gave.
    pub fn region_name(&self, index: u32) -> Option<&str> {
        self.regions.get(index as usize).map(String::as_str)
    }

    /// The slot of `name(args…)`; `None` when not declared.
    pub fn lookup<S: AsRef<str>>(&self, name: &str, args: &[S]) -> Option<PerceptSlot> {
        // The index compares bytes; up to eight arguments are viewed as such on the stack, more
        // (no rule file has them) take an allocation rather than a limit.
        let mut bytes: [&[u8]; 8] = [&[]; 8];
        match bytes.get_mut(..args.len()) {
            Some(b) => {
                for (b, a) in b.iter_mut().zip(args) {
                    *b = a.as_ref().as_bytes();
                }
                self.index.get(&self.instances, name.as_bytes(), b)
            }
            None => {
                let owned: Vec<&[u8]> = args.iter().map(|a| a.as_ref().as_bytes()).collect();
                self.index.get(&self.instances, name.as_bytes(), &owned)
            }
        }
    }

    /// [`Schema::lookup`] on raw bytes (not yet validated as UTF-8), for the fast JSON path.
    pub(crate) fn lookup_bytes(&self, name: &[u8], args: &[&[u8]]) -> Option<PerceptSlot> {
        self.index.get(&self.instances, name, args)
    }

    /// [`Schema::place`] on raw bytes, for the fast JSON path.
    pub(crate) fn place_bytes(&self, name: &[u8]) -> Option<usize> {
        self.places.iter().position(|p| p.as_bytes() == name)
    }

    /// Index of the place called `name`.
    pub fn place(&self, name: &str) -> Option<usize> {
        self.places.iter().position(|p| p == name)
    }

    /// Place names in id order.
    pub fn places(&self) -> &[String] {
        &self.places
    }

    /// Number of percept slots a frame needs.
    pub fn slots(&self) -> usize {
        self.slots
    }
}

/// What a record carries besides its percepts.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameMeta {
    /// 1-based line number of the record.
    pub line: u64,
    /// Time in seconds, if given.
    pub t: Option<f64>,
    /// Odometry increment (zero when absent).
    pub odometry: Odometry,
    /// Heading in the map frame, degrees, if given.
    pub heading: Option<f64>,
    /// True when the record carries a `truth` object.
    pub truth_known: bool,
    /// The true place (`None` between places or when unknown).
    pub truth_place: Option<usize>,
    /// The true pose `[x, y, θ°]`, if given.
    pub truth_pose: Option<[f64; 3]>,
    /// The region known from outside (`"region": "R0"`), as an index into the schema's region
    /// names.
    pub region: Option<u32>,
    /// Set when this record restarts the clock ([`TimePolicy::Restart`]): the previous
    /// accepted time, for the note a reader of concatenated logs reports.
    pub restart: Option<f64>,
}

impl FrameMeta {
    /// The note to report when this record restarts the clock.
    pub fn restart_note(&self) -> Option<TimeRestart> {
        Some(TimeRestart {
            line: self.line,
            t: self.t?,
            previous: self.restart?,
        })
    }
}

/// A record where the clock starts again ([`TimePolicy::Restart`]): accepted, and reported.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeRestart {
    /// 1-based line number.
    pub line: u64,
    /// The record's time.
    pub t: f64,
    /// The previous accepted time.
    pub previous: f64,
}

impl fmt::Display for TimeRestart {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: note: time starts again at t = {} after t = {} (--time restart)",
            self.line, self.t, self.previous
        )
    }
}

/// Why a record was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Rejection {
    /// Not a record of the right shape (JSON syntax, wrong types, missing fields, CSV row width).
    #[error("column {column}: {message}")]
    Malformed {
        /// 1-based column (byte) where the problem was found.
        column: usize,
        /// What is wrong, in this program's words (no position: that is `column`).
        message: String,
    },
    /// Longer than [`MAX_LINE`].
    #[error("line longer than {MAX_LINE} bytes")]
    TooLong,
    /// A format version this build does not read.
    #[error("unsupported format version {found} (this build reads {FORMAT_VERSION})")]
    Version {
        /// The version found.
        found: u64,
    },
    /// A percept instance the rule file does not declare.
    #[error("unknown percept `{instance}`")]
    UnknownPercept {
        /// `name(args…)` as written.
        instance: String,
    },
    /// A NaN degree, value, time or odometry component.
    #[error("{field} is NaN")]
    Nan {
        /// What was NaN (`degree of sonar_wall(North)`, `t`, `odometry`…).
        field: String,
    },
    /// A degree outside `[0, 1]`.
    #[error("percept `{instance}`: degree {degree} is outside [0, 1]")]
    DegreeRange {
        /// The percept instance.
        instance: String,
        /// The degree found.
        degree: f64,
    },
    /// An infinite value, time or odometry component.
    #[error("{field} is not finite ({value})")]
    Infinite {
        /// What was infinite.
        field: String,
        /// The value.
        value: f64,
    },
    /// The same percept instance twice in one record.
    #[error("percept `{instance}` given twice")]
    Duplicate {
        /// The percept instance.
        instance: String,
    },
    /// A key the format does not define (a misspelling such as `odometri` would otherwise drop
    /// its value silently).
    #[error("unknown key `{key}` in {within}")]
    UnknownKey {
        /// The key as written.
        key: String,
        /// `record`, `percept` or `truth`.
        within: &'static str,
    },
    /// A key given twice in one object (which one counts would be a guess).
    #[error("key `{key}` given twice in {within}")]
    DuplicateKey {
        /// The key.
        key: String,
        /// `record`, `percept` or `truth`.
        within: &'static str,
    },
    /// A time earlier than the previous accepted record's.
    #[error("time goes backwards: t = {t} after t = {previous}")]
    TimeBackwards {
        /// This record's time.
        t: f64,
        /// The previous accepted record's time.
        previous: f64,
    },
    /// A time later than the next record's, which itself follows the previous accepted time:
    /// this one time is out of place (a corrupt timestamp), judged by both neighbours
    /// ([`crate::io::time_order`]).
    #[error(
        "time t = {t} is out of place: the next record's t = {next} follows the records before"
    )]
    TimeOutlier {
        /// This record's time.
        t: f64,
        /// The next record's time.
        next: f64,
    },
    /// A truth place the map does not have.
    #[error("unknown truth place `{name}`")]
    UnknownTruthPlace {
        /// The name written.
        name: String,
    },
    /// A `region` that is no place, room, region or kind of the map and rules.
    #[error("unknown region `{name}`")]
    UnknownRegion {
        /// The name written.
        name: String,
    },
    /// Problems of the CSV header, each naming its column. Unknown columns are ignored (their
    /// cells unread); a repeated column, or a first line that names no column at all (a missing
    /// header), leaves the stream unreadable ([`Rejection::NoCsvHeader`] on every row).
    #[error("CSV header: {}", crate::io::csv::HeaderProblem::list(problems))]
    CsvHeader {
        /// What is wrong, column by column.
        problems: Vec<crate::io::csv::HeaderProblem>,
    },
    /// A CSV row after a header that could not be used.
    #[error("not read: the CSV header on line 1 is unusable")]
    NoCsvHeader,
}

impl Rejection {
    /// The 1-based column (byte) the problem was found at, when it has one.
    pub fn column(&self) -> Option<usize> {
        match self {
            Rejection::Malformed { column, .. } => Some(*column),
            _ => None,
        }
    }

    /// What is wrong without its position (the column is [`Rejection::column`]), so that a
    /// front end can print `FILE:LINE:COLUMN: what` as the command line does.
    pub fn message(&self) -> String {
        match self {
            Rejection::Malformed { message, .. } => message.clone(),
            reason => reason.to_string(),
        }
    }

    /// A short, stable name of the kind of problem, for counting in summaries.
    pub fn kind(&self) -> &'static str {
        match self {
            Rejection::Malformed { .. } | Rejection::TooLong => "malformed",
            Rejection::Version { .. } => "version",
            Rejection::UnknownPercept { .. } => "unknown_percept",
            Rejection::Nan { .. } => "nan",
            Rejection::DegreeRange { .. } => "degree_out_of_range",
            Rejection::Infinite { .. } => "not_finite",
            Rejection::Duplicate { .. } => "duplicate_percept",
            Rejection::UnknownKey { .. } => "unknown_key",
            Rejection::DuplicateKey { .. } => "duplicate_key",
            Rejection::TimeBackwards { .. } => "time_backwards",
            Rejection::TimeOutlier { .. } => "time_outlier",
            Rejection::UnknownTruthPlace { .. } => "unknown_truth_place",
            Rejection::UnknownRegion { .. } => "unknown_region",
            Rejection::CsvHeader { .. } => "csv_header",
            Rejection::NoCsvHeader => "no_csv_header",
        }
    }
}

/// A rejected record: its 1-based line number and why. Displayed as `LINE: reason`, or
/// `LINE:COLUMN: what` when the problem has a column (one position, as editors read it).
#[derive(Debug, Clone, PartialEq)]
pub struct LineError {
    /// 1-based line number.
    pub line: u64,
    /// Why it was rejected.
    pub reason: Rejection,
}

impl fmt::Display for LineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.reason.column() {
            Some(column) => write!(f, "{}:{column}: {}", self.line, self.reason.message()),
            None => write!(f, "{}: {}", self.line, self.reason),
        }
    }
}

impl std::error::Error for LineError {}

/// What [`StreamReader::next_frame`] produced.
#[derive(Debug, Clone, PartialEq)]
pub enum ReadOutcome {
    /// The frame and its meta data were filled.
    Frame,
    /// A record was rejected and skipped.
    Rejected(LineError),
    /// The stream has ended.
    End,
}

/// Buffers reused from record to record.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    name: String,
    /// The key being read (serde path).
    key: String,
    args: Vec<String>,
    nargs: usize,
    /// `seen[slot] == stamp` when the slot was set in the current record.
    seen: Vec<u32>,
    stamp: u32,
    /// The cells of a CSV row.
    pub(crate) cells: crate::io::csv::Cells,
    /// The slots set in the current record, in the record's order (a frame is dense and keeps
    /// no order; a consumer pairing readings in the order they were written needs it).
    order: Vec<PerceptSlot>,
}

impl Scratch {
    /// Starts a new record: forget which slots were set, without touching every entry.
    pub(crate) fn begin(&mut self, slots: usize) {
        self.order.clear();
        if self.seen.len() != slots {
            self.seen = vec![0; slots];
            self.stamp = 0;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.seen.fill(0);
            self.stamp = 1;
        }
    }

    /// Marks `slot` set; false if it already was in this record.
    pub(crate) fn mark(&mut self, slot: PerceptSlot) -> bool {
        match self.seen.get_mut(slot.0 as usize) {
            Some(s) if *s == self.stamp => false,
            Some(s) => {
                *s = self.stamp;
                self.order.push(slot);
                true
            }
            None => true,
        }
    }
}

/// Renders `name(args…)` for a message (only on the rejection path).
pub(crate) fn instance_name<S: AsRef<str>>(name: &str, args: &[S]) -> String {
    if args.is_empty() {
        name.to_string()
    } else {
        let args: Vec<&str> = args.iter().map(AsRef::as_ref).collect();
        format!("{name}({})", args.join(", "))
    }
}

/// Checks one percept and writes it into `frame`; the first problem is kept in `problem`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn put_percept<S: AsRef<str>>(
    schema: &Schema,
    scratch_seen: &mut Scratch,
    frame: &mut Frame,
    problem: &mut Option<Rejection>,
    name: &str,
    args: &[S],
    degree: f64,
    value: Option<f64>,
) {
    if problem.is_some() {
        return;
    }
    let Some(slot) = schema.lookup(name, args) else {
        *problem = Some(Rejection::UnknownPercept {
            instance: instance_name(name, args),
        });
        return;
    };
    let bad = if degree.is_nan() {
        Some(Rejection::Nan {
            field: format!("degree of {}", instance_name(name, args)),
        })
    } else if !(0.0..=1.0).contains(&degree) {
        Some(Rejection::DegreeRange {
            instance: instance_name(name, args),
            degree,
        })
    } else {
        match value {
            Some(v) if v.is_nan() => Some(Rejection::Nan {
                field: format!("value of {}", instance_name(name, args)),
            }),
            Some(v) if v.is_infinite() => Some(Rejection::Infinite {
                field: format!("value of {}", instance_name(name, args)),
                value: v,
            }),
            _ => None,
        }
    };
    if let Some(b) = bad {
        *problem = Some(b);
        return;
    }
    if !scratch_seen.mark(slot) {
        *problem = Some(Rejection::Duplicate {
            instance: instance_name(name, args),
        });
        return;
    }
    frame.set(slot, degree, value);
}

/// Checks that the time, odometry, heading and truth pose of a parsed record are finite (their
/// order in time is judged by the reader, which sees the next record too).
pub(crate) fn check_meta(meta: &FrameMeta) -> Option<Rejection> {
    let finite = |field: &str, v: f64| -> Option<Rejection> {
        if v.is_nan() {
            Some(Rejection::Nan {
                field: field.to_string(),
            })
        } else if v.is_infinite() {
            Some(Rejection::Infinite {
                field: field.to_string(),
                value: v,
            })
        } else {
            None
        }
    };
    if let Some(t) = meta.t {
        if let Some(r) = finite("t", t) {
            return Some(r);
        }
    }
    let o = meta.odometry;
    for (f, v) in [
        ("odometry dx", o.dx),
        ("odometry dy", o.dy),
        ("odometry dtheta", o.dtheta),
    ] {
        if let Some(r) = finite(f, v) {
            return Some(r);
        }
    }
    if let Some(h) = meta.heading {
        if let Some(r) = finite("heading", h) {
            return Some(r);
        }
    }
    if let Some(p) = meta.truth_pose {
        for v in p {
            if let Some(r) = finite("truth pose", v) {
                return Some(r);
            }
        }
    }
    None
}

/// Reads frames from a stream, one line at a time. See the module docs.
#[derive(Debug)]
pub struct StreamReader<R> {
    input: R,
    /// Holds a line only when it is not whole in the input's own buffer (see `next_frame`).
    buf: Vec<u8>,
    line: u64,
    bytes: u64,
    parser: LineParser,
    /// How a time earlier than the previous one is read.
    time: TimePolicy,
    /// The time of the last record handed out.
    last_t: Option<f64>,
    /// A timed record waiting for the next record's time before it is judged.
    held: Held,
    /// The percept order of the last frame handed out.
    out_order: Vec<PerceptSlot>,
    /// Records rejected while a record before them was held: reported after it, so that
    /// everything comes out in stream order.
    deferred: std::collections::VecDeque<LineError>,
}

/// Most rejections deferred behind a held record; past it the held record is judged without
/// its successor, so that a stream of nothing but bad lines keeps memory flat.
const MAX_DEFERRED: usize = 256;

/// The record held back by one (see [`StreamReader::next_frame`]).
#[derive(Debug)]
struct Held {
    frame: Frame,
    meta: FrameMeta,
    order: Vec<PerceptSlot>,
    state: HeldState,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum HeldState {
    /// Nothing held.
    Empty,
    /// A timed record, to be judged when the next record's time is known.
    Judging,
    /// A record without a time (nothing to judge), to be handed out next.
    Ready,
}

/// Everything but the I/O: turns one line into a frame, a rejection, or nothing (blank lines,
/// the CSV header). Kept apart from the input so that a line can be borrowed from the input's
/// buffer while it is parsed.
#[derive(Debug)]
struct LineParser {
    schema: Schema,
    format: StreamFormat,
    csv: Option<CsvLayout>,
    /// CSV header problems still to be reported, in column order (reversed for `pop`).
    pending: Vec<LineError>,
    scratch: Scratch,
    fast: bool,
}

/// Position of the first `\n` in `b`, eight bytes at a time (lines are a few hundred bytes, so
/// this is a measurable part of reading a record).
fn find_newline(b: &[u8]) -> Option<usize> {
    const LO: u64 = 0x0101_0101_0101_0101;
    const HI: u64 = 0x8080_8080_8080_8080;
    const NL: u64 = LO * b'\n' as u64;
    let mut chunks = b.chunks_exact(8);
    let mut off = 0;
    for c in &mut chunks {
        let mut w = [0u8; 8];
        w.copy_from_slice(c);
        let x = u64::from_le_bytes(w) ^ NL;
        // The lowest set bit marks the first zero byte of `x` exactly (borrows only run upwards).
        let z = x.wrapping_sub(LO) & !x & HI;
        if z != 0 {
            return Some(off + (z.trailing_zeros() / 8) as usize);
        }
        off += 8;
    }
    chunks
        .remainder()
        .iter()
        .position(|&c| c == b'\n')
        .map(|p| off + p)
}

impl<R: BufRead> StreamReader<R> {
    /// A reader of `format` over `input`, resolving names with `schema`.
    pub fn new(input: R, schema: Schema, format: StreamFormat) -> Self {
        let slots = schema.slots;
        StreamReader {
            input,
            buf: Vec::with_capacity(1024),
            line: 0,
            bytes: 0,
            time: TimePolicy::Monotone,
            last_t: None,
            held: Held {
                frame: Frame::new(slots),
                meta: FrameMeta::default(),
                order: Vec::new(),
                state: HeldState::Empty,
            },
            out_order: Vec::new(),
            deferred: std::collections::VecDeque::new(),
            parser: LineParser {
                schema,
                format,
                csv: None,
                pending: Vec::new(),
                scratch: Scratch::default(),
                fast: true,
            },
        }
    }

    /// The same reader reading times by `policy` ([`TimePolicy::Monotone`] by default).
    pub fn with_time_policy(mut self, policy: TimePolicy) -> Self {
        self.time = policy;
        self
    }

    /// Turns the JSON fast path on (the default) or off. Off, every JSON line goes through the
    /// serde path; results are the same either way, so this exists for comparisons (tests,
    /// benchmarks), not for users.
    pub fn set_fast_path(&mut self, on: bool) {
        self.parser.fast = on;
    }

    /// The schema names are resolved with.
    pub fn schema(&self) -> &Schema {
        &self.parser.schema
    }

    /// The slots of the last frame read, in the order its record wrote them (a [`Frame`] is
    /// dense and does not keep that order). Meaningful right after [`StreamReader::next_frame`]
    /// returned [`ReadOutcome::Frame`].
    pub fn percept_order(&self) -> &[PerceptSlot] {
        &self.out_order
    }

    /// Bytes consumed so far (for progress bars).
    pub fn bytes_read(&self) -> u64 {
        self.bytes
    }

    /// Lines consumed so far.
    pub fn lines_read(&self) -> u64 {
        self.line
    }

    /// Reads one line into `buf` (without its line ending). `Ok(None)` at the end; `Ok(Some(false))`
    /// for a line longer than [`MAX_LINE`] (skipped, not held).
    fn read_line(&mut self) -> std::io::Result<Option<bool>> {
        let bytes = match read_bounded(&mut self.input, &mut self.buf)? {
            LineRead::End => return Ok(None),
            LineRead::Line { bytes } => bytes,
            LineRead::TooLong { bytes } => {
                self.bytes += bytes as u64;
                self.line += 1;
                return Ok(Some(false));
            }
        };
        self.bytes += bytes as u64;
        self.line += 1;
        while matches!(self.buf.last(), Some(b'\n' | b'\r')) {
            self.buf.pop();
        }
        Ok(Some(true))
    }

    /// Reads the next record into `frame` (it must have [`Schema::slots`] slots) and `meta`.
    /// Blank lines are skipped. I/O errors end the stream with an error.
    ///
    /// A record with a time is handed out only once the next record's time is known (or the
    /// stream has ended), so that its time is judged against both neighbours
    /// ([`crate::io::time_order::judge`]): one corrupt time is the one record rejected.
    /// Records and rejections come out in stream order.
    pub fn next_frame(
        &mut self,
        frame: &mut Frame,
        meta: &mut FrameMeta,
    ) -> std::io::Result<ReadOutcome> {
        loop {
            if let Some(e) = self.deferred.front() {
                if self.held.state == HeldState::Empty || e.line < self.held.meta.line {
                    if let Some(e) = self.deferred.pop_front() {
                        return Ok(ReadOutcome::Rejected(e));
                    }
                }
            }
            if self.held.state == HeldState::Ready {
                self.held.state = HeldState::Empty;
                self.hand_out(frame, meta);
                return Ok(ReadOutcome::Frame);
            }
            let next = match self.next_parsed(frame, meta)? {
                ReadOutcome::Rejected(e) if self.held.state == HeldState::Judging => {
                    self.deferred.push_back(e);
                    if self.deferred.len() < MAX_DEFERRED {
                        continue;
                    }
                    // Too many to hold back: judge the held record without its successor.
                    let verdict = self.judge_held(None);
                    self.hand_out(frame, meta);
                    self.held.state = HeldState::Empty;
                    return Ok(outcome(verdict, meta.line));
                }
                ReadOutcome::Rejected(e) => return Ok(ReadOutcome::Rejected(e)),
                ReadOutcome::End if self.held.state == HeldState::Judging => None,
                ReadOutcome::End => return Ok(ReadOutcome::End),
                ReadOutcome::Frame => Some(meta.t),
            };
            if self.held.state == HeldState::Empty {
                match next {
                    Some(Some(_)) => {
                        self.hold(frame, meta);
                        continue;
                    }
                    _ => {
                        std::mem::swap(&mut self.out_order, &mut self.parser.scratch.order);
                        return Ok(ReadOutcome::Frame);
                    }
                }
            }
            // The held record is judged with the next one's time (`None`: no evidence).
            let verdict = self.judge_held(next.flatten());
            self.hand_out(frame, meta);
            self.held.state = HeldState::Empty;
            if let Some(t) = next {
                // The record just read takes the held place.
                std::mem::swap(&mut self.held.order, &mut self.parser.scratch.order);
                self.held.state = match t {
                    Some(_) => HeldState::Judging,
                    None => HeldState::Ready,
                };
            }
            return Ok(outcome(verdict, meta.line));
        }
    }

    /// Holds the record just read in `frame`/`meta` back until the next record is read.
    fn hold(&mut self, frame: &mut Frame, meta: &mut FrameMeta) {
        std::mem::swap(&mut self.held.frame, frame);
        std::mem::swap(&mut self.held.meta, meta);
        std::mem::swap(&mut self.held.order, &mut self.parser.scratch.order);
        self.held.state = HeldState::Judging;
    }

    /// Swaps the held record into `frame`/`meta` (and the record there into the held place).
    fn hand_out(&mut self, frame: &mut Frame, meta: &mut FrameMeta) {
        std::mem::swap(&mut self.held.frame, frame);
        std::mem::swap(&mut self.held.meta, meta);
        std::mem::swap(&mut self.held.order, &mut self.out_order);
    }

    /// Judges the held record's time given the next record's; `Some` rejects it.
    fn judge_held(&mut self, next: Option<f64>) -> Option<Rejection> {
        let meta = &mut self.held.meta;
        let t = meta.t?;
        match judge(self.last_t, t, next, self.time) {
            TimeVerdict::Keep => {
                self.last_t = Some(t);
                None
            }
            TimeVerdict::Restart { previous } => {
                meta.restart = Some(previous);
                self.last_t = Some(t);
                None
            }
            TimeVerdict::Backwards { previous } => Some(Rejection::TimeBackwards { t, previous }),
            TimeVerdict::Outlier { next } => Some(Rejection::TimeOutlier { t, next }),
        }
    }

    /// Reads and parses the next record, without judging its time.
    fn next_parsed(
        &mut self,
        frame: &mut Frame,
        meta: &mut FrameMeta,
    ) -> std::io::Result<ReadOutcome> {
        loop {
            if let Some(e) = self.parser.pending.pop() {
                return Ok(ReadOutcome::Rejected(e));
            }
            // Zero-copy: a line that lies whole in the input's buffer is parsed where it lies.
            // Anything else (a line across a buffer boundary, the last line without a newline,
            // an overlong line) is copied by `read_line`, which also enforces MAX_LINE.
            let avail = self.input.fill_buf()?;
            let window = &avail[..avail.len().min(MAX_LINE + 1)];
            if let Some(pos) = find_newline(window) {
                let mut text = &window[..pos];
                while let [rest @ .., b'\r'] = text {
                    text = rest;
                }
                self.line += 1;
                self.bytes += pos as u64 + 1;
                let got = self.parser.parse(text, self.line, frame, meta);
                self.input.consume(pos + 1);
                match got {
                    Some(outcome) => return Ok(outcome),
                    None => continue,
                }
            }
            let Some(ok) = self.read_line()? else {
                return Ok(ReadOutcome::End);
            };
            if !ok {
                return Ok(ReadOutcome::Rejected(LineError {
                    line: self.line,
                    reason: Rejection::TooLong,
                }));
            }
            if let Some(outcome) = self.parser.parse(&self.buf, self.line, frame, meta) {
                return Ok(outcome);
            }
        }
    }
}

/// A frame, or the rejection of the record on `line`.
fn outcome(rejection: Option<Rejection>, line: u64) -> ReadOutcome {
    match rejection {
        None => ReadOutcome::Frame,
        Some(reason) => ReadOutcome::Rejected(LineError { line, reason }),
    }
}

/// Where [`read_records`] reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Threads {
    /// On the consumer's thread, one record at a time.
    One,
    /// On a second thread, in batches, ahead of the consumer.
    ReadAhead,
}

impl Threads {
    /// Reading ahead when the machine has a second core to read on, else one thread.
    pub fn available() -> Threads {
        match std::thread::available_parallelism() {
            Ok(n) if n.get() > 1 => Threads::ReadAhead,
            _ => Threads::One,
        }
    }
}

/// One record as [`read_records`] hands it over.
#[derive(Debug)]
pub enum Record<'a> {
    /// A frame and its meta data.
    Frame(&'a Frame, &'a FrameMeta),
    /// A rejected record.
    Rejected(LineError),
}

/// Frames per batch handed between the threads: enough that the channel's cost per frame is
/// small, few enough that a batch of the largest frames stays far below a megabyte.
const BATCH: usize = 256;

/// Batches in existence at once: one being read, one being consumed, and two queued so that
/// neither thread waits on a momentary stall of the other.
const IN_FLIGHT: usize = 4;

/// Records read ahead: frames in the order read, and the sequence of frames and rejections.
struct Batch {
    frames: Vec<Frame>,
    metas: Vec<FrameMeta>,
    /// `None` for the next frame of `frames`, `Some` for a rejection, in stream order.
    order: Vec<Option<LineError>>,
    /// Set on the last batch: the end of the stream, or the read error that ended it.
    end: Option<std::io::Result<()>>,
}

/// Reads every record of `reader` and hands it to `consume` in stream order, stopping at the
/// end of the stream, at the first error `consume` returns, or at a read error (turned into the
/// caller's error by `read_error`, after every record before it was consumed). `progress` is
/// called after each record with the reader (for a progress bar), on the reading thread.
/// `slots` is the frame size ([`Schema::slots`]).
pub fn read_records<R, E>(
    reader: StreamReader<R>,
    threads: Threads,
    progress: impl FnMut(&StreamReader<R>) + Send,
    read_error: impl FnOnce(std::io::Error) -> E,
    consume: impl FnMut(Record<'_>) -> Result<(), E>,
) -> Result<(), E>
where
    R: BufRead + Send,
{
    match threads {
        Threads::One => read_here(reader, progress, read_error, consume),
        Threads::ReadAhead => read_ahead(reader, progress, read_error, consume),
    }
}

/// [`read_records`] on the caller's thread.
fn read_here<R: BufRead, E>(
    mut reader: StreamReader<R>,
    mut progress: impl FnMut(&StreamReader<R>),
    read_error: impl FnOnce(std::io::Error) -> E,
    mut consume: impl FnMut(Record<'_>) -> Result<(), E>,
) -> Result<(), E> {
    let mut frame = Frame::new(reader.schema().slots());
    let mut meta = FrameMeta::default();
    loop {
        let got = match reader.next_frame(&mut frame, &mut meta) {
            Ok(got) => got,
            Err(e) => return Err(read_error(e)),
        };
        progress(&reader);
        match got {
            ReadOutcome::End => return Ok(()),
            ReadOutcome::Frame => consume(Record::Frame(&frame, &meta))?,
            ReadOutcome::Rejected(e) => consume(Record::Rejected(e))?,
        }
    }
}

/// [`read_records`] with the reading on a second thread (see the module docs).
fn read_ahead<R: BufRead + Send, E>(
    mut reader: StreamReader<R>,
    mut progress: impl FnMut(&StreamReader<R>) + Send,
    read_error: impl FnOnce(std::io::Error) -> E,
    mut consume: impl FnMut(Record<'_>) -> Result<(), E>,
) -> Result<(), E> {
    let slots = reader.schema().slots();
    let (full_tx, full_rx) = mpsc::sync_channel::<Batch>(IN_FLIGHT);
    let (free_tx, free_rx) = mpsc::sync_channel::<Batch>(IN_FLIGHT);
    for _ in 0..IN_FLIGHT {
        // Cannot fail: the receiver is alive and the channel holds IN_FLIGHT.
        let _ = free_tx.send(Batch::new(slots));
    }
    std::thread::scope(|scope| {
        scope.spawn(move || {
            // Ends when the stream does, or when the consumer has gone (its ends are dropped).
            while let Ok(mut batch) = free_rx.recv() {
                batch.fill(&mut reader, &mut progress);
                let last = batch.end.is_some();
                if full_tx.send(batch).is_err() || last {
                    return;
                }
            }
        });
        // The consumer: owns `full_rx` and `free_tx`, dropped on return so that the reader stops.
        let (full_rx, free_tx) = (full_rx, free_tx);
        while let Ok(mut batch) = full_rx.recv() {
            batch.drain(&mut consume)?;
            match batch.end.take() {
                Some(Ok(())) => return Ok(()),
                Some(Err(e)) => return Err(read_error(e)),
                None => {
                    let _ = free_tx.send(batch);
                }
            }
        }
        // The reader thread ended without an end marker: it can only have panicked, which
        // the scope re-raises; there is nothing more to consume.
        Ok(())
    })
}

impl Batch {
    /// An empty batch of frames of `slots` slots, allocated once and reused.
    fn new(slots: usize) -> Batch {
        Batch {
            frames: (0..BATCH).map(|_| Frame::new(slots)).collect(),
            metas: vec![FrameMeta::default(); BATCH],
            order: Vec::with_capacity(BATCH),
            end: None,
        }
    }

    /// Reads up to [`BATCH`] records, or to the end of the stream (then `end` is set).
    fn fill<R: BufRead>(
        &mut self,
        reader: &mut StreamReader<R>,
        progress: &mut impl FnMut(&StreamReader<R>),
    ) {
        self.order.clear();
        let mut used = 0;
        // Rejections count towards the batch too, so that a stream of nothing but bad
        // records still moves in bounded batches.
        while self.order.len() < BATCH && self.end.is_none() {
            match reader.next_frame(&mut self.frames[used], &mut self.metas[used]) {
                Ok(ReadOutcome::Frame) => {
                    self.order.push(None);
                    used += 1;
                }
                Ok(ReadOutcome::Rejected(e)) => self.order.push(Some(e)),
                Ok(ReadOutcome::End) => self.end = Some(Ok(())),
                Err(e) => self.end = Some(Err(e)),
            }
            progress(reader);
        }
    }

    /// Hands the batch's records to `consume` in stream order.
    fn drain<E>(&mut self, consume: &mut impl FnMut(Record<'_>) -> Result<(), E>) -> Result<(), E> {
        let mut frames = self.frames.iter().zip(&self.metas);
        for entry in self.order.drain(..) {
            match entry {
                Some(e) => consume(Record::Rejected(e))?,
                None => {
                    // `order` has exactly as many `None`s as frames were filled.
                    if let Some((frame, meta)) = frames.next() {
                        consume(Record::Frame(frame, meta))?;
                    }
                }
            }
        }
        Ok(())
    }
}

impl LineParser {
    /// Parses line number `line` (without its line ending). `None` when the line is not a
    /// record (blank, or the CSV header, whose problems are queued in `pending`).
    fn parse(
        &mut self,
        text: &[u8],
        line: u64,
        frame: &mut Frame,
        meta: &mut FrameMeta,
    ) -> Option<ReadOutcome> {
        // A UTF-8 byte-order mark (as some editors save) is not part of the first record.
        let text = match (line, text.strip_prefix(b"\xEF\xBB\xBF")) {
            (1, Some(rest)) => rest,
            _ => text,
        };
        if text.iter().all(u8::is_ascii_whitespace) {
            return None;
        }
        if self.format == StreamFormat::Csv && self.csv.is_none() {
            self.header(text, line);
            return None;
        }
        self.reset(line, frame, meta);
        let mut problem = None;
        match &self.csv {
            Some(layout) => layout.parse_row(
                text,
                &self.schema,
                &mut self.scratch,
                frame,
                meta,
                &mut problem,
            ),
            None if self.fast
                && fast_record::scan_record(text, &self.schema, &mut self.scratch, frame, meta) => {
            }
            None => {
                // Not a record the fast scanner vouches for: start over with serde, which
                // words every rejection.
                self.reset(line, frame, meta);
                problem = self.parse_serde(text, frame, meta);
            }
        }
        let problem = problem.or_else(|| check_meta(meta));
        Some(match problem {
            Some(reason) => ReadOutcome::Rejected(LineError { line, reason }),
            None => ReadOutcome::Frame,
        })
    }

    /// Reads the CSV header on `line`; its problems, if any, become one rejection of that line
    /// (so that every line yields at most one outcome).
    fn header(&mut self, text: &[u8], line: u64) {
        let (layout, problem) = CsvLayout::from_header(text, &self.schema, &mut self.scratch);
        self.csv = Some(layout);
        self.pending = problem
            .into_iter()
            .map(|reason| LineError { line, reason })
            .collect();
    }

    /// Empties the frame and meta data for a record on `line`.
    fn reset(&mut self, line: u64, frame: &mut Frame, meta: &mut FrameMeta) {
        *meta = FrameMeta {
            line,
            ..FrameMeta::default()
        };
        frame.clear();
        self.scratch.begin(self.schema.slots);
    }

    /// Reads a JSON record with the serde seed; the first problem found, if any.
    fn parse_serde(
        &mut self,
        text: &[u8],
        frame: &mut Frame,
        meta: &mut FrameMeta,
    ) -> Option<Rejection> {
        let mut problem = None;
        let mut ctx = Ctx {
            schema: &self.schema,
            frame,
            meta,
            scratch: &mut self.scratch,
            problem: &mut problem,
            version: None,
            has_percepts: false,
        };
        let mut de = serde_json::Deserializer::from_slice(text);
        let parsed = RecordSeed(&mut ctx)
            .deserialize(&mut de)
            .and_then(|()| de.end());
        match parsed {
            Err(e) => Some(malformed(&e)),
            Ok(()) => match ctx.version.filter(|&v| v != FORMAT_VERSION as u64) {
                Some(v) => Some(Rejection::Version { found: v }),
                None => problem,
            },
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The JSON seed: deserializes one record straight into the frame.

struct Ctx<'s> {
    schema: &'s Schema,
    frame: &'s mut Frame,
    meta: &'s mut FrameMeta,
    scratch: &'s mut Scratch,
    problem: &'s mut Option<Rejection>,
    version: Option<u64>,
    has_percepts: bool,
}

/// A number as JSON writes it, or one of the strings `"NaN"`, `"inf"`, `"-inf"` (any case,
/// `"Infinity"` too), read so that it can be reported rather than failing as malformed.
#[derive(Debug, Clone, Copy, Default)]
struct Num(f64);

/// A number, `null` (none), or a NaN/inf string.
#[derive(Debug, Clone, Copy, Default)]
struct OptNum(Option<f64>);

struct NumVisitor;

impl<'de> Visitor<'de> for NumVisitor {
    type Value = Option<f64>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number (or \"NaN\")")
    }
    fn visit_f64<E>(self, v: f64) -> Result<Self::Value, E> {
        Ok(Some(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Self::Value, E> {
        Ok(Some(v as f64))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Self::Value, E> {
        Ok(Some(v as f64))
    }
    fn visit_unit<E>(self) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_none<E>(self) -> Result<Self::Value, E> {
        Ok(None)
    }
    fn visit_str<E: de::Error>(self, s: &str) -> Result<Self::Value, E> {
        let t = s.trim();
        let lower = |w: &str| t.eq_ignore_ascii_case(w);
        if lower("nan") {
            Ok(Some(f64::NAN))
        } else if lower("inf") || lower("+inf") || lower("infinity") {
            Ok(Some(f64::INFINITY))
        } else if lower("-inf") || lower("-infinity") {
            Ok(Some(f64::NEG_INFINITY))
        } else {
            Err(E::invalid_value(de::Unexpected::Str(s), &self))
        }
    }
}

impl<'de> Deserialize<'de> for Num {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match d.deserialize_any(NumVisitor)? {
            Some(v) => Ok(Num(v)),
            None => Err(de::Error::invalid_type(de::Unexpected::Unit, &NumVisitor)),
        }
    }
}

impl<'de> Deserialize<'de> for OptNum {
    fn deserialize<D: de::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NumVisitor).map(OptNum)
    }
}

#[derive(Clone, Copy)]
enum RecordKey {
    Version,
    T,
    Odometry,
    Heading,
    Percepts,
    Truth,
    Region,
}

impl RecordKey {
    fn parse(key: &str) -> Option<Self> {
        Some(match key {
            "version" => Self::Version,
            "t" => Self::T,
            "odometry" => Self::Odometry,
            "heading" => Self::Heading,
            "percepts" => Self::Percepts,
            "truth" => Self::Truth,
            "region" => Self::Region,
            _ => return None,
        })
    }
}

#[derive(Clone, Copy)]
enum PerceptKey {
    Name,
    Args,
    Value,
    Degree,
}

impl PerceptKey {
    fn parse(key: &str) -> Option<Self> {
        Some(match key {
            "name" => Self::Name,
            "args" => Self::Args,
            "value" => Self::Value,
            "degree" => Self::Degree,
            _ => return None,
        })
    }
}

#[derive(Clone, Copy)]
enum TruthKey {
    Place,
    Pose,
}

impl TruthKey {
    fn parse(key: &str) -> Option<Self> {
        Some(match key {
            "place" => Self::Place,
            "pose" => Self::Pose,
            _ => return None,
        })
    }
}

/// Reads the next key of an object of kind `within` and resolves it with `parse`. Returns
/// `Ok(None)` at the end of the object, `Ok(Some(None))` for a key to skip: unknown or already
/// seen (bit `index` of `seen`), which becomes the record's problem unless it already has one.
fn next_key<'de, A: MapAccess<'de>, K: Copy>(
    map: &mut A,
    ctx: &mut Ctx<'_>,
    seen: &mut u8,
    within: &'static str,
    parse: fn(&str) -> Option<K>,
    index: fn(K) -> u8,
) -> Result<Option<Option<K>>, A::Error> {
    if map.next_key_seed(StrInto(&mut ctx.scratch.key))?.is_none() {
        return Ok(None);
    }
    let key = ctx.scratch.key.as_str();
    let problem = match parse(key) {
        Some(k) if *seen & (1 << index(k)) == 0 => {
            *seen |= 1 << index(k);
            return Ok(Some(Some(k)));
        }
        Some(_) => Rejection::DuplicateKey {
            key: key.to_string(),
            within,
        },
        None => Rejection::UnknownKey {
            key: key.to_string(),
            within,
        },
    };
    if ctx.problem.is_none() {
        *ctx.problem = Some(problem);
    }
    map.next_value::<IgnoredAny>()?;
    Ok(Some(None))
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct OdometryWire {
    #[serde(default)]
    dx: Num,
    #[serde(default)]
    dy: Num,
    #[serde(default)]
    dtheta: Num,
}

struct RecordSeed<'a, 's>(&'a mut Ctx<'s>);

impl<'de> DeserializeSeed<'de> for RecordSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for RecordSeed<'_, '_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a frame record object")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let ctx = self.0;
        let mut seen = 0u8;
        while let Some(key) = next_key(&mut map, ctx, &mut seen, "record", RecordKey::parse, |k| {
            k as u8
        })? {
            let Some(key) = key else { continue };
            match key {
                RecordKey::Version => ctx.version = Some(map.next_value::<u64>()?),
                RecordKey::T => ctx.meta.t = map.next_value::<OptNum>()?.0,
                RecordKey::Odometry => {
                    let o = map
                        .next_value::<Option<OdometryWire>>()?
                        .unwrap_or_default();
                    ctx.meta.odometry = Odometry {
                        dx: o.dx.0,
                        dy: o.dy.0,
                        dtheta: o.dtheta.0,
                    };
                }
                RecordKey::Heading => ctx.meta.heading = map.next_value::<OptNum>()?.0,
                RecordKey::Percepts => {
                    map.next_value_seed(PerceptsSeed(ctx))?;
                    ctx.has_percepts = true;
                }
                RecordKey::Truth => map.next_value_seed(TruthSeed(ctx))?,
                RecordKey::Region => {
                    map.next_value_seed(StrInto(&mut ctx.scratch.name))?;
                    match ctx.schema.region(ctx.scratch.name.as_bytes()) {
                        Some(r) => ctx.meta.region = Some(r),
                        None if ctx.problem.is_none() => {
                            *ctx.problem = Some(Rejection::UnknownRegion {
                                name: ctx.scratch.name.clone(),
                            });
                        }
                        None => {}
                    }
                }
            }
        }
        if !ctx.has_percepts {
            return Err(de::Error::missing_field("percepts"));
        }
        Ok(())
    }
}

struct PerceptsSeed<'a, 's>(&'a mut Ctx<'s>);

impl<'de> DeserializeSeed<'de> for PerceptsSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for PerceptsSeed<'_, '_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array of percepts")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        while seq.next_element_seed(PerceptSeed(&mut *self.0))?.is_some() {}
        Ok(())
    }
}

struct PerceptSeed<'a, 's>(&'a mut Ctx<'s>);

impl<'de> DeserializeSeed<'de> for PerceptSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for PerceptSeed<'_, '_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a percept object {name, args, value, degree}")
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let ctx = self.0;
        let mut has_name = false;
        let mut degree = None;
        let mut value = None;
        ctx.scratch.nargs = 0;
        let mut seen = 0u8;
        while let Some(key) = next_key(
            &mut map,
            ctx,
            &mut seen,
            "percept",
            PerceptKey::parse,
            |k| k as u8,
        )? {
            let Some(key) = key else { continue };
            match key {
                PerceptKey::Name => {
                    map.next_value_seed(StrInto(&mut ctx.scratch.name))?;
                    has_name = true;
                }
                PerceptKey::Args => {
                    let n = map.next_value_seed(ArgsSeed(&mut ctx.scratch.args))?;
                    ctx.scratch.nargs = n;
                }
                PerceptKey::Value => value = map.next_value::<OptNum>()?.0,
                PerceptKey::Degree => degree = Some(map.next_value::<Num>()?.0),
            }
        }
        if !has_name {
            return Err(de::Error::missing_field("name"));
        }
        let Some(degree) = degree else {
            return Err(de::Error::missing_field("degree"));
        };
        // Take the name buffers out while `put_percept` writes the `seen` stamps; put them back
        // afterwards so their capacity is reused by the next percept.
        let name = std::mem::take(&mut ctx.scratch.name);
        let args_buf = std::mem::take(&mut ctx.scratch.args);
        let args = args_buf.len().min(ctx.scratch.nargs);
        put_percept(
            ctx.schema,
            ctx.scratch,
            ctx.frame,
            ctx.problem,
            &name,
            &args_buf[..args],
            degree,
            value,
        );
        ctx.scratch.name = name;
        ctx.scratch.args = args_buf;
        Ok(())
    }
}

/// Deserializes a string into a reused buffer.
struct StrInto<'a>(&'a mut String);

impl<'de> DeserializeSeed<'de> for StrInto<'_> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_str(self)
    }
}

impl<'de> Visitor<'de> for StrInto<'_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a string")
    }
    fn visit_str<E>(self, s: &str) -> Result<(), E> {
        self.0.clear();
        self.0.push_str(s);
        Ok(())
    }
}

/// Deserializes an array of strings into reused buffers; yields how many there were.
struct ArgsSeed<'a>(&'a mut Vec<String>);

impl<'de> DeserializeSeed<'de> for ArgsSeed<'_> {
    type Value = usize;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<usize, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for ArgsSeed<'_> {
    type Value = usize;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("an array of argument names")
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<usize, A::Error> {
        let mut n = 0;
        loop {
            if n == self.0.len() {
                self.0.push(String::new());
            }
            if seq.next_element_seed(StrInto(&mut self.0[n]))?.is_none() {
                return Ok(n);
            }
            n += 1;
        }
    }
}

struct TruthSeed<'a, 's>(&'a mut Ctx<'s>);

impl<'de> DeserializeSeed<'de> for TruthSeed<'_, '_> {
    type Value = ();
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_option(self)
    }
}

impl<'de> Visitor<'de> for TruthSeed<'_, '_> {
    type Value = ();
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a truth object {place, pose}")
    }
    fn visit_none<E>(self) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }
    fn visit_some<D: de::Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_map(self)
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let ctx = self.0;
        ctx.meta.truth_known = true;
        let mut seen = 0u8;
        while let Some(key) = next_key(&mut map, ctx, &mut seen, "truth", TruthKey::parse, |k| {
            k as u8
        })? {
            let Some(key) = key else { continue };
            match key {
                TruthKey::Place => {
                    let place = map.next_value_seed(PlaceSeed(ctx.schema))?;
                    match place {
                        Ok(p) => ctx.meta.truth_place = p,
                        Err(name) => {
                            if ctx.problem.is_none() {
                                *ctx.problem = Some(Rejection::UnknownTruthPlace { name });
                            }
                        }
                    }
                }
                TruthKey::Pose => {
                    ctx.meta.truth_pose = map
                        .next_value::<Option<[Num; 3]>>()?
                        .map(|p| [p[0].0, p[1].0, p[2].0]);
                }
            }
        }
        Ok(())
    }
}

/// A truth place name resolved against the schema: `Ok(None)` for null, `Err(name)` if unknown.
struct PlaceSeed<'a>(&'a Schema);

impl<'de> DeserializeSeed<'de> for PlaceSeed<'_> {
    type Value = Result<Option<usize>, String>;
    fn deserialize<D: de::Deserializer<'de>>(self, d: D) -> Result<Self::Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for PlaceSeed<'_> {
    type Value = Result<Option<usize>, String>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a place name or null")
    }
    fn visit_unit<E>(self) -> Result<Self::Value, E> {
        Ok(Ok(None))
    }
    fn visit_none<E>(self) -> Result<Self::Value, E> {
        Ok(Ok(None))
    }
    fn visit_str<E>(self, s: &str) -> Result<Self::Value, E> {
        Ok(self.0.place(s).map(Some).ok_or_else(|| s.to_string()))
    }
}

/// A serde_json error as a rejection in this program's words. serde_json says where with "at
/// line 1 column C" (a record is one line, so its line is always 1); the column is kept as data
/// and the reader reports the file's line, so the message itself carries no position.
fn malformed(e: &serde_json::Error) -> Rejection {
    let text = e.to_string();
    let what = text
        .rsplit_once(" at line ")
        .map_or(text.as_str(), |(w, _)| w);
    let message = match e.classify() {
        serde_json::error::Category::Eof => {
            "the record ends before its closing brace, bracket or quote".to_string()
        }
        serde_json::error::Category::Syntax => format!("not JSON: {}", syntax_words(what)),
        serde_json::error::Category::Data => data_words(what),
        serde_json::error::Category::Io => what.to_string(),
    };
    Rejection::Malformed {
        column: e.column().max(1),
        message,
    }
}

/// Plain words for serde_json's syntax messages.
fn syntax_words(what: &str) -> &'static str {
    match what {
        "expected ident" => "a bare word where a value belongs (text needs quotes; the words JSON knows are true, false and null)",
        "expected value" => "a value is missing here, or is not a JSON value",
        "key must be a string" => "an object key must be a quoted string",
        "trailing characters" => "more text after the record's closing brace",
        "trailing comma" => "a comma before a closing brace or bracket",
        "expected `:`" => "a `:` is missing after a key",
        "expected `,` or `}`" => "a `,` or `}` is missing",
        "expected `,` or `]`" => "a `,` or `]` is missing",
        "invalid number" | "number out of range" => "a number JSON cannot represent",
        _ if what.starts_with("control character") => "a raw control character inside a string",
        _ if what.contains("escape") || what.contains("surrogate") || what.contains("unicode") => {
            "a bad escape inside a string"
        }
        _ => "unexpected character",
    }
}

/// Plain words for serde's shape messages (`invalid type: X, expected Y`, `missing field`).
fn data_words(what: &str) -> String {
    if let Some((found, expected)) = what
        .strip_prefix("invalid type: ")
        .or_else(|| what.strip_prefix("invalid value: "))
        .and_then(|r| r.split_once(", expected "))
    {
        return format!("expected {expected}, found {found}");
    }
    if let Some(field) = what.strip_prefix("missing field ") {
        return format!("the field {field} is missing");
    }
    what.to_string()
}
