//! The `io` layer: the stream reader (fast path against the plain one, reading ahead), the Intel
//! chain end to end, and ROS 2 bags against the CARMEN log they were written from.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod buildings;
mod evidence_per_metre;
mod extract_rosbag2;
mod fuzz_corpus;
mod intel_accuracy;
mod mrclam_hostile;
mod stream_csv;
mod stream_fastpath;
mod stream_hostile;
mod stream_readahead;
mod stream_time;
