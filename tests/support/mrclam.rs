//! A tiny MRCLAM directory written into scratch space, shared by the tests that need one
//! without the real data set: robot 1 sees landmark 6 (barcode 63) at (2, 0) from the origin.

use std::path::{Path, PathBuf};

/// Writes `Barcodes.dat` and robot 1's files into `dir` (created), with `odometry` as
/// `Robot1_Odometry.dat`; returns `dir`.
pub fn tiny_dir(dir: &Path, odometry: &str) -> PathBuf {
    std::fs::create_dir_all(dir).expect("scratch space is writable");
    let w = |f: &str, s: &str| std::fs::write(dir.join(f), s).expect("scratch space is writable");
    w("Barcodes.dat", "# Subject # Barcode #\n1 5\n6 63\n");
    w("Robot1_Odometry.dat", odometry);
    w(
        "Robot1_Measurement.dat",
        "# t barcode range bearing\n10.5 63 2.0 0.0\n10.6 34 1.0 0.0\n11.0 63 2.0 0.0\n",
    );
    w(
        "Robot1_Groundtruth.dat",
        "10.0 0.0 0.0 0.0\n11.0 0.0 0.0 0.0\n12.0 0.0 0.0 0.0\n",
    );
    dir.to_path_buf()
}
