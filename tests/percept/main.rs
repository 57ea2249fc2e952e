//! The `percept` layer and its readers: extractors on synthetic and real geometry, property tests,
//! and the CARMEN extraction.

#[allow(dead_code)]
#[path = "../support/mod.rs"]
mod support;

mod extract_carmen;
mod percept_extractors;
mod percept_props;
mod percept_readers;
mod percept_real_data;
