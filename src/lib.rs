//! lplace: possibilistic place recognition.

pub mod grid;
pub mod io;
