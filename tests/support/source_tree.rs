//! The crate's own sources as files, for the tests that read them (`tests/layers.rs`,
//! `tests/fn_length.rs`); included there by path, since those are single-file test binaries.

use std::fs;
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, recursively, appended to `out` (an unreadable folder adds
/// nothing: the callers then find fewer files than they expect and say so).
pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}
