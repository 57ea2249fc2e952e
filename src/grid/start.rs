//! Starting the grid from a known pose (tracking) instead of total ignorance: the belief is the
//! one cell holding the position, with the heading known exactly (under
//! [`Shift::Lattice`](super::Shift) the lattice is moved so that this cell's centre is the
//! position). Used to compare localizers
//! when all of them start from the same known first pose (`lplace compare --start-at-truth`).
//!
//! # Complexity
//!
//! O(cells).

use super::{FuzzyGrid, GridError};

impl FuzzyGrid {
    /// Forgets the belief and puts the robot at `(x, y)` with heading `theta` (radians): that
    /// cell gets possibility 1 and the heading set `⟨theta, 0, 0, 1, 0⟩`, every other cell 0;
    /// pending motion is dropped. The floor (`GridConfig::floor`) comes back with the next
    /// update, as after any update.
    ///
    /// # Errors
    /// [`GridError::BadConfig`] (field `start`) when the position is outside the grid or a
    /// value is not finite; the belief is then unchanged.
    pub fn start_at(&mut self, x: f32, y: f32, theta: f32) -> Result<(), GridError> {
        let outside = GridError::BadConfig {
            field: "start",
            reason: "the start pose must be finite and inside the grid",
        };
        if !theta.is_finite() {
            return Err(outside);
        }
        let (c, r) = self.start_cell(x, y).ok_or(outside)?;
        self.reset();
        self.centre_lattice_on(x, y);
        self.h.fill(0.0);
        let k = r * self.nx + c;
        self.h[k] = 1.0;
        self.theta[k] = crate::core::angle::wrap_pi_f32(theta);
        self.delta[k] = 0.0;
        self.bias[k] = 0.0;
        Ok(())
    }

    /// The cell that holds `(x, y)` once the belief is reset, and, under
    /// [`Shift::Lattice`](super::Shift), the lattice centred on the point.
    fn start_cell(&self, x: f32, y: f32) -> Option<(usize, usize)> {
        if self.cfg.shift == super::Shift::Cells {
            return self.cell_of(x, y);
        }
        let [cx, cy] = self.corner;
        let s = self.cell;
        let at = |v: f32, c: f32, n: usize| {
            let k = ((v - c) / s - 0.5).round();
            (k >= 0.0 && k < n as f32).then_some(k as usize)
        };
        Some((at(x, cx, self.nx)?, at(y, cy, self.ny)?))
    }
}

#[cfg(test)]
mod tests {
    use crate::grid::{FuzzyGrid, GridConfig};

    #[test]
    fn starts_in_the_cell_of_the_pose_and_rejects_outside() {
        let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 4.0, 3.0]).unwrap();
        g.start_at(1.23, 2.07, 0.5).unwrap();
        let e = g.estimate();
        // The cell (12, 20) spans [1.2, 1.3] × [2.0, 2.1]: its centre is the estimate.
        assert!(
            (e.x - 1.25).abs() < 1e-5 && (e.y - 2.05).abs() < 1e-5,
            "{e:?}"
        );
        assert!((e.theta - 0.5).abs() < 1e-5, "{e:?}");
        assert!(e.reliability > 0.9, "{e:?}");
        assert_eq!(g.possibility(11, 20), 0.0);
        let before = g.possibilities().to_vec();
        assert!(g.start_at(5.0, 1.0, 0.0).is_err());
        assert!(g.start_at(1.0, 1.0, f32::NAN).is_err());
        assert_eq!(g.possibilities(), &before[..]);
    }
}
