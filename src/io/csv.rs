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
//! Arguments are separated by spaces (commas would split the cell). Cells are not quoted; `nan`,
//! `inf` parse as such and are then rejected like their JSON counterparts. A header column that is
//! none of these, or names an undeclared percept, is reported once (on line 1) and its cells are
//! ignored. Depends on `io::stream` (schema, checks) and `engine::frame`.

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

/// One data row split into cells (byte ranges into `text`).
struct Row<'a> {
    text: &'a str,
    fields: &'a [(usize, usize)],
}

impl Row<'_> {
    fn cell(&self, i: usize) -> &str {
        let (a, b) = self.fields[i];
        self.text[a..b].trim()
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
                if problem.is_none() {
                    *problem = Some(Rejection::Malformed {
                        column: self.fields[i].0 + 1,
                        message: format!("`{c}` is not a number"),
                    });
                }
                None
            }
        }
    }
}

/// Keeps `r` in `problem` unless an earlier problem is there.
fn first(problem: &mut Option<Rejection>, r: impl FnOnce() -> Rejection) {
    if problem.is_none() {
        *problem = Some(r());
    }
}

impl CsvLayout {
    /// Resolves a header row; returns the layout and the problems found in it.
    pub fn from_header(line: &[u8], schema: &Schema) -> (CsvLayout, Vec<Rejection>) {
        let text = String::from_utf8_lossy(line);
        let mut layout = CsvLayout {
            cols: Vec::new(),
            percepts: Vec::new(),
            has_truth: false,
        };
        let mut problems = Vec::new();
        for cell in text.split(',') {
            let cell = cell.trim();
            let col = match fixed_col(cell) {
                Some(col) => col,
                None => layout.percept_col(cell, schema).unwrap_or_else(|r| {
                    problems.push(r);
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
        (layout, problems)
    }

    /// Resolves a `deg:…` or `val:…` header cell (the next column), registering its percept.
    fn percept_col(&mut self, cell: &str, schema: &Schema) -> Result<Col, Rejection> {
        let column = |reason| Rejection::CsvColumn {
            column: cell.to_string(),
            reason,
        };
        let (is_degree, rest) = if let Some(r) = cell.strip_prefix("deg:") {
            (true, r)
        } else if let Some(r) = cell.strip_prefix("val:") {
            (false, r)
        } else {
            return Err(column(
                "not a known column (deg:…, val:…, t, dx, dy, dtheta, heading, truth_…)",
            ));
        };
        let (name, args) = split_instance(rest).ok_or_else(|| column("unbalanced parentheses"))?;
        if schema.lookup(name, &args).is_none() {
            return Err(Rejection::UnknownPercept {
                instance: crate::io::stream::instance_name(name, &args),
            });
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
            return Err(column("repeated column"));
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
        let text = match std::str::from_utf8(line) {
            Ok(t) => t,
            Err(e) => {
                *problem = Some(Rejection::Malformed {
                    column: e.valid_up_to() + 1,
                    message: "not UTF-8".into(),
                });
                return;
            }
        };
        // The cell ranges live in the scratch space; taken out while `scratch` marks slots.
        let mut fields = std::mem::take(&mut scratch.fields);
        fields.clear();
        let mut start = 0;
        for (i, b) in text.bytes().enumerate() {
            if b == b',' {
                fields.push((start, i));
                start = i + 1;
            }
        }
        fields.push((start, text.len()));
        if fields.len() == self.cols.len() {
            let row = Row {
                text,
                fields: &fields,
            };
            self.read_meta(&row, schema, meta, problem);
            self.read_percepts(&row, schema, scratch, frame, problem);
        } else {
            *problem = Some(Rejection::Malformed {
                column: 1,
                message: format!(
                    "row has {} fields, the header has {}",
                    fields.len(),
                    self.cols.len()
                ),
            });
        }
        scratch.fields = fields;
    }

    /// Reads the row's non-percept cells, in column order.
    fn read_meta(
        &self,
        row: &Row<'_>,
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
        row: &Row<'_>,
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
                (None, Some(_)) => first(problem, || Rejection::Malformed {
                    column: p.value.map_or(1, |i| row.fields[i].0 + 1),
                    message: format!(
                        "a value for `{}` without its degree",
                        crate::io::stream::instance_name(&p.name, &p.args)
                    ),
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
