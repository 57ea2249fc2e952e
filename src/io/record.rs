//! The frame record: one frame of a percept stream as it appears on the wire (a JSON object, one
//! per line in a stream), and its conversion into the engine's dense [`Frame`].
//!
//! ```json
//! {"version": 1, "t": 12.5,
//!  "odometry": {"dx": 0.10, "dy": 0.0, "dtheta": 0.0}, "heading": 90.0,
//!  "percepts": [{"name": "beacon_angle", "value": 116.0, "degree": 0.9},
//!               {"name": "sonar_wall", "args": ["North"], "degree": 0.8}],
//!  "truth": {"place": "P2", "pose": [4.5, 3.4, 90.0]}}
//! ```
//!
//! Only `percepts` is required. `degree` is the engine's degree (1 = fully supported; paper
//! 003's dissimilarities δ become `1 − δ`); `value` is the measured value compared with a
//! place's expectation. The reader does no I/O: it takes a string.

use crate::engine::{Frame, PerceptTable};
use serde::{Deserialize, Serialize};

/// The stream format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// Odometry increment since the previous frame, in the robot's frame at the previous frame:
/// metres forward (`dx`) and left (`dy`), and degrees turned (`dtheta`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    /// Metres forward.
    #[serde(default)]
    pub dx: f64,
    /// Metres to the left.
    #[serde(default)]
    pub dy: f64,
    /// Degrees turned counter-clockwise.
    #[serde(default)]
    pub dtheta: f64,
}

impl Odometry {
    /// The increment in SI units (metres, radians), as the trackers take it.
    pub fn to_si(self) -> crate::core::Odometry {
        crate::core::Odometry {
            forward: self.dx,
            left: self.dy,
            turn: self.dtheta.to_radians(),
        }
    }
}

/// One percept of a frame record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PerceptRecord {
    /// Percept name as declared in the rule file.
    pub name: String,
    /// Domain arguments (`["North"]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub args: Vec<String>,
    /// Measured value, when the percept has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// Degree in `[0, 1]`.
    pub degree: f64,
}

/// Ground truth carried by recorded or simulated frames.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    /// The place the robot is at, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub place: Option<String>,
    /// `[x, y, θ]` in metres and degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose: Option<[f64; 3]>,
}

/// One frame as written in a stream.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    /// Format version; absent means [`FORMAT_VERSION`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub version: Option<u32>,
    /// Time in seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    /// Odometry increment since the previous frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub odometry: Option<Odometry>,
    /// The robot's heading in the map frame, degrees counter-clockwise from the map's +x, when
    /// the source has one (a compass, or an axis-locked estimate such as
    /// [`crate::percept::compass`]). With it the tracker carries displacement vectors, not
    /// just distances.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading: Option<f64>,
    /// The percepts.
    pub percepts: Vec<PerceptRecord>,
    /// Ground truth, if known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub truth: Option<Truth>,
    /// A region known from outside (a place, room, region or kind name): the engine conditions
    /// its distribution on it (`Engine::step_within`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub region: Option<String>,
}

/// Why a record (or one percept of it) was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecordError {
    /// Not valid JSON, or not of the record's shape.
    #[error("malformed record at column {column}: {message}")]
    Malformed {
        /// 1-based column where parsing failed.
        column: usize,
        /// The JSON parser's explanation.
        message: String,
    },
    /// A version this build does not read.
    #[error("unsupported format version {found} (this build reads {FORMAT_VERSION})")]
    Version {
        /// The version found.
        found: u32,
    },
    /// A percept the rule file does not declare (with these arguments).
    #[error("unknown percept `{name}({})`", args.join(", "))]
    UnknownPercept {
        /// Its name.
        name: String,
        /// Its arguments.
        args: Vec<String>,
    },
    /// A degree that is NaN or outside `[0, 1]`.
    #[error("percept `{name}`: degree {degree} is not in [0, 1]")]
    Degree {
        /// The percept.
        name: String,
        /// The degree found.
        degree: f64,
    },
    /// A value that is not finite.
    #[error("percept `{name}`: value {value} is not finite")]
    Value {
        /// The percept.
        name: String,
        /// The value found.
        value: f64,
    },
}

impl RecordError {
    /// A short, stable name of the kind of problem (the names of `io::stream`'s rejections).
    pub fn kind(&self) -> &'static str {
        match self {
            RecordError::Malformed { .. } => "malformed",
            RecordError::Version { .. } => "version",
            RecordError::UnknownPercept { .. } => "unknown_percept",
            RecordError::Degree { degree, .. } if degree.is_nan() => "nan",
            RecordError::Degree { .. } => "degree_out_of_range",
            RecordError::Value { .. } => "not_finite",
        }
    }
}

impl FrameRecord {
    /// Parses one JSON record.
    pub fn parse(text: &str) -> Result<FrameRecord, RecordError> {
        let rec: FrameRecord = serde_json::from_str(text).map_err(|e| RecordError::Malformed {
            column: e.column(),
            message: e.to_string(),
        })?;
        match rec.version {
            Some(v) if v != FORMAT_VERSION => Err(RecordError::Version { found: v }),
            _ => Ok(rec),
        }
    }

    /// Fills `frame` (cleared first) from this record. Percepts that cannot be used are left
    /// out of the frame and returned, one error each; the rest of the frame is still filled.
    pub fn fill(&self, table: &PerceptTable, frame: &mut Frame, rejected: &mut Vec<RecordError>) {
        frame.clear();
        for p in &self.percepts {
            let args: Vec<&str> = p.args.iter().map(String::as_str).collect();
            let Some(slot) = table.slot(&p.name, &args) else {
                rejected.push(RecordError::UnknownPercept {
                    name: p.name.clone(),
                    args: p.args.clone(),
                });
                continue;
            };
            if !(0.0..=1.0).contains(&p.degree) {
                rejected.push(RecordError::Degree {
                    name: p.name.clone(),
                    degree: p.degree,
                });
                continue;
            }
            if let Some(v) = p.value {
                if !v.is_finite() {
                    rejected.push(RecordError::Value {
                        name: p.name.clone(),
                        value: v,
                    });
                    continue;
                }
            }
            frame.set(slot, p.degree, p.value);
        }
    }
}
