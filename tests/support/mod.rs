//! What the test binaries share: the `lplace` binary, where the real data lives, scratch space.
//! Included by each binary's `main.rs` as `mod support`.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

pub mod carmen;
pub mod landmarks;
pub mod mrclam;

/// The `lplace` binary of this build, run from the crate root (so relative paths such as
/// `maps/office.map` resolve as in the README).
pub fn lplace() -> Command {
    let mut c = Command::cargo_bin("lplace").expect("the lplace binary is built");
    c.current_dir(env!("CARGO_MANIFEST_DIR"));
    c
}

/// The real-data folder: `$LPLACE_DATA`, else `../shared/data` beside the crate.
pub fn data_dir() -> PathBuf {
    match std::env::var_os("LPLACE_DATA") {
        Some(d) => PathBuf::from(d),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"),
    }
}

/// MRCLAM dataset 7's folder, or `None` (after saying so on stderr) when it is absent, so
/// that the caller can skip.
pub fn mrclam_dir() -> Option<PathBuf> {
    let dir = data_dir().join("mrclam-dataset7");
    if dir.join("Barcodes.dat").exists() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: MRCLAM dataset 7 not found at {} (set LPLACE_DATA)",
            dir.display()
        );
        None
    }
}

/// A fresh, empty directory `group/name` under cargo's per-target temporary directory.
pub fn scratch(group: &str, name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("the target's temporary directory is writable");
    d
}
