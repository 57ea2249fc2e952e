//! Readers and writers of recorded data. None of them opens files: they take
//! text or `BufRead`/`Write` handles from the caller.

pub mod mrclam;
pub mod tum;
