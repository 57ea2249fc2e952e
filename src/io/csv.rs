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
            let col = match cell {
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
                _ => {
                    let (is_degree, rest) = if let Some(r) = cell.strip_prefix("deg:") {
                        (true, r)
                    } else if let Some(r) = cell.strip_prefix("val:") {
                        (false, r)
                    } else {
                        problems.push(Rejection::CsvColumn {
                            column: cell.to_string(),
                            reason: "not a known column (deg:…, val:…, t, dx, dy, dtheta, heading, truth_…)",
                        });
                        layout.cols.push(Col::Ignored);
                        continue;
                    };
                    let Some((name, args)) = split_instance(rest) else {
                        problems.push(Rejection::CsvColumn {
                            column: cell.to_string(),
                            reason: "unbalanced parentheses",
                        });
                        layout.cols.push(Col::Ignored);
                        continue;
                    };
                    if schema.lookup(name, &args).is_none() {
                        problems.push(Rejection::UnknownPercept {
                            instance: crate::io::stream::instance_name(name, &args),
                        });
                        layout.cols.push(Col::Ignored);
                        continue;
                    }
                    let k = match layout
                        .percepts
                        .iter()
                        .position(|p| p.name == name && p.args == args)
                    {
                        Some(k) => k,
                        None => {
                            layout.percepts.push(PerceptCols {
                                name: name.to_string(),
                                args: args.iter().map(|a| a.to_string()).collect(),
                                degree: None,
                                value: None,
                            });
                            layout.percepts.len() - 1
                        }
                    };
                    let i = layout.cols.len();
                    let p = &mut layout.percepts[k];
                    let slot = if is_degree {
                        &mut p.degree
                    } else {
                        &mut p.value
                    };
                    if slot.is_some() {
                        problems.push(Rejection::CsvColumn {
                            column: cell.to_string(),
                            reason: "repeated column",
                        });
                        layout.cols.push(Col::Ignored);
                        continue;
                    }
                    *slot = Some(i);
                    if is_degree {
                        Col::Degree(k)
                    } else {
                        Col::Value(k)
                    }
                }
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
        if fields.len() != self.cols.len() {
            *problem = Some(Rejection::Malformed {
                column: 1,
                message: format!(
                    "row has {} fields, the header has {}",
                    fields.len(),
                    self.cols.len()
                ),
            });
            scratch.fields = fields;
            return;
        }
        let cell = |i: usize| {
            let (a, b) = fields[i];
            text[a..b].trim()
        };
        let num = |i: usize, problem: &mut Option<Rejection>| -> Option<f64> {
            let c = cell(i);
            if c.is_empty() {
                return None;
            }
            match c.parse::<f64>() {
                Ok(v) => Some(v),
                Err(_) => {
                    if problem.is_none() {
                        *problem = Some(Rejection::Malformed {
                            column: fields[i].0 + 1,
                            message: format!("`{c}` is not a number"),
                        });
                    }
                    None
                }
            }
        };
        meta.truth_known = self.has_truth;
        let mut pose = [f64::NAN, f64::NAN, 0.0];
        let mut has_pose = false;
        for (i, col) in self.cols.iter().enumerate() {
            match col {
                Col::Version => {
                    if let Some(v) = num(i, problem) {
                        if v != FORMAT_VERSION as f64 && problem.is_none() {
                            *problem = Some(Rejection::Version {
                                found: if v >= 0.0 { v as u64 } else { 0 },
                            });
                        }
                    }
                }
                Col::T => meta.t = num(i, problem),
                Col::Dx => meta.odometry.dx = num(i, problem).unwrap_or(0.0),
                Col::Dy => meta.odometry.dy = num(i, problem).unwrap_or(0.0),
                Col::Dtheta => meta.odometry.dtheta = num(i, problem).unwrap_or(0.0),
                Col::Heading => meta.heading = num(i, problem),
                Col::TruthPlace => {
                    let c = cell(i);
                    if !c.is_empty() {
                        match schema.place(c) {
                            Some(p) => meta.truth_place = Some(p),
                            None => {
                                if problem.is_none() {
                                    *problem = Some(Rejection::UnknownTruthPlace {
                                        name: c.to_string(),
                                    });
                                }
                            }
                        }
                    }
                }
                Col::TruthX | Col::TruthY | Col::TruthTheta => {
                    if let Some(v) = num(i, problem) {
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
        for p in &self.percepts {
            let degree = p.degree.and_then(|i| num(i, problem));
            let value = p.value.and_then(|i| num(i, problem));
            match (degree, value) {
                (Some(d), v) => {
                    put_percept(schema, scratch, frame, problem, &p.name, &p.args, d, v)
                }
                (None, Some(_)) => {
                    if problem.is_none() {
                        *problem = Some(Rejection::Malformed {
                            column: p.value.map_or(1, |i| fields[i].0 + 1),
                            message: format!(
                                "a value for `{}` without its degree",
                                crate::io::stream::instance_name(&p.name, &p.args)
                            ),
                        });
                    }
                }
                (None, None) => {}
            }
        }
        scratch.fields = fields;
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
