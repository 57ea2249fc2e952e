//! Baselines the Fuzzy Position Grid is compared with: a Monte Carlo particle filter after
//! paper 004 ([`pf`]) and Fuzzy Reverse Monte Carlo Localization after paper 001 ([`rmcl`]).
//! Both are [`crate::localize::Localizer`]s, so `crate::localize::drive` steps, kidnaps and
//! scores them exactly as it does the grid.
//!
//! This module owns the error type shared by the two methods and the input checks every
//! [`crate::localize::Localizer`] must make (a rejected input leaves the belief unchanged). It
//! may depend on `grid` (reading and landmark types, the motion check; the grid stage of R-MCL),
//! `localize` (the trait) and `core::rng` (the seeded generator); it never does I/O.
//!
//! # Complexity
//!
//! See [`pf`] (O(particles) per reading) and [`rmcl`] (O(cells) per frame).
//!
//! # Example
//!
//! ```
//! use lplace::baseline::{ParticleFilter, PfConfig};
//! use lplace::core::Odometry;
//! use lplace::grid::{Landmark, LandmarkTable};
//! use lplace::localize::Localizer;
//! let table = LandmarkTable::new(vec![Landmark { id: 1, x: 0.0, y: 0.0 }]).unwrap();
//! let mut pf = ParticleFilter::new(&table, &PfConfig::default(), [-2.0, -2.0, 2.0, 2.0], 7)?;
//! // A NaN motion is rejected, not absorbed.
//! let bad = Odometry { forward: f64::NAN, left: 0.0, turn: 0.0 };
//! assert!(pf.predict(&bad, 0.1).is_err());
//! # Ok::<(), lplace::baseline::BaselineError>(())
//! ```

pub mod pf;
pub mod rmcl;

pub use pf::{ParticleFilter, PfConfig};
pub use rmcl::{FuzzyRmcl, RmclConfig};

use crate::core::Odometry;
use crate::grid::{GridError, LandmarkTable, Observation};

/// Everything a baseline rejects. Variants carry the offending data; nothing here panics.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaselineError {
    /// A configuration value is out of range.
    #[error("bad baseline configuration: `{field}` {reason}")]
    BadConfig {
        /// Name of the field.
        field: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The RON text of a configuration does not parse.
    #[error("baseline configuration, line {line} column {column}: {problem}")]
    Ron {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong there (an unknown key names the nearest known one).
        problem: crate::core::config::RonProblem,
    },
    /// The extent is not `x_min < x_max`, `y_min < y_max`, all finite.
    #[error("bad bounds {0:?}: need finite x_min < x_max, y_min < y_max")]
    BadBounds([f32; 4]),
    /// A rejected reading or motion — the input checks every localizer shares
    /// ([`Observation::check`], [`crate::grid::check_motion`], an unknown landmark) — or an error of
    /// R-MCL's grid stage.
    #[error("{0}")]
    Grid(#[from] GridError),
}

/// Checks bounds as [`crate::grid::FuzzyGrid::new`] expects them.
pub(crate) fn check_bounds(b: [f32; 4]) -> Result<(), BaselineError> {
    if b.iter().any(|v| !v.is_finite()) || b[2] <= b[0] || b[3] <= b[1] {
        return Err(BaselineError::BadBounds(b));
    }
    Ok(())
}

/// Checks an odometry increment and its elapsed time ([`crate::grid::check_motion`]).
pub(crate) fn check_motion(odometry: &Odometry, dt: f64) -> Result<(), BaselineError> {
    Ok(crate::grid::check_motion(odometry, dt)?)
}

/// A checked reading: landmark position and the finite, non-negative values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Reading {
    pub lx: f64,
    pub ly: f64,
    pub range: Option<f64>,
    pub bearing: Option<f64>,
}

/// Looks the landmark up and checks the values of an observation.
pub(crate) fn check_observation(
    table: &LandmarkTable,
    obs: &Observation,
) -> Result<Reading, BaselineError> {
    let m = table
        .get(obs.landmark)
        .ok_or(GridError::UnknownLandmark(obs.landmark))?;
    obs.check()?;
    Ok(Reading {
        lx: m.x as f64,
        ly: m.y as f64,
        range: obs.range.map(f64::from),
        bearing: obs.bearing.map(f64::from),
    })
}

/// Maps the configuration reader's error onto [`BaselineError::Ron`].
pub(crate) fn ron_error(e: crate::core::config::RonError) -> BaselineError {
    BaselineError::Ron {
        line: e.line,
        column: e.column,
        problem: e.problem,
    }
}
