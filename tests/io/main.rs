//! The `io` layer: the stream reader (fast path against the plain one, reading ahead) and the Intel
//! chain end to end.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod intel_accuracy;
mod stream_fastpath;
mod stream_readahead;
