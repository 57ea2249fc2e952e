//! The CSV form of a percept stream: a header row naming the columns, then one frame per row.
//!
//! | column | meaning |
//! |--------|---------|
//! | `version` | format version (optional; must be 1) |
//! | `t` | time in seconds |
//! | `dx`, `dy`, `dtheta` | odometry increment (metres forward, left; degrees) |
//! | `heading` | heading in the map frame, degrees (optional; empty = unknown) |
//! | `truth_place` | true place name; empty between places |
//! | `truth_x`, `truth_y`, `truth_theta` | true pose |
//! | `deg:NAME` or `deg:NAME(ARG ARG)` | degree of a percept instance; empty = not perceived |
//! | `val:NAME` or `val:NAME(ARG ARG)` | its measured value; needs the degree in the same row |
//!
//! Lines are split by the `csv` crate: a cell may be quoted (`"deg:sonar_wall(North)"`, `""`
//! for a quote inside), but a record never spans lines (a quote left open is a rejected row), so
//! that every line yields at most one outcome. Arguments are separated by spaces. `nan`, `inf`
//! parse as such and are then rejected like their JSON counterparts. The header's problems are
//! one rejection of line 1 naming each column: a column that is none of these, or names an
//! undeclared percept, is ignored (its cells unread); a column given twice, or a first line that
//! names no column (a missing header), leaves the stream unreadable and every row is rejected.
//! A UTF-8 byte-order mark before the header is ignored (by the stream reader). Depends on
//! `io::stream` (schema, checks) and `engine::frame`.

use crate::engine::{Frame, PerceptSlot, PerceptTable};
use crate::io::record::{FrameRecord, FORMAT_VERSION};
use crate::io::stream::{put_percept, FrameMeta, Rejection, Schema, Scratch};
use std::io::Write;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Col {
    Version,
    T,
    Dx,
    Dy,
    Dtheta,
    Heading,
    TruthPlace,
    TruthX,
    TruthY,
    TruthTheta,
    /// Index into `percepts`, degree cell.
    Degree(usize),
    /// Index into `percepts`, value cell.
    Value(usize),
    Ignored,
}

#[derive(Debug, Clone)]
struct PerceptCols {
    name: String,
    args: Vec<String>,
    degree: Option<usize>,
    value: Option<usize>,
}

/// The columns of a CSV stream, resolved from its header.
#[derive(Debug, Clone)]
pub struct CsvLayout {
    cols: Vec<Col>,
    percepts: Vec<PerceptCols>,
    has_truth: bool,
    /// False after a header that cannot be used (repeated or no known column).
    usable: bool,
}

/// Splits `NAME(A B)` into the name and its arguments.
fn split_instance(s: &str) -> Option<(&str, Vec<&str>)> {
    match s.find('(') {
        None => Some((s.trim(), Vec::new())),
        Some(i) => {
            let rest = s[i + 1..].trim_end();
            let inner = rest.strip_suffix(')')?;
            Some((s[..i].trim(), inner.split_whitespace().collect()))
        }
    }
}

/// The fixed (non-percept) column a header cell names, if any.
fn fixed_col(cell: &str) -> Option<Col> {
    Some(match cell {
        "version" => Col::Version,
        "t" => Col::T,
        "dx" => Col::Dx,
        "dy" => Col::Dy,
        "dtheta" => Col::Dtheta,
        "heading" => Col::Heading,
        "truth_place" => Col::TruthPlace,
        "truth_x" => Col::TruthX,
        "truth_y" => Col::TruthY,
        "truth_theta" => Col::TruthTheta,
        _ => return None,
    })
}

/// A CSV line's cells, split by the `csv` crate (quoted cells, doubled quotes), kept from row
/// to row.
#[derive(Debug, Default)]
pub(crate) struct Cells {
    record: csv::ByteRecord,
    /// The unescaped cells, one after another.
    text: String,
    /// Byte range of each cell in `text`.
    fields: Vec<(usize, usize)>,
    /// 1-based column (byte) where each cell starts in the line, for messages.
    columns: Vec<usize>,
}

impl Cells {
    /// Splits one line (a record never spans lines in a stream: a quote left open is an error).
    fn split(&mut self, line: &[u8]) -> Result<(), Rejection> {
        self.text.clear();
        self.fields.clear();
        self.columns.clear();
        let mut quoted = false;
        self.columns.push(1);
        for (i, &b) in line.iter().enumerate() {
            match b {
                b'"' => quoted = !quoted,
                b',' if !quoted => self.columns.push(i + 2),
                _ => {}
            }
        }
        if quoted {
            let column = line.iter().rposition(|&b| b == b'"').map_or(1, |p| p + 1);
            return Err(malformed(
                column,
                "a quoted cell is not closed on its line".into(),
            ));
        }
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .buffer_capacity(line.len().max(64))
            .from_reader(line);
        if let Err(e) = reader.read_byte_record(&mut self.record) {
            return Err(malformed(1, format!("not CSV: {e}")));
        }
        for (k, cell) in self.record.iter().enumerate() {
            let column = self.columns.get(k).copied().unwrap_or(1);
            let cell = std::str::from_utf8(cell)
                .map_err(|e| malformed(column + e.valid_up_to(), "not UTF-8".into()))?;
            let start = self.text.len();
            self.text.push_str(cell.trim());
            self.fields.push((start, self.text.len()));
        }
        Ok(())
    }

    fn len(&self) -> usize {
        self.fields.len()
    }

    fn cell(&self, i: usize) -> &str {
        self.fields.get(i).map_or("", |&(a, b)| &self.text[a..b])
    }

    fn column(&self, i: usize) -> usize {
        self.columns.get(i).copied().unwrap_or(1)
    }

    /// Cell `i` as a number; `None` when empty, or when not a number (then the problem is kept
    /// in `problem` unless one is there already).
    fn num(&self, i: usize, problem: &mut Option<Rejection>) -> Option<f64> {
        let c = self.cell(i);
        if c.is_empty() {
            return None;
        }
        match c.parse::<f64>() {
            Ok(v) => Some(v),
            Err(_) => {
                first(problem, || {
                    malformed(self.column(i), format!("`{c}` is not a number"))
                });
                None
            }
        }
    }
}

fn malformed(column: usize, message: String) -> Rejection {
    Rejection::Malformed { column, message }
}

/// One problem of a CSV header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HeaderProblem {
    /// The header cell.
    pub column: String,
    /// What is wrong with it.
    pub reason: &'static str,
}

impl HeaderProblem {
    /// `column `a`: reason; column `b`: reason`, for a message.
    pub fn list(problems: &[HeaderProblem]) -> String {
        let parts: Vec<String> = problems
            .iter()
            .map(|p| format!("column `{}`: {}", p.column, p.reason))
            .collect();
        parts.join("; ")
    }
}

/// Keeps `r` in `problem` unless an earlier problem is there.
fn first(problem: &mut Option<Rejection>, r: impl FnOnce() -> Rejection) {
    if problem.is_none() {
        *problem = Some(r());
    }
}

impl CsvLayout {
    /// Resolves a header row; returns the layout and the rejection of the header line when it
    /// has problems (every problem column named). A repeated column or a line that names no
    /// known column (a missing header) makes the layout unusable: every row is then rejected.
    pub(crate) fn from_header(
        line: &[u8],
        schema: &Schema,
        scratch: &mut Scratch,
    ) -> (CsvLayout, Option<Rejection>) {
        let mut layout = CsvLayout {
            cols: Vec::new(),
            percepts: Vec::new(),
            has_truth: false,
            usable: true,
        };
        let cells = &mut scratch.cells;
        if let Err(r) = cells.split(line) {
            layout.usable = false;
            return (layout, Some(r));
        }
        let mut problems = Vec::new();
        for i in 0..cells.len() {
            let cell = cells.cell(i);
            let col = match fixed_col(cell) {
                Some(col) if layout.cols.contains(&col) => {
                    problems.push(HeaderProblem {
                        column: cell.to_string(),
                        reason: "given twice",
                    });
                    layout.usable = false;
                    Col::Ignored
                }
                Some(col) => col,
                None => layout.percept_col(cell, schema).unwrap_or_else(|p| {
                    layout.usable &= p.reason != "given twice";
                    problems.push(p);
                    Col::Ignored
                }),
            };
            if matches!(
                col,
                Col::TruthPlace | Col::TruthX | Col::TruthY | Col::TruthTheta
            ) {
                layout.has_truth = true;
            }
            layout.cols.push(col);
        }
        let named = (0..cells.len()).any(|i| {
            let c = cells.cell(i);
            fixed_col(c).is_some() || c.starts_with("deg:") || c.starts_with("val:")
        });
        if !named {
            layout.usable = false;
            problems = vec![HeaderProblem {
                column: cells.cell(0).to_string(),
                reason:
                    "the first line names no column (t, dx, …, deg:NAME): is the header missing?",
            }];
        }
        let problem = (!problems.is_empty()).then_some(Rejection::CsvHeader { problems });
        (layout, problem)
    }

    /// Resolves a `deg:…` or `val:…` header cell (the next column), registering its percept.
    fn percept_col(&mut self, cell: &str, schema: &Schema) -> Result<Col, HeaderProblem> {
        let column = |reason| HeaderProblem {
            column: cell.to_string(),
            reason,
        };
        let (is_degree, rest) = if let Some(r) = cell.strip_prefix("deg:") {
            (true, r)
        } else if let Some(r) = cell.strip_prefix("val:") {
            (false, r)
        } else {
            return Err(column(
                "not a known column (deg:…, val:…, t, dx, dy, dtheta, heading, truth_…); its cells are ignored",
            ));
        };
        let (name, args) = split_instance(rest).ok_or_else(|| column("unbalanced parentheses"))?;
        if schema.lookup(name, &args).is_none() {
            return Err(column(
                "a percept the rule file does not declare; its cells are ignored",
            ));
        }
        let k = match self
            .percepts
            .iter()
            .position(|p| p.name == name && p.args == args)
        {
            Some(k) => k,
            None => {
                self.percepts.push(PerceptCols {
                    name: name.to_string(),
                    args: args.iter().map(|a| a.to_string()).collect(),
                    degree: None,
                    value: None,
                });
                self.percepts.len() - 1
            }
        };
        let i = self.cols.len();
        let p = &mut self.percepts[k];
        let slot = if is_degree {
            &mut p.degree
        } else {
            &mut p.value
        };
        if slot.is_some() {
            return Err(column("given twice"));
        }
        *slot = Some(i);
        Ok(if is_degree {
            Col::Degree(k)
        } else {
            Col::Value(k)
        })
    }

    /// Parses one data row into `frame` and `meta`; the first problem goes to `problem`.
    pub(crate) fn parse_row(
        &self,
        line: &[u8],
        schema: &Schema,
        scratch: &mut Scratch,
        frame: &mut Frame,
        meta: &mut FrameMeta,
        problem: &mut Option<Rejection>,
    ) {
        if !self.usable {
            *problem = Some(Rejection::NoCsvHeader);
            return;
        }
        // The cells live in the scratch space; taken out while `scratch` marks slots.
        let mut cells = std::mem::take(&mut scratch.cells);
        match cells.split(line) {
            Err(r) => *problem = Some(r),
            Ok(()) if cells.len() == self.cols.len() => {
                self.read_meta(&cells, schema, meta, problem);
                self.read_percepts(&cells, schema, scratch, frame, problem);
            }
            Ok(()) => {
                *problem = Some(malformed(
                    1,
                    format!(
                        "row has {} cells, the header has {}",
                        cells.len(),
                        self.cols.len()
                    ),
                ));
            }
        }
        scratch.cells = cells;
    }

    /// Reads the row's non-percept cells, in column order.
    fn read_meta(
        &self,
        row: &Cells,
        schema: &Schema,
        meta: &mut FrameMeta,
        problem: &mut Option<Rejection>,
    ) {
        meta.truth_known = self.has_truth;
        let mut pose = [f64::NAN, f64::NAN, 0.0];
        let mut has_pose = false;
        for (i, col) in self.cols.iter().enumerate() {
            match col {
                Col::Version => {
                    if let Some(v) = row.num(i, problem) {
                        if v != FORMAT_VERSION as f64 {
                            first(problem, || Rejection::Version {
                                found: if v >= 0.0 { v as u64 } else { 0 },
                            });
                        }
                    }
                }
                Col::T => meta.t = row.num(i, problem),
                Col::Dx => meta.odometry.dx = row.num(i, problem).unwrap_or(0.0),
                Col::Dy => meta.odometry.dy = row.num(i, problem).unwrap_or(0.0),
                Col::Dtheta => meta.odometry.dtheta = row.num(i, problem).unwrap_or(0.0),
                Col::Heading => meta.heading = row.num(i, problem),
                Col::TruthPlace => {
                    let c = row.cell(i);
                    if !c.is_empty() {
                        match schema.place(c) {
                            Some(p) => meta.truth_place = Some(p),
                            None => first(problem, || Rejection::UnknownTruthPlace {
                                name: c.to_string(),
                            }),
                        }
                    }
                }
                Col::TruthX | Col::TruthY | Col::TruthTheta => {
                    if let Some(v) = row.num(i, problem) {
                        let k = match col {
                            Col::TruthX => 0,
                            Col::TruthY => 1,
                            _ => 2,
                        };
                        pose[k] = v;
                        has_pose |= k < 2;
                    }
                }
                Col::Degree(_) | Col::Value(_) | Col::Ignored => {}
            }
        }
        if has_pose {
            meta.truth_pose = Some(pose);
        }
    }

    /// Reads the row's percept cells, percept by percept in header order.
    fn read_percepts(
        &self,
        row: &Cells,
        schema: &Schema,
        scratch: &mut Scratch,
        frame: &mut Frame,
        problem: &mut Option<Rejection>,
    ) {
        for p in &self.percepts {
            let degree = p.degree.and_then(|i| row.num(i, problem));
            let value = p.value.and_then(|i| row.num(i, problem));
            match (degree, value) {
                (Some(d), v) => {
                    put_percept(schema, scratch, frame, problem, &p.name, &p.args, d, v)
                }
                (None, Some(_)) => first(problem, || {
                    malformed(
                        p.value.map_or(1, |i| row.column(i)),
                        format!(
                            "a value for `{}` without its degree",
                            crate::io::stream::instance_name(&p.name, &p.args)
                        ),
                    )
                }),
                (None, None) => {}
            }
        }
    }
}

/// Writes frame records as CSV rows with a fixed header.
#[derive(Debug, Clone)]
pub struct CsvWriter {
    /// Per percept instance: name, args, and whether it has a value column.
    instances: Vec<(String, Vec<String>, bool)>,
    table: PerceptTable,
}

impl CsvWriter {
    /// A writer for every instance of `table`; `has_value(slot)` says which get a `val:` column.
    pub fn new(table: &PerceptTable, has_value: impl Fn(PerceptSlot) -> bool) -> CsvWriter {
        let instances = table
            .instances()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                (
                    p.name.clone(),
                    p.args.clone(),
                    has_value(PerceptSlot(i as u32)),
                )
            })
            .collect();
        CsvWriter {
            instances,
            table: table.clone(),
        }
    }

    fn column(prefix: &str, name: &str, args: &[String]) -> String {
        if args.is_empty() {
            format!("{prefix}:{name}")
        } else {
            format!("{prefix}:{name}({})", args.join(" "))
        }
    }

    /// Writes the header row.
    pub fn write_header(&self, out: &mut impl Write) -> std::io::Result<()> {
        write!(
            out,
            "version,t,dx,dy,dtheta,heading,truth_place,truth_x,truth_y,truth_theta"
        )?;
        for (name, args, has_value) in &self.instances {
            write!(out, ",{}", Self::column("deg", name, args))?;
            if *has_value {
                write!(out, ",{}", Self::column("val", name, args))?;
            }
        }
        writeln!(out)
    }

    /// Writes one record as a row; percepts the table does not know are left out.
    pub fn write_row(&self, rec: &FrameRecord, out: &mut impl Write) -> std::io::Result<()> {
        let opt = |v: Option<f64>| v.map_or_else(String::new, |x| x.to_string());
        let odo = rec.odometry.unwrap_or_default();
        let truth = rec.truth.clone().unwrap_or_default();
        let pose = truth.pose;
        write!(
            out,
            "{},{},{},{},{},{},{},{},{},{}",
            rec.version.unwrap_or(FORMAT_VERSION),
            opt(rec.t),
            odo.dx,
            odo.dy,
            odo.dtheta,
            opt(rec.heading),
            truth.place.unwrap_or_default(),
            opt(pose.map(|p| p[0])),
            opt(pose.map(|p| p[1])),
            opt(pose.map(|p| p[2])),
        )?;
        let mut cells: Vec<(Option<f64>, Option<f64>)> = vec![(None, None); self.instances.len()];
        for p in &rec.percepts {
            let args: Vec<&str> = p.args.iter().map(String::as_str).collect();
            if let Some(s) = self.table.slot(&p.name, &args) {
                if let Some(c) = cells.get_mut(s.0 as usize) {
                    *c = (Some(p.degree), p.value);
                }
            }
        }
        for ((_, _, has_value), (d, v)) in self.instances.iter().zip(&cells) {
            write!(out, ",{}", opt(*d))?;
            if *has_value {
                write!(out, ",{}", opt(*v))?;
            }
        }
        writeln!(out)
    }
}
