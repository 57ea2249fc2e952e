//! Opening a percept stream named on the command line, shared by every command that reads one
//! (`eval`, `grid`, `compare`, `survey`), so that they open, name and report streams alike: `-` is stdin
//! (reported as `<stdin>`), a directory is refused, and each rejected record is reported on
//! stderr as `STREAM:LINE: reason`.

use std::io::{BufRead, BufReader};
use std::path::Path;

use super::CliError;
use crate::io::stream::{LineError, TimeRestart};

/// Input buffer size: records are a few hundred bytes, and a large buffer lets most lines be
/// parsed where they lie in it.
const BUFFER: usize = 1 << 16;

/// An opened stream.
pub(super) struct StreamInput {
    /// How reports name the stream.
    pub name: String,
    /// The bytes.
    pub input: Box<dyn BufRead + Send>,
    /// Its length in bytes, when it is a file (for a progress bar).
    pub size: Option<u64>,
}

/// Opens `path` (`-` for stdin).
///
/// # Errors
/// [`CliError::Read`] when the file cannot be opened or is a directory.
pub(super) fn open(path: &Path) -> Result<StreamInput, CliError> {
    if path.as_os_str() == "-" {
        return Ok(StreamInput {
            name: "<stdin>".into(),
            input: Box::new(BufReader::with_capacity(BUFFER, std::io::stdin())),
            size: None,
        });
    }
    let read_err = |source| CliError::Read {
        path: path.display().to_string(),
        source,
    };
    let f = std::fs::File::open(path).map_err(read_err)?;
    let meta = f.metadata().map_err(read_err)?;
    if meta.is_dir() {
        return Err(read_err(std::io::Error::other("is a directory")));
    }
    Ok(StreamInput {
        name: path.display().to_string(),
        input: Box::new(BufReader::with_capacity(BUFFER, f)),
        size: Some(meta.len()),
    })
}

/// The note on a record of stream `name` where the clock starts again (`--time restart`).
pub(super) fn note(name: &str, n: &TimeRestart) -> String {
    format!("{name}:{n}")
}

/// The report of a rejected record of stream `name`.
pub(super) fn rejection(name: &str, e: &LineError) -> String {
    format!("{name}:{e}")
}
