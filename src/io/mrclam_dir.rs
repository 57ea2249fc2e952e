//! Opens an MRCLAM dataset directory: the one place that reads MRCLAM files from disk. Parsing
//! stays in [`crate::io::mrclam`] (whose readers do no I/O); this module names the files
//! (`Barcodes.dat`, `Landmark_Groundtruth.dat`, `RobotN_{Odometry,Measurement,Groundtruth}.dat`),
//! reads them leniently (the `*_lenient` readers of [`crate::io::mrclam`], one pass: a malformed
//! line or an out-of-place time is skipped and returned with its path, never dropped silently) and merges each robot's files into
//! [`MetricFrame`]s. The CLI (`extract`, `grid`, `compare`, `fuse`), the examples and the
//! real-data tests all load MRCLAM through [`load`].
//!
//! May depend on: `io::mrclam`.
//!
//! # Complexity
//!
//! O(bytes) reading plus [`crate::io::mrclam::merge`] per robot; the files of one robot are
//! held in memory while merging.
//!
//! # Example
//!
//! ```no_run
//! use lplace::io::mrclam_dir;
//! let data = mrclam_dir::load("mrclam-dataset7".as_ref(), &[1])?;
//! for s in &data.skipped {
//!     eprintln!("{}:{}", s.path.display(), s.error);
//! }
//! println!("robot 1: {} frames", data.robots[0].frames.len());
//! # Ok::<(), mrclam_dir::DatasetError>(())
//! ```

use std::path::{Path, PathBuf};

use super::mrclam::{self, Barcodes, Lenient, MergeOptions, MrclamError};
use crate::grid::LandmarkTruth;
use crate::localize::{MetricFrame, TruthRow};
use std::collections::BTreeMap;

/// The landmark survey's file name.
pub const LANDMARKS: &str = "Landmark_Groundtruth.dat";

/// One robot's recording.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotLog {
    /// Robot (subject) number, 1–5; other robots' readings name it.
    pub robot: u32,
    /// Its frames ([`crate::io::mrclam::merge`]), readings of landmarks and robots.
    pub frames: Vec<MetricFrame>,
    /// Its Vicon ground truth.
    pub truth: Vec<TruthRow>,
    /// Readings with a barcode in neither list (misreads), dropped.
    pub misread: usize,
    /// Misread barcode → count.
    pub misread_barcodes: BTreeMap<u32, usize>,
    /// Landmark and robot readings kept.
    pub readings: usize,
}

/// A line skipped as malformed, with the file it is in.
#[derive(Debug)]
pub struct SkippedLine {
    /// The file.
    pub path: PathBuf,
    /// Why (carries the 1-based line number).
    pub error: MrclamError,
}

/// An MRCLAM directory, read.
#[derive(Debug)]
pub struct Dataset {
    /// Barcode → subject.
    pub barcodes: Barcodes,
    /// The surveyed landmarks (subjects 6–20); `None` when the directory has no
    /// `Landmark_Groundtruth.dat` (`extract` takes landmark positions from a map instead).
    pub landmarks: Option<Vec<LandmarkTruth>>,
    /// The requested robots, in the order asked.
    pub robots: Vec<RobotLog>,
    /// Every malformed line skipped, in file and line order.
    pub skipped: Vec<SkippedLine>,
    /// The directory read.
    pub dir: PathBuf,
}

impl Dataset {
    /// The landmark survey, for the commands that need it.
    ///
    /// # Errors
    /// [`DatasetError::MissingSurvey`] when the directory had no `Landmark_Groundtruth.dat`.
    pub fn survey(&self) -> Result<&[LandmarkTruth], DatasetError> {
        self.landmarks
            .as_deref()
            .ok_or_else(|| DatasetError::MissingSurvey {
                path: self.dir.join(LANDMARKS),
            })
    }
}

/// Why a dataset could not be read.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// A file could not be opened or read.
    #[error("{}: {source}", path.display())]
    Open {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A file could not be read to its end (a read error).
    #[error("{}: {source}", path.display())]
    Unreadable {
        /// The file.
        path: PathBuf,
        /// The reader's error (with its line).
        #[source]
        source: MrclamError,
    },
    /// The landmark survey is needed but the directory has none.
    #[error("{}: not found (the landmark survey is needed here)", path.display())]
    MissingSurvey {
        /// Where it was looked for.
        path: PathBuf,
    },
    /// A robot number outside 1–5.
    #[error("MRCLAM has robots 1 to 5, not {robot}")]
    NoSuchRobot {
        /// The number asked for.
        robot: u32,
    },
}

/// Reads the directory's barcodes and landmarks and the files of `robots` (each 1–5).
///
/// # Errors
/// [`DatasetError`] naming the file that could not be opened or parsed, or the robot number
/// that does not exist.
pub fn load(dir: &Path, robots: &[u32]) -> Result<Dataset, DatasetError> {
    if let Some(&robot) = robots.iter().find(|r| !(1..=5).contains(*r)) {
        return Err(DatasetError::NoSuchRobot { robot });
    }
    let mut skipped = Vec::new();
    let barcodes = read(dir, "Barcodes.dat", &mut skipped, |b| {
        mrclam::read_barcodes_lenient(b)
    })?;
    let landmarks = if dir.join(LANDMARKS).exists() {
        Some(read(dir, LANDMARKS, &mut skipped, |b| {
            mrclam::read_landmarks_lenient(b)
        })?)
    } else {
        None
    };
    let mut logs = Vec::with_capacity(robots.len());
    for &robot in robots {
        let odo = read(
            dir,
            &format!("Robot{robot}_Odometry.dat"),
            &mut skipped,
            |b| mrclam::read_odometry_lenient(b),
        )?;
        let meas = read(
            dir,
            &format!("Robot{robot}_Measurement.dat"),
            &mut skipped,
            |b| mrclam::read_measurements_lenient(b, &barcodes),
        )?;
        let truth = read(
            dir,
            &format!("Robot{robot}_Groundtruth.dat"),
            &mut skipped,
            |b| mrclam::read_groundtruth_lenient(b),
        )?;
        logs.push(RobotLog {
            robot,
            frames: mrclam::merge(&odo, &meas.rows, &truth, &MergeOptions::default()),
            truth,
            misread: meas.misread,
            misread_barcodes: meas.misread_barcodes,
            readings: meas.rows.len(),
        });
    }
    Ok(Dataset {
        barcodes,
        landmarks,
        robots: logs,
        skipped,
        dir: dir.to_path_buf(),
    })
}

/// Reads one file leniently; its malformed lines go to `skipped` with the path.
fn read<T>(
    dir: &Path,
    name: &str,
    skipped: &mut Vec<SkippedLine>,
    parse: impl FnOnce(&[u8]) -> Result<Lenient<T>, MrclamError>,
) -> Result<T, DatasetError> {
    let path = dir.join(name);
    let bytes = std::fs::read(&path).map_err(|source| DatasetError::Open {
        path: path.clone(),
        source,
    })?;
    match parse(&bytes) {
        Ok(Lenient {
            value,
            skipped: bad,
        }) => {
            skipped.extend(bad.into_iter().map(|error| SkippedLine {
                path: path.clone(),
                error,
            }));
            Ok(value)
        }
        Err(source) => Err(DatasetError::Unreadable { path, source }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A throwaway directory with a two-landmark, one-robot dataset; robot 1's odometry has one
    /// malformed line (line 3).
    fn tiny() -> PathBuf {
        let dir = std::env::temp_dir().join(format!("lplace-mrclam-dir-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let files = [
            ("Barcodes.dat", "# header\n1 5\n6 63\n7 81\n"),
            (
                "Landmark_Groundtruth.dat",
                "6 1.0 2.0 0.01 0.01\n7 3.0 -1.0 0.01 0.01\n",
            ),
            (
                "Robot1_Odometry.dat",
                "10.0 0.1 0.0\n10.5 0.1 0.0\nten 0.1 0.0\n11.0 0.0 0.0\n",
            ),
            (
                "Robot1_Measurement.dat",
                "10.5 63 2.0 0.1\n10.5 34 1.0 0.0\n",
            ),
            (
                "Robot1_Groundtruth.dat",
                "10.0 0.0 0.0 0.0\n11.0 0.1 0.0 0.0\n",
            ),
        ];
        for (name, text) in files {
            std::fs::write(dir.join(name), text).unwrap();
        }
        dir
    }

    #[test]
    fn loads_reports_skipped_lines_and_misreads() {
        let dir = tiny();
        let d = load(&dir, &[1]).unwrap();
        assert_eq!(d.landmarks.as_ref().map(Vec::len), Some(2));
        assert_eq!(d.robots.len(), 1);
        let r = &d.robots[0];
        assert_eq!((r.robot, r.misread, r.readings), (1, 1, 1));
        assert_eq!(r.misread_barcodes.get(&34), Some(&1));
        // The one bad odometry line is reported with its file and line, not dropped.
        assert_eq!(d.skipped.len(), 1);
        assert!(d.skipped[0].path.ends_with("Robot1_Odometry.dat"));
        assert!(matches!(
            d.skipped[0].error,
            MrclamError::Malformed { line: 3, .. }
        ));
        assert!(matches!(
            load(&dir, &[6]),
            Err(DatasetError::NoSuchRobot { robot: 6 })
        ));
        assert!(matches!(load(&dir, &[2]), Err(DatasetError::Open { .. })));
        std::fs::remove_file(dir.join(LANDMARKS)).unwrap();
        let d = load(&dir, &[1]).unwrap();
        assert!(d.landmarks.is_none());
        assert!(matches!(
            d.survey(),
            Err(DatasetError::MissingSurvey { .. })
        ));
        std::fs::remove_dir_all(&dir).ok();
    }
}
