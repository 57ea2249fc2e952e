//! Where data files are found: a relative path that does not exist from the current folder is
//! looked up under `$LPLACE_DATA` (the folder of the public data sets, see docs/data.md), as the
//! tests do, so `lplace grid --from-dir mrclam-dataset7 …` works from anywhere.

use std::path::{Path, PathBuf};

/// `path` as given when it exists (or is `-`, or absolute); else `$LPLACE_DATA/path` when that
/// exists; else `path` unchanged, so that errors name what the user wrote.
pub fn resolve(path: &Path) -> PathBuf {
    resolve_in(
        path,
        std::env::var_os("LPLACE_DATA").as_deref().map(Path::new),
    )
}

fn resolve_in(path: &Path, data: Option<&Path>) -> PathBuf {
    if path.as_os_str() == "-" || path.is_absolute() || path.exists() {
        return path.to_path_buf();
    }
    match data.map(|d| d.join(path)) {
        Some(p) if p.exists() => p,
        _ => path.to_path_buf(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looks_under_the_data_folder_only_for_what_is_not_here() {
        let data = std::env::temp_dir().join(format!("lplace-data-{}", std::process::id()));
        std::fs::create_dir_all(data.join("set")).expect("temp is writable");
        let rel = Path::new("set");
        assert_eq!(resolve_in(rel, Some(&data)), data.join("set"));
        assert_eq!(
            resolve_in(Path::new("nothing"), Some(&data)),
            Path::new("nothing")
        );
        assert_eq!(resolve_in(rel, None), rel);
        // What exists here wins over the data folder.
        assert_eq!(
            resolve_in(Path::new("Cargo.toml"), Some(&data)),
            Path::new("Cargo.toml")
        );
        assert_eq!(resolve_in(Path::new("-"), Some(&data)), Path::new("-"));
    }
}
