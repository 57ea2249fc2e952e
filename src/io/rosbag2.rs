//! ROS 2 bags (MCAP storage) → the percept stream `--from carmen` makes: `sensor_msgs/msg/
//! LaserScan` and `nav_msgs/msg/Odometry` messages become the scans and odometry readings that
//! [`CarmenFramer`] turns into frames, so the two sources give the same frames for the same
//! data. Library code behind `lplace extract --from rosbag2`; it does no I/O of its own (it
//! reads an MCAP file's bytes, which the caller maps or reads). The MCAP container is read
//! with the `mcap` crate, the messages' CDR with `cdr-encoding` (serde), not by hand.
//!
//! # Topics
//! Found by message type when not named: the scan topic is the one `LaserScan` topic, the
//! odometry topic the one `Odometry` topic, the truth topic the one `geometry_msgs/msg/
//! PoseStamped` topic (none when there is none). Two candidates and no choice is an error
//! naming them ([`BagError::Ambiguous`]). A named truth topic may also carry `Odometry`.
//! `tf`/`tf_static` are not read: the scanner is taken at the robot's origin plus the
//! configured forward offset, and truth comes from a pose topic.
//!
//! # Semantics (what a ROS robot records ↔ what the CARMEN reader uses)
//! Messages are taken in file order (rosbag2 writes them as they arrive). Each odometry
//! message is an `ODOM` reading; each scan is a `FLASER` whose odometry pose is the last
//! odometry pose before it and whose pose is the last truth pose before it (else the odometry
//! pose). The frame's odometry is then the increment of the odometry track between scans, as
//! for CARMEN. Scans before the first odometry message have no pose to start from: they are
//! skipped and counted. A scan's time is its header stamp.
//!
//! # Numbers
//! Beams are at `angle_min + i·angle_increment`. ROS stores ranges and angles as `float32`;
//! a range is widened to `f64` through its shortest decimal form (the number it was written
//! from: `1.09f32` reads as the `f64` nearest 1.09, as a text log would give), an angle that
//! is the `float32` of a quarter turn multiple (`angle_min`) or of `π/q` (`angle_increment`)
//! to that value exactly, so a scan written from a CARMEN log reads exactly as the log does.
//! Either changes a native `float32` reading by less than half its last place. A range that is NaN or outside `[range_min,
//! range_max]` is "no return" and reads as `+∞`, as the extractors expect.
//!
//! # Bad messages
//! A message on a chosen topic with another type, another encoding than CDR, a payload that
//! does not decode (truncated, bad string) or a non-finite pose is a [`MessageError`] carrying
//! the topic and the log time; it is reported through the caller's callback, counted, and
//! skipped. A file that is not MCAP, or whose records are broken, stops the conversion with
//! a [`BagError`] after the frames read so far.

use std::collections::BTreeMap;
use std::sync::Arc;

use byteorder::{BigEndian, LittleEndian};
use serde::Deserialize;
use thiserror::Error;

use crate::core::Pose2;
use crate::io::carmen::{CarmenMessage, LaserScan, Odom};
use crate::io::carmen_stream::CarmenFramer;
use crate::io::record::FrameRecord;

/// The scan message type.
pub const LASER_SCAN: &str = "sensor_msgs/msg/LaserScan";
/// The odometry message type.
pub const ODOMETRY: &str = "nav_msgs/msg/Odometry";
/// The default truth message type.
pub const POSE_STAMPED: &str = "geometry_msgs/msg/PoseStamped";

/// Why a bag could not be read at all.
#[derive(Debug, Error)]
pub enum BagError {
    /// The MCAP container is broken (or the file is not MCAP).
    #[error("not a readable MCAP file: {0}")]
    Mcap(#[from] mcap::McapError),
    /// No topic carries the needed message type.
    #[error("no {role} topic: no channel carries {msg_type}")]
    NoTopic {
        /// scan / odometry.
        role: &'static str,
        /// The type looked for.
        msg_type: &'static str,
    },
    /// A topic named on the command line is not in the bag.
    #[error("the {role} topic {topic} is not in the bag")]
    MissingTopic {
        /// scan / odometry / truth.
        role: &'static str,
        /// The name given.
        topic: String,
    },
    /// Several topics carry the type; the user must choose.
    #[error("several {role} topics ({}): choose one with --{role}-topic", topics.join(", "))]
    Ambiguous {
        /// scan / odom / truth.
        role: &'static str,
        /// The candidates.
        topics: Vec<String>,
    },
}

/// Why one message was skipped.
#[derive(Debug, Error)]
pub enum MessageError {
    /// The message's schema is not the type the topic is read as.
    #[error("{topic} at {log_time} ns: message type {found}, expected {expected}")]
    UnexpectedType {
        /// Topic.
        topic: String,
        /// Log time, nanoseconds.
        log_time: u64,
        /// The schema name found (empty when the channel has none).
        found: String,
        /// The type expected.
        expected: &'static str,
    },
    /// Not CDR-encoded.
    #[error("{topic} at {log_time} ns: message encoding {encoding:?}, expected cdr")]
    Encoding {
        /// Topic.
        topic: String,
        /// Log time, nanoseconds.
        log_time: u64,
        /// The encoding found.
        encoding: String,
    },
    /// The payload does not decode as the type (truncated, bad length, bad string).
    #[error(
        "{topic} at {log_time} ns: payload of {len} bytes does not decode as {msg_type}: {source}"
    )]
    Decode {
        /// Topic.
        topic: String,
        /// Log time, nanoseconds.
        log_time: u64,
        /// Payload length.
        len: usize,
        /// The type tried.
        msg_type: &'static str,
        /// The decoder's reason.
        #[source]
        source: cdr_encoding::Error,
    },
    /// The 4-byte encapsulation header is missing or names another representation.
    #[error("{topic} at {log_time} ns: no CDR encapsulation header (payload of {len} bytes)")]
    Encapsulation {
        /// Topic.
        topic: String,
        /// Log time, nanoseconds.
        log_time: u64,
        /// Payload length.
        len: usize,
    },
    /// A pose or scan angle is not finite.
    #[error("{topic} at {log_time} ns: {field} is not finite")]
    NotFinite {
        /// Topic.
        topic: String,
        /// Log time, nanoseconds.
        log_time: u64,
        /// Which field.
        field: &'static str,
    },
}

/// Topic names chosen by the user (`None`: found by type).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TopicChoice {
    /// `--scan-topic`.
    pub scan: Option<String>,
    /// `--odom-topic`.
    pub odom: Option<String>,
    /// `--truth-topic`.
    pub truth: Option<String>,
}

/// The topics a conversion reads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topics {
    /// Scans.
    pub scan: String,
    /// Odometry.
    pub odom: String,
    /// Ground-truth poses, when the bag has them.
    pub truth: Option<String>,
}

/// What a conversion did.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BagSummary {
    /// Frames produced.
    pub frames: u64,
    /// Scan, odometry and truth messages used.
    pub scans: u64,
    /// Odometry messages used.
    pub odoms: u64,
    /// Truth messages used.
    pub truths: u64,
    /// Scans skipped because no odometry came before them.
    pub scans_before_odometry: u64,
    /// Messages on other topics.
    pub other: u64,
    /// Messages rejected ([`MessageError`]).
    pub rejected: u64,
}

/// Picks the topics: the user's choices, checked against the bag, else the one topic of
/// each type (from the summary section when the file has one, else from a pass over it).
///
/// # Errors
/// [`BagError`] when the file is not MCAP, a named topic is absent, or a type has no topic
/// or several.
pub fn resolve_topics(bag: &[u8], choice: &TopicChoice) -> Result<Topics, BagError> {
    let by_topic = channel_types(bag)?;
    let pick = |role: &'static str,
                named: &Option<String>,
                types: &[&'static str]|
     -> Result<Option<String>, BagError> {
        if let Some(t) = named {
            return match by_topic.contains_key(t) {
                true => Ok(Some(t.clone())),
                false => Err(BagError::MissingTopic {
                    role,
                    topic: t.clone(),
                }),
            };
        }
        let found: Vec<String> = by_topic
            .iter()
            .filter(|(_, ty)| ty.as_str() == types[0])
            .map(|(t, _)| t.clone())
            .collect();
        match found.len() {
            0 | 1 => Ok(found.into_iter().next()),
            _ => Err(BagError::Ambiguous {
                role,
                topics: found,
            }),
        }
    };
    let scan = pick("scan", &choice.scan, &[LASER_SCAN])?.ok_or(BagError::NoTopic {
        role: "scan",
        msg_type: LASER_SCAN,
    })?;
    let odom = pick("odom", &choice.odom, &[ODOMETRY])?.ok_or(BagError::NoTopic {
        role: "odometry",
        msg_type: ODOMETRY,
    })?;
    let truth = pick("truth", &choice.truth, &[POSE_STAMPED])?;
    Ok(Topics { scan, odom, truth })
}

/// Topic → schema name of every channel (the first channel wins for a repeated topic).
fn channel_types(bag: &[u8]) -> Result<BTreeMap<String, String>, BagError> {
    let mut out = BTreeMap::new();
    if let Some(summary) = mcap::Summary::read(bag)? {
        // The summary holds channels in a hash map: visit them in id order (the order they
        // were declared), so that "the first channel wins" does not depend on hashing.
        let mut channels: Vec<_> = summary.channels.values().collect();
        channels.sort_by_key(|ch| ch.id);
        for ch in channels {
            out.entry(ch.topic.clone())
                .or_insert_with(|| schema_name(ch));
        }
        return Ok(out);
    }
    let mut stream = mcap::read::RawMessageStream::new(bag)?;
    while let Some(m) = stream.next() {
        let m = m?;
        if let Some(ch) = stream.get_channel(m.header.channel_id) {
            out.entry(ch.topic.clone())
                .or_insert_with(|| schema_name(&ch));
        }
    }
    Ok(out)
}

fn schema_name(ch: &mcap::Channel<'_>) -> String {
    ch.schema
        .as_ref()
        .map_or_else(String::new, |s| s.name.clone())
}

#[derive(Deserialize)]
struct Time {
    sec: i32,
    nanosec: u32,
}

#[derive(Deserialize)]
struct Header {
    stamp: Time,
    #[allow(dead_code)]
    frame_id: String,
}

#[derive(Deserialize)]
struct Point {
    x: f64,
    y: f64,
    #[allow(dead_code)]
    z: f64,
}

#[derive(Deserialize)]
struct Quaternion {
    x: f64,
    y: f64,
    z: f64,
    w: f64,
}

#[derive(Deserialize)]
struct Pose {
    position: Point,
    orientation: Quaternion,
}

/// `float64[36]`, read as six rows (serde reads fixed arrays of up to 32 elements).
type Covariance = [[f64; 6]; 6];

#[derive(Deserialize)]
#[allow(dead_code)]
struct OdometryMsg {
    header: Header,
    child_frame_id: String,
    pose: Pose,
    pose_covariance: Covariance,
    twist: [f64; 6],
    twist_covariance: Covariance,
}

#[derive(Deserialize)]
#[allow(dead_code)]
struct PoseStampedMsg {
    header: Header,
    pose: Pose,
}

#[derive(Deserialize)]
#[allow(dead_code)]
struct LaserScanMsg {
    header: Header,
    angle_min: f32,
    angle_max: f32,
    angle_increment: f32,
    time_increment: f32,
    scan_time: f32,
    range_min: f32,
    range_max: f32,
    ranges: Vec<f32>,
    intensities: Vec<f32>,
}

/// Where a message came from, for error reports.
struct Origin<'a> {
    topic: &'a str,
    log_time: u64,
}

/// Decodes a CDR payload (4-byte encapsulation header, then the message, aligned from after
/// the header) as `T`.
fn decode<'de, T: Deserialize<'de>>(
    data: &'de [u8],
    msg_type: &'static str,
    at: &Origin<'_>,
) -> Result<T, MessageError> {
    let body = data.get(4..).ok_or_else(|| MessageError::Encapsulation {
        topic: at.topic.to_owned(),
        log_time: at.log_time,
        len: data.len(),
    })?;
    // The representation identifier: 0x0000/0x0001 CDR big/little endian (PL_CDR variants
    // 0x0002/0x0003 do not occur in ROS 2 messages).
    let decoded = match (data[0], data[1]) {
        (0, 1) => cdr_encoding::from_bytes::<T, LittleEndian>(body),
        (0, 0) => cdr_encoding::from_bytes::<T, BigEndian>(body),
        _ => {
            return Err(MessageError::Encapsulation {
                topic: at.topic.to_owned(),
                log_time: at.log_time,
                len: data.len(),
            })
        }
    };
    decoded
        .map(|(v, _)| v)
        .map_err(|source| MessageError::Decode {
            topic: at.topic.to_owned(),
            log_time: at.log_time,
            len: data.len(),
            msg_type,
            source,
        })
}

/// The planar pose of a ROS pose: position x, y and the yaw of the orientation.
fn pose2(p: &Pose, at: &Origin<'_>) -> Result<Pose2, MessageError> {
    let q = &p.orientation;
    let yaw = (2.0 * (q.w * q.z + q.x * q.y)).atan2(1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    let pose = Pose2 {
        x: p.position.x,
        y: p.position.y,
        theta: yaw,
    };
    if pose.x.is_finite() && pose.y.is_finite() && pose.theta.is_finite() {
        Ok(pose)
    } else {
        Err(MessageError::NotFinite {
            topic: at.topic.to_owned(),
            log_time: at.log_time,
            field: "pose",
        })
    }
}

fn seconds(t: &Time) -> f64 {
    f64::from(t.sec) + f64::from(t.nanosec) * 1e-9
}

/// A `float32` as the `f64` of its shortest decimal form (module docs, Numbers).
fn widen(x: f32, buf: &mut ryu::Buffer) -> f64 {
    if !x.is_finite() {
        return f64::from(x);
    }
    buf.format_finite(x).parse().unwrap_or(f64::from(x))
}

/// A `float32` angle as an `f64`: when it is the `float32` of `π·k/q` — `angle_min` with
/// `q = quarter` (4: a multiple of a quarter turn, `k` the nearest whole number), or
/// `angle_increment` with `quarter` 1 (`k = 1`, `q` the nearest whole number up to 4096) —
/// that value exactly: the angle the writer meant, a scanner's −π/2 start or π/180 step.
/// Otherwise [`widen`] (module docs, Numbers).
fn widen_angle(x: f32, quarter: u32, buf: &mut ryu::Buffer) -> f64 {
    use std::f64::consts::PI;
    let wide = f64::from(x);
    let candidate = if quarter > 1 {
        let q = f64::from(quarter);
        (wide * q / PI).round() * PI / q
    } else {
        let q = (PI / wide).round();
        if (1.0..=4096.0).contains(&q) {
            PI / q
        } else {
            f64::NAN
        }
    };
    if candidate.is_finite() && candidate as f32 == x {
        candidate
    } else {
        widen(x, buf)
    }
}

/// One conversion: the topics read, and the state carried between messages (and files).
pub struct BagConverter<'f, 'm> {
    framer: &'f mut CarmenFramer<'m>,
    topics: Topics,
    laser_offset: f64,
    last_odom: Option<Pose2>,
    last_truth: Option<Pose2>,
    summary: BagSummary,
    ryu: ryu::Buffer,
}

/// What a topic is read as.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Scan,
    Odom,
    Truth,
    Other,
}

impl BagConverter<'_, '_> {
    /// Handles one message of a chosen topic; a scan yields a frame.
    fn message(
        &mut self,
        role: Role,
        schema: &str,
        data: &[u8],
        at: &Origin<'_>,
    ) -> Result<Option<FrameRecord>, MessageError> {
        let expect = |ty: &'static str| {
            if schema == ty {
                Ok(ty)
            } else {
                Err(MessageError::UnexpectedType {
                    topic: at.topic.to_owned(),
                    log_time: at.log_time,
                    found: schema.to_owned(),
                    expected: ty,
                })
            }
        };
        match role {
            Role::Scan => {
                let msg: LaserScanMsg = decode(data, expect(LASER_SCAN)?, at)?;
                self.scan(&msg, at)
            }
            Role::Odom => {
                let msg: OdometryMsg = decode(data, expect(ODOMETRY)?, at)?;
                let pose = pose2(&msg.pose, at)?;
                self.last_odom = Some(pose);
                self.summary.odoms += 1;
                self.framer.push(
                    &CarmenMessage::Odom(Odom {
                        pose,
                        tv: 0.0,
                        rv: 0.0,
                        accel: 0.0,
                        timestamp: seconds(&msg.header.stamp),
                    }),
                    self.laser_offset,
                );
                Ok(None)
            }
            Role::Truth => {
                let pose = if schema == ODOMETRY {
                    let msg: OdometryMsg = decode(data, ODOMETRY, at)?;
                    pose2(&msg.pose, at)?
                } else {
                    let msg: PoseStampedMsg = decode(data, expect(POSE_STAMPED)?, at)?;
                    pose2(&msg.pose, at)?
                };
                self.last_truth = Some(pose);
                self.summary.truths += 1;
                Ok(None)
            }
            Role::Other => Ok(None),
        }
    }

    fn scan(
        &mut self,
        msg: &LaserScanMsg,
        at: &Origin<'_>,
    ) -> Result<Option<FrameRecord>, MessageError> {
        let first = widen_angle(msg.angle_min, 4, &mut self.ryu);
        let step = widen_angle(msg.angle_increment, 1, &mut self.ryu);
        if !(first.is_finite() && step.is_finite()) {
            return Err(MessageError::NotFinite {
                topic: at.topic.to_owned(),
                log_time: at.log_time,
                field: "angle_min or angle_increment",
            });
        }
        let Some(odom_pose) = self.last_odom else {
            self.summary.scans_before_odometry += 1;
            return Ok(None);
        };
        let (lo, hi) = (f64::from(msg.range_min), f64::from(msg.range_max));
        let ranges = msg
            .ranges
            .iter()
            .map(|&r| {
                let w = widen(r, &mut self.ryu);
                let valid = w.is_finite() && f64::from(r) >= lo && f64::from(r) <= hi;
                if valid {
                    w
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        let scan = LaserScan {
            ranges,
            pose: self.last_truth.unwrap_or(odom_pose),
            odom_pose,
            timestamp: seconds(&msg.header.stamp),
        };
        self.summary.scans += 1;
        self.summary.frames += 1;
        Ok(Some(self.framer.push_scan(
            &scan,
            first,
            step,
            self.laser_offset,
        )))
    }
}

impl<'f, 'm> BagConverter<'f, 'm> {
    /// A conversion of the `topics` of one bag (one or more `.mcap` files, in order) into
    /// frames of `framer`; `laser_offset` is the scanner's forward offset, metres.
    pub fn new(framer: &'f mut CarmenFramer<'m>, topics: Topics, laser_offset: f64) -> Self {
        BagConverter {
            framer,
            topics,
            laser_offset,
            last_odom: None,
            last_truth: None,
            summary: BagSummary::default(),
            ryu: ryu::Buffer::new(),
        }
    }

    /// What the conversion did so far.
    pub fn summary(&self) -> &BagSummary {
        &self.summary
    }

    /// Converts the messages of one `.mcap` file (its bytes): every frame goes to `on_frame`
    /// (which may fail and then stops the conversion), every bad message to `on_error`,
    /// after which the conversion goes on.
    ///
    /// # Errors
    /// `Ok(Err(e))` when `on_frame` fails; `Err` when the container breaks ([`BagError::Mcap`]).
    pub fn push_file<E>(
        &mut self,
        bag: &[u8],
        mut on_frame: impl FnMut(FrameRecord) -> Result<(), E>,
        mut on_error: impl FnMut(&MessageError),
    ) -> Result<Result<(), E>, BagError> {
        // Role and schema per channel id, decided once per channel.
        let mut roles: BTreeMap<u16, (Role, Arc<mcap::Channel<'_>>, String)> = BTreeMap::new();
        let mut stream = mcap::read::RawMessageStream::new(bag)?;
        while let Some(m) = stream.next() {
            let m = m?;
            let id = m.header.channel_id;
            let (role, ch, schema) = match roles.entry(id) {
                std::collections::btree_map::Entry::Occupied(o) => &*o.into_mut(),
                std::collections::btree_map::Entry::Vacant(v) => {
                    let Some(ch) = stream.get_channel(id) else {
                        self.summary.other += 1;
                        continue;
                    };
                    let role = match ch.topic.as_str() {
                        t if t == self.topics.scan => Role::Scan,
                        t if t == self.topics.odom => Role::Odom,
                        t if Some(t) == self.topics.truth.as_deref() => Role::Truth,
                        _ => Role::Other,
                    };
                    let schema = schema_name(&ch);
                    &*v.insert((role, ch, schema))
                }
            };
            if *role == Role::Other {
                self.summary.other += 1;
                continue;
            }
            let at = Origin {
                topic: &ch.topic,
                log_time: m.header.log_time,
            };
            let result = if ch.message_encoding == "cdr" {
                self.message(*role, schema, &m.data, &at)
            } else {
                Err(MessageError::Encoding {
                    topic: ch.topic.clone(),
                    log_time: at.log_time,
                    encoding: ch.message_encoding.clone(),
                })
            };
            match result {
                Ok(Some(frame)) => {
                    if let Err(e) = on_frame(frame) {
                        return Ok(Err(e));
                    }
                }
                Ok(None) => {}
                Err(e) => {
                    self.summary.rejected += 1;
                    on_error(&e);
                }
            }
        }
        Ok(Ok(()))
    }
}
