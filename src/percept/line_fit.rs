//! Orthogonal (total) least-squares line fitting in the plane.
//!
//! This is the one geometric primitive every extractor of paper 003 §4 rests on
//! (beacon cuts, structured-light lines, sonar walls). It depends only on
//! `nalgebra` point types and `thiserror`; it knows nothing about sensors,
//! percepts or degrees.
//!
//! Ordinary least squares `y = a·x + b` measures residuals vertically, so it
//! fails on vertical lines and its answer changes when the frame rotates. The
//! total least-squares line minimises the sum of squared *orthogonal*
//! distances instead: it passes through the centroid and its normal is the
//! eigenvector of the 2×2 scatter matrix with the smaller eigenvalue. We use
//! the closed form of that eigenvector (a half-angle `atan2`), which is exact
//! for a symmetric 2×2 matrix and cheaper than a general eigen-solver, and we
//! recompute the residual sum from the points rather than from the eigenvalue
//! formula because the latter loses all precision when the smaller eigenvalue
//! is many orders of magnitude below the larger one (long, clean walls).

use nalgebra::{Point2, Vector2};
use thiserror::Error;

/// Why a set of points has no well-defined best-fit line.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
pub enum LineFitError {
    /// Fewer than two points were given.
    #[error("a line needs at least two points, got {count}")]
    TooFewPoints {
        /// Number of points supplied.
        count: usize,
    },
    /// Every point is the same point, so no direction is defined.
    #[error("all {count} points coincide; no direction is defined")]
    Coincident {
        /// Number of points supplied.
        count: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("point {index} has a non-finite coordinate ({x}, {y})")]
    NonFinite {
        /// Index of the first offending point.
        index: usize,
        /// Its x coordinate.
        x: f64,
        /// Its y coordinate.
        y: f64,
    },
    /// The coordinates are finite but so large that the scatter overflows.
    #[error("the scatter of {count} points overflows f64")]
    Overflow {
        /// Number of points supplied.
        count: usize,
    },
}

/// The best-fit line of a point set, `normal · p = offset`.
///
/// Units are those of the input coordinates (metres for scans, pixels for
/// images); angles are radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineFit {
    /// Centroid of the points; the fitted line passes through it.
    pub centroid: Point2<f64>,
    /// Unit direction of the line, canonicalised so that `direction.x > 0`
    /// or, for a vertical line, `direction == (0, 1)`.
    pub direction: Vector2<f64>,
    /// Angle of `direction` from the +x axis, in `(−π/2, π/2]`.
    pub angle: f64,
    /// Unit normal, `direction` rotated by +90°.
    pub normal: Vector2<f64>,
    /// Signed distance of the line from the origin along `normal`.
    pub offset: f64,
    /// `dy/dx` of the line; `None` when the line is vertical (|dx| < 1e-12).
    pub slope: Option<f64>,
    /// Root-mean-square orthogonal distance of the points from the line
    /// (population form, divides by the point count).
    pub rms_dispersion: f64,
    /// Root-mean-square extent of the points *along* the line; compare with
    /// `rms_dispersion` to see whether the set is line-like at all.
    pub rms_spread: f64,
    /// Number of points fitted.
    pub count: usize,
}

impl LineFit {
    /// Signed orthogonal distance of `p` from the line (positive on the
    /// `normal` side).
    pub fn signed_distance(&self, p: &Point2<f64>) -> f64 {
        self.normal.dot(&p.coords) - self.offset
    }
}

/// Fits a line to `points` by orthogonal least squares.
///
/// # Errors
/// [`LineFitError`] when fewer than two distinct points are given, a
/// coordinate is not finite, or the scatter overflows. Never panics.
///
/// # Complexity
/// Three passes over the points, `O(n)` time, `O(1)` extra space, no allocation.
///
/// # Example
/// ```
/// use lplace::percept::line_fit::fit_line;
/// use nalgebra::Point2;
/// // A vertical line x = 2: ordinary least squares would fail here.
/// let pts = [Point2::new(2.0, 0.0), Point2::new(2.0, 1.0), Point2::new(2.0, 3.0)];
/// let fit = fit_line(&pts).unwrap();
/// assert!(fit.slope.is_none());
/// assert!((fit.angle - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
/// assert!(fit.rms_dispersion < 1e-12);
/// ```
pub fn fit_line(points: &[Point2<f64>]) -> Result<LineFit, LineFitError> {
    let count = points.len();
    let c = centroid(points)?;
    let (sxx, syy, sxy) = scatter(points, c);
    if !(sxx.is_finite()
        && syy.is_finite()
        && sxy.is_finite()
        && c.x.is_finite()
        && c.y.is_finite())
    {
        return Err(LineFitError::Overflow { count });
    }
    // Major-axis angle of the scatter ellipse.
    let mut angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    if angle <= -std::f64::consts::FRAC_PI_2 {
        angle += std::f64::consts::PI;
    }
    let (s, co) = angle.sin_cos();
    let (direction, slope) = if co.abs() < 1e-12 {
        (Vector2::new(0.0, 1.0), None)
    } else {
        (Vector2::new(co, s), Some(s / co))
    };
    let normal = Vector2::new(-direction.y, direction.x);
    let offset = normal.dot(&c.coords);
    let (mut ortho, mut along) = (0.0_f64, 0.0_f64);
    for p in points {
        let d = p - c;
        let o = normal.dot(&d);
        let a = direction.dot(&d);
        ortho += o * o;
        along += a * a;
    }
    let n = count as f64;
    let rms_dispersion = (ortho / n).sqrt();
    let rms_spread = (along / n).sqrt();
    if !(rms_dispersion.is_finite() && rms_spread.is_finite() && offset.is_finite()) {
        return Err(LineFitError::Overflow { count });
    }
    Ok(LineFit {
        centroid: c,
        direction,
        angle,
        normal,
        offset,
        slope,
        rms_dispersion,
        rms_spread,
        count,
    })
}

/// The points' centroid, or why there is no line through them (fewer than two, all the same,
/// a non-finite coordinate).
fn centroid(points: &[Point2<f64>]) -> Result<Point2<f64>, LineFitError> {
    let count = points.len();
    if count < 2 {
        return Err(LineFitError::TooFewPoints { count });
    }
    let first = points[0];
    let mut distinct = false;
    // Sums are taken relative to the first point: points sharing an exact
    // coordinate (a vertical or horizontal wall) then have an exactly zero
    // spread in it, and far-from-origin data loses less precision.
    let (mut sx, mut sy) = (0.0_f64, 0.0_f64);
    for (index, p) in points.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(LineFitError::NonFinite {
                index,
                x: p.x,
                y: p.y,
            });
        }
        distinct |= *p != first;
        sx += p.x - first.x;
        sy += p.y - first.y;
    }
    if !distinct {
        return Err(LineFitError::Coincident { count });
    }
    let n = count as f64;
    Ok(Point2::new(first.x + sx / n, first.y + sy / n))
}

/// The centred second moments `(Σdx², Σdy², Σdx·dy)` about `c`. A second pass: the one-pass
/// formula Σx² − n·x̄² cancels catastrophically for scans far from the map origin.
fn scatter(points: &[Point2<f64>], c: Point2<f64>) -> (f64, f64, f64) {
    let (mut sxx, mut syy, mut sxy) = (0.0_f64, 0.0_f64, 0.0_f64);
    for p in points {
        let (dx, dy) = (p.x - c.x, p.y - c.y);
        sxx += dx * dx;
        syy += dy * dy;
        sxy += dx * dy;
    }
    (sxx, syy, sxy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn horizontal_line_has_zero_slope_and_offset_equal_to_height() {
        // y = 3 for x in 0..5: normal (0, 1), offset 3, slope 0.
        let pts: Vec<_> = (0..5).map(|i| Point2::new(i as f64, 3.0)).collect();
        let f = fit_line(&pts).unwrap();
        assert!(f.slope.unwrap().abs() < 1e-12);
        assert!((f.offset - 3.0).abs() < 1e-12);
        assert!(f.rms_dispersion < 1e-12);
        // Spread of 0..4 about 2: sqrt((4+1+0+1+4)/5) = sqrt(2).
        assert!((f.rms_spread - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn slope_of_diagonal() {
        // y = 2x + 1 → slope 2, angle atan(2).
        let pts: Vec<_> = (0..4)
            .map(|i| Point2::new(i as f64, 2.0 * i as f64 + 1.0))
            .collect();
        let f = fit_line(&pts).unwrap();
        assert!((f.slope.unwrap() - 2.0).abs() < 1e-12);
        assert!((f.angle - 2f64.atan()).abs() < 1e-12);
        // Distance from origin to 2x − y + 1 = 0 is 1/√5.
        assert!((f.offset.abs() - 1.0 / 5f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn two_parallel_rows_give_half_gap_dispersion() {
        // Points on y = ±0.5, long in x: line y = 0, every point 0.5 away.
        let mut pts = Vec::new();
        for i in 0..10 {
            pts.push(Point2::new(i as f64, 0.5));
            pts.push(Point2::new(i as f64, -0.5));
        }
        let f = fit_line(&pts).unwrap();
        assert!((f.rms_dispersion - 0.5).abs() < 1e-12);
    }

    #[test]
    fn degenerate_inputs_are_typed_errors() {
        assert_eq!(fit_line(&[]), Err(LineFitError::TooFewPoints { count: 0 }));
        let p = Point2::new(1.0, 1.0);
        assert_eq!(fit_line(&[p]), Err(LineFitError::TooFewPoints { count: 1 }));
        assert_eq!(
            fit_line(&[p, p, p]),
            Err(LineFitError::Coincident { count: 3 })
        );
        assert!(matches!(
            fit_line(&[p, Point2::new(f64::NAN, 0.0)]),
            Err(LineFitError::NonFinite { index: 1, .. })
        ));
        assert_eq!(
            fit_line(&[Point2::new(-1e300, 0.0), Point2::new(1e300, 1.0)]),
            Err(LineFitError::Overflow { count: 2 })
        );
    }
}
