//! Output files named on the command line: checked before any work, never written over an
//! input, written atomically.
//!
//! A run over a long recording can take minutes; a typo in `--plot nodir/p.svg` must not cost
//! them, so every command checks its output paths first ([`check`]). A file is written to a
//! temporary file beside it and renamed into place ([`write_atomic`]), so a failed or
//! interrupted run leaves the old file (or none), never half of a new one.

use super::CliError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output path cannot be written (found before any work; exit 2).
#[derive(Debug, thiserror::Error)]
pub enum OutputProblem {
    /// The folder the file would go into does not exist.
    #[error("folder `{0}` does not exist")]
    NoFolder(String),
    /// The path names a folder, not a file.
    #[error("it is a folder")]
    IsFolder,
    /// The path names a file where a folder is wanted.
    #[error("it is a file, not a folder")]
    NotFolder,
    /// The path is one of the command's inputs.
    #[error("it is an input of this command ({0}); refusing to write over it")]
    IsInput(String),
    /// Two outputs of the command name the same file.
    #[error("{0} writes the same file")]
    Twice(&'static str),
}

/// One output of a command: the flag that named it and the path.
#[derive(Debug, Clone, Copy)]
pub struct Output<'a> {
    /// The flag, e.g. `--plot` (for messages).
    pub flag: &'static str,
    /// The path as the user wrote it.
    pub path: &'a Path,
    /// A folder (created if needed) rather than a file.
    pub folder: bool,
}

impl<'a> Output<'a> {
    /// An output file.
    pub fn file(flag: &'static str, path: &'a Path) -> Self {
        Output {
            flag,
            path,
            folder: false,
        }
    }

    /// An output folder (created if needed).
    pub fn folder(flag: &'static str, path: &'a Path) -> Self {
        Output {
            flag,
            path,
            folder: true,
        }
    }
}

/// Checks every output before any work: its folder exists, it is not a folder (or, for a
/// folder output, not a file), it is none of `inputs` (given as `(what, path)`; `-` for stdin
/// is skipped), and no two outputs name the same file.
pub fn check(outputs: &[Output<'_>], inputs: &[(&str, &Path)]) -> Result<(), CliError> {
    for (i, out) in outputs.iter().enumerate() {
        let fail = |why| CliError::OutputPath {
            flag: out.flag,
            path: out.path.display().to_string(),
            why,
        };
        if out.folder {
            if out.path.exists() && !out.path.is_dir() {
                return Err(fail(OutputProblem::NotFolder));
            }
            continue;
        }
        if out.path.is_dir() {
            return Err(fail(OutputProblem::IsFolder));
        }
        let folder = parent(out.path);
        if !folder.is_dir() {
            return Err(fail(OutputProblem::NoFolder(folder.display().to_string())));
        }
        if let Some((what, _)) = inputs
            .iter()
            .find(|(_, p)| p.as_os_str() != "-" && same_file(p, out.path))
        {
            return Err(fail(OutputProblem::IsInput((*what).to_string())));
        }
        let earlier = outputs[..i]
            .iter()
            .find(|o| !o.folder && (o.path == out.path || same_file(o.path, out.path)));
        if let Some(o) = earlier {
            return Err(fail(OutputProblem::Twice(o.flag)));
        }
    }
    Ok(())
}

/// Writes a file atomically: `fill` writes into a temporary file in the same folder, which then
/// replaces `path` by a rename. On any error the temporary file is removed and `path` is left
/// as it was. A link is followed: the file it names is replaced and the link kept. A path that
/// names no regular file but a device or a pipe (`-o /dev/null`, `-o /dev/stdout`) is written
/// in place: a rename would put a regular file where the device was (run as root, `/dev/null`
/// itself).
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), CliError> {
    let fail = |source| CliError::WriteFile {
        path: path.display().to_string(),
        source,
    };
    let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir());
    if special {
        return write_in_place(path, fill).map_err(fail);
    }
    let target = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let tmp = temp_name(&target);
    let result = (|| {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        std::fs::rename(&tmp, &target)
    })();
    result.map_err(|e| {
        // The temporary file may not exist (creation failed); nothing else to undo.
        let _ = std::fs::remove_file(&tmp);
        fail(e)
    })
}

/// Writes straight into an existing device or pipe.
fn write_in_place(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let file = std::fs::OpenOptions::new().write(true).open(path)?;
    let mut w = std::io::BufWriter::new(file);
    fill(&mut w)?;
    w.flush()
}

/// Creates an output folder (and its parents), naming it on failure.
pub fn create_folder(path: &Path) -> Result<(), CliError> {
    std::fs::create_dir_all(path).map_err(|source| CliError::WriteFile {
        path: path.display().to_string(),
        source,
    })
}

/// The folder a file goes into (`.` for a bare file name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// A hidden name beside `path`, unique to this process, for [`write_atomic`].
fn temp_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    parent(path).join(format!(".{name}.{}.lplace-tmp", std::process::id()))
}

/// Whether two paths name the same existing file (through links and `..` alike).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(unix)]
    #[test]
    fn a_device_is_written_in_place_and_stays_a_device() {
        use std::os::unix::fs::FileTypeExt;
        let null = Path::new("/dev/null");
        if !std::fs::metadata(null).is_ok_and(|m| m.file_type().is_char_device()) {
            eprintln!("SKIP: /dev/null is not a character device here");
            return;
        }
        write_atomic(null, |w| w.write_all(b"discarded")).unwrap();
        let m = std::fs::metadata(null).unwrap();
        assert!(m.file_type().is_char_device(), "{m:?}");
    }

    #[cfg(unix)]
    #[test]
    fn a_link_is_followed_and_kept() {
        let d = scratch("link");
        let (file, link) = (d.join("real.svg"), d.join("link.svg"));
        std::fs::write(&file, "old").unwrap();
        std::os::unix::fs::symlink(&file, &link).unwrap();
        write_atomic(&link, |w| w.write_all(b"new")).unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        let _ = std::fs::remove_dir_all(d);
    }

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("lplace-output-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temp is writable");
        d
    }

    #[test]
    fn atomic_write_replaces_and_a_failed_one_keeps_the_old_file() {
        let d = scratch("atomic");
        let p = d.join("out.txt");
        write_atomic(&p, |w| w.write_all(b"one")).expect("writes");
        assert_eq!(std::fs::read(&p).expect("exists"), b"one");
        let failed = write_atomic(&p, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("disk full"))
        });
        assert!(matches!(failed, Err(CliError::WriteFile { .. })));
        assert_eq!(std::fs::read(&p).expect("kept"), b"one");
        let left: Vec<_> = std::fs::read_dir(&d).expect("lists").collect();
        assert_eq!(left.len(), 1, "no temporary file left behind");
    }

    #[test]
    fn check_finds_each_problem() {
        let d = scratch("check");
        let input = d.join("in.jsonl");
        std::fs::write(&input, "{}\n").expect("writes");
        let inputs = [("STREAM", input.as_path())];
        let problem = |outs: &[Output<'_>]| match check(outs, &inputs) {
            Err(CliError::OutputPath { why, .. }) => Some(why.to_string()),
            _ => None,
        };
        let missing = d.join("nodir/p.svg");
        assert!(problem(&[Output::file("--plot", &missing)])
            .is_some_and(|w| w.contains("does not exist")));
        assert!(problem(&[Output::file("--plot", &d)]).is_some_and(|w| w == "it is a folder"));
        // The same input reached through another spelling.
        let other = d
            .join("..")
            .join(d.file_name().expect("named"))
            .join("in.jsonl");
        assert!(problem(&[Output::file("--plot", &other)]).is_some_and(|w| w.contains("STREAM")));
        let fresh = d.join("p.svg");
        assert!(
            problem(&[Output::file("--plot", &fresh), Output::file("-o", &fresh)])
                .is_some_and(|w| w.contains("--plot"))
        );
        assert!(problem(&[Output::folder("--svg", &input)]).is_some());
        assert!(problem(&[Output::file("--plot", &fresh), Output::folder("--svg", &d)]).is_none());
    }
}
