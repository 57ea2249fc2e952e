//! Reading and writing what crosses the program's edge: percept-stream records and raw sensor
//! logs and trajectories. Every reader here parses bytes or lines that the caller supplies and performs no I/O of
//! its own, so the same code serves files, pipes and tests; malformed records are typed errors
//! carrying what went wrong (and the line number where there are lines), and the caller decides
//! whether to skip and report them.

pub mod carmen;
pub mod carmen_stream;
pub mod csv;
mod fast_record;
pub mod landmark_stream;
pub mod line;
pub mod mrclam;
pub mod mrclam_dir;
pub mod mrclam_stream;
pub mod record;
#[cfg(feature = "rosbag2")]
pub mod rosbag2;
pub mod stream;
pub mod time_order;
pub mod tum;
pub mod uci;
