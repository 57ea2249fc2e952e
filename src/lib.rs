//! lplace: possibilistic place recognition.

pub mod io;
pub mod percept;
