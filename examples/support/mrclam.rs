//! Where the MRCLAM examples find dataset 7: `$LPLACE_DATA/mrclam-dataset7`, else
//! `../shared/data/mrclam-dataset7` beside the repository; the data is never copied here.

use std::path::PathBuf;

/// The dataset 7 folder, or `None` after saying on stdout that it is absent (the examples then
/// exit 0: they are demonstrations, not checks).
pub fn dataset7() -> Option<PathBuf> {
    let dir = match std::env::var_os("LPLACE_DATA") {
        Some(d) => PathBuf::from(d).join("mrclam-dataset7"),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mrclam-dataset7"),
    };
    if dir.join("Barcodes.dat").exists() {
        Some(dir)
    } else {
        println!(
            "MRCLAM dataset 7 not found at {} — set LPLACE_DATA; skipping.",
            dir.display()
        );
        None
    }
}
