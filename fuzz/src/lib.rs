//! lplace's fuzz targets' shared entry points (see `entries.rs`).

#[path = "entries.rs"]
mod entries;
pub use entries::*;
