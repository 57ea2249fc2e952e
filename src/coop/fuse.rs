//! Fusion of the robots' object grids (paper 002 §2.2 eq. (1) and §3) and the baselines the
//! paper compares it with.
//!
//! * [`fuse`]: the product t-norm `μ(p) = Π_i μ_i(p)`, non-idempotent so that positions all
//!   robots find possible reinforce each other, and a grid with a high bias (an unreliable robot)
//!   scales every cell almost alike and so hardly moves the result. The product is then divided
//!   by its height (the possibilistic normalisation the self grids use too): paper 002 does not
//!   spell this step out, but without it a fused grid of several robots sinks towards 0 and its
//!   floor stops reading as a bias. `1 − height` is the robots' conflict, reported in [`Fused`].
//!   Normalising does not move the centre of gravity of [`ObjectGrid::centre_of_gravity`], whose
//!   cut and weights are relative to the grid's range.
//! * [`average`] and [`weighted_average`]: the individual estimates averaged, plainly or
//!   weighted by each robot's self-localization reliability (paper 002 §4.4, `Δ^avg`, `Δ^wavg`).
//!
//! # Complexity
//!
//! [`fuse`]: O(robots · cells). The averages: O(robots).
//!
//! # Example
//!
//! ```
//! use lplace::coop::{fuse, GridGeometry, ObjectGrid};
//! let geo = GridGeometry { nx: 3, ny: 1, x0: 0.0, y0: 0.0, cell: 1.0 };
//! let a = ObjectGrid::new(geo, vec![0.1, 1.0, 0.5]).unwrap();
//! let b = ObjectGrid::new(geo, vec![0.8, 0.8, 1.0]).unwrap(); // unreliable: bias 0.8
//! let f = fuse(&[a, b]).unwrap();
//! // products 0.08, 0.8, 0.5, divided by the height 0.8
//! let want = [0.1, 1.0, 0.625];
//! assert!(f.grid.values().iter().zip(want).all(|(v, w)| (v - w).abs() < 1e-6));
//! assert!((f.conflict - 0.2).abs() < 1e-6);
//! ```

use super::{CoopError, ObjectGrid};
use serde::{Deserialize, Serialize};

/// The fused grid and the robots' conflict.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fused {
    /// The normalised product (height 1 unless every cell is 0).
    pub grid: ObjectGrid,
    /// `1 − height` of the product before normalisation, in [0, 1]: 0 when the robots agree
    /// somewhere completely, 1 when no position is possible for all of them.
    pub conflict: f32,
}

/// Fuses object grids by the normalised product (see the module docs). The result does not
/// depend on the order of the grids (up to rounding).
///
/// # Errors
/// [`CoopError::Empty`] for no grids, [`CoopError::GeometryMismatch`] when a grid does not
/// share the first one's geometry.
pub fn fuse(grids: &[ObjectGrid]) -> Result<Fused, CoopError> {
    let first = grids.first().ok_or(CoopError::Empty)?;
    let geo = *first.geometry();
    for (index, g) in grids.iter().enumerate() {
        if *g.geometry() != geo {
            return Err(CoopError::GeometryMismatch {
                index,
                nx: geo.nx,
                ny: geo.ny,
                found_nx: g.geometry().nx,
                found_ny: g.geometry().ny,
            });
        }
    }
    let mut values = first.values().to_vec();
    for g in &grids[1..] {
        for (v, w) in values.iter_mut().zip(g.values()) {
            *v *= w;
        }
    }
    let height = values.iter().copied().fold(0.0f32, f32::max);
    if height > 0.0 {
        let k = 1.0 / height;
        for v in &mut values {
            *v = (*v * k).min(1.0);
        }
    }
    let grid = ObjectGrid::new(geo, values).ok_or(CoopError::Empty)?;
    Ok(Fused {
        grid,
        conflict: (1.0 - height).clamp(0.0, 1.0),
    })
}

/// Plain average of point estimates; `None` when there are none.
pub fn average(points: &[(f32, f32)]) -> Option<(f32, f32)> {
    let w: Vec<f32> = vec![1.0; points.len()];
    weighted_average(points, &w)
}

/// Average of point estimates weighted by `weights` (paper 002: self-localization reliability).
/// Non-finite or negative weights count as 0; when every weight is 0 the plain average is
/// returned. `None` when there is no point.
pub fn weighted_average(points: &[(f32, f32)], weights: &[f32]) -> Option<(f32, f32)> {
    if points.is_empty() {
        return None;
    }
    let w = |k: usize| {
        let v = weights.get(k).copied().unwrap_or(0.0);
        if v.is_finite() && v > 0.0 {
            v as f64
        } else {
            0.0
        }
    };
    let total: f64 = (0..points.len()).map(w).sum();
    let (mut sx, mut sy) = (0.0f64, 0.0f64);
    for (k, p) in points.iter().enumerate() {
        let wk = if total > 0.0 {
            w(k) / total
        } else {
            1.0 / points.len() as f64
        };
        sx += wk * p.0 as f64;
        sy += wk * p.1 as f64;
    }
    Some((sx as f32, sy as f32))
}
