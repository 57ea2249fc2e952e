//! Cooperative object localization (paper 002) on hand-worked cases: the sup formula on tiny
//! self grids (golden values worked out by hand, and a brute-force reference that samples the
//! headings), fusion by product, the averages, and the run-length code.

use lplace::coop::rle::{decode, encode, RleError};
use lplace::coop::{
    average, fuse, object_grid, weighted_average, CoopConfig, CoopError, GridGeometry, ObjectGrid,
    ObjectReading,
};
use lplace::grid::{FuzzyGrid, GridConfig, SensorModel, Trapezoid};
use proptest::prelude::*;
use std::f32::consts::{FRAC_PI_2, PI};

const CRISP: SensorModel = SensorModel {
    core_abs: 0.0,
    core_rel: 0.0,
    slope_abs: 0.0,
    slope_rel: 0.0,
    bias: 0.0,
};

/// A self grid over `[0, w] × [0, h]` (0.1 m cells) where nothing is possible.
fn empty_grid(w: f32, h: f32) -> FuzzyGrid {
    let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, w, h]).unwrap();
    g.possibilities_mut().fill(0.0);
    g
}

fn put(g: &mut FuzzyGrid, col: usize, row: usize, h: f32, heading: Trapezoid) {
    let nx = g.nx();
    g.possibilities_mut()[row * nx + col] = h;
    g.set_heading_set(col, row, heading);
}

#[test]
fn crisp_golden_case_matches_the_hand_worked_cells() {
    // 5×5 cells of 0.1 m. Robot possibly at cell (1, 1) facing +x (possibility 1) or at cell
    // (3, 2) facing +y (possibility 0.6); crisp heading sets, crisp reading ρ = 0.2 m, φ = 0.
    // A cell p is on the digital circle when |d − ρ| ≤ s/2 = 0.05 and in the direction θ + φ
    // within the half angle atan(0.05 / d) it subtends.
    // From (1, 1): offset (2, 0): d = 0.2, ψ = 0 → cell (3, 1) = 1.
    //   (2, 1): d = 0.2236 on the circle, but ψ = atan(0.5) = 0.464 > atan(0.05/0.2236) = 0.220.
    //   (1, 1): d = 0.141, |d − ρ| = 0.059 > 0.05: off the circle.
    // From (3, 2): offset (0, 2): d = 0.2, ψ = π/2 = θ → cell (3, 4) = 0.6.
    // Everything else 0 (reliability 1, sensor biases 0: floor 0).
    let mut g = empty_grid(0.5, 0.5);
    put(&mut g, 1, 1, 1.0, Trapezoid::new(0.0, 0.0, 0.0, 1.0, 0.0));
    put(
        &mut g,
        3,
        2,
        0.6,
        Trapezoid::new(FRAC_PI_2, 0.0, 0.0, 1.0, 0.0),
    );
    let cfg = CoopConfig {
        range: CRISP,
        bearing: CRISP,
        ..CoopConfig::default()
    };
    let o = object_grid(
        &g,
        1.0,
        ObjectReading {
            range: 0.2,
            bearing: 0.0,
        },
        &cfg,
    )
    .unwrap();
    for row in 0..5 {
        for col in 0..5 {
            let want = match (col, row) {
                (3, 1) => 1.0,
                (3, 4) => 0.6,
                _ => 0.0,
            };
            assert_eq!(o.value(col, row), want, "cell ({col}, {row})");
        }
    }
}

#[test]
fn certain_robot_facing_x_sees_the_object_one_metre_ahead() {
    // Robot certainly in cell (5, 10) (centre (0.55, 1.05)) with heading core 0.1, flank 0.1;
    // default sensor models (range core 0.1 + 5 %, flank 0.2 + 15 %; bearing core 0.06, flank
    // 0.1; biases 0.1) and self reliability 1: floor β = 1 − min(1 − 0.1, 1) = 0.1.
    let mut g = empty_grid(3.0, 2.0);
    put(&mut g, 5, 10, 1.0, Trapezoid::new(0.0, 0.1, 0.1, 1.0, 0.0));
    let cfg = CoopConfig::default();
    let o = object_grid(
        &g,
        1.0,
        ObjectReading {
            range: 1.0,
            bearing: 0.0,
        },
        &cfg,
    )
    .unwrap();
    // One metre ahead: cell (15, 10), d = 1 = ρ, ψ = 0 = θ → 1.
    assert_eq!(o.value(15, 10), 1.0);
    assert!((o.floor() - 0.1).abs() < 1e-6);
    // Cell (15, 13): d = hypot(1, 0.3) = 1.04403 (in the range core ± 0.125), ψ = 0.291457,
    // half angle atan(0.05 / 1.04403) = 0.047854. Headings allowed: centre 0.291457, core
    // 0.06 + 2 · 0.047854 = 0.155708, flank 0.1; own heading set: centre 0, core 0.1, flank 0.1.
    // Supports reach 0.05 + 0.1 + 0.077854 + 0.1 = 0.327854, so the flanks cross at
    // (0.327854 − 0.291457) / (0.1 + 0.1) = 0.181985.
    assert!(
        (o.value(15, 13) - 0.181985).abs() < 1e-3,
        "{}",
        o.value(15, 13)
    );
    // Behind the robot: only the floor.
    assert!((o.value(0, 10) - 0.1).abs() < 1e-6);
    let (x, y) = o.centre_of_gravity(0.5).unwrap();
    assert!(
        (x - 1.55).abs() < 0.03 && (y - 1.05).abs() < 0.03,
        "({x}, {y})"
    );
}

#[test]
fn the_floor_is_one_minus_the_least_reliability() {
    let mut g = empty_grid(1.0, 1.0);
    put(&mut g, 2, 2, 1.0, Trapezoid::new(0.0, 0.1, 0.1, 1.0, 0.0));
    let r = ObjectReading {
        range: 0.5,
        bearing: 0.0,
    };
    let cfg = CoopConfig::default(); // biases 0.1: observation reliability 0.9
    let o = object_grid(&g, 0.3, r, &cfg).unwrap();
    assert!((o.floor() - 0.7).abs() < 1e-6); // 1 − min(0.9, 0.3)
    let literal = CoopConfig {
        self_reliability_in_floor: false,
        ..CoopConfig::default()
    };
    let o = object_grid(&g, 0.3, r, &literal).unwrap();
    assert!((o.floor() - 0.1).abs() < 1e-6);
    // A robot that knows nothing of itself says nothing about the object.
    let o = object_grid(&g, 0.0, r, &cfg).unwrap();
    assert!(o.values().iter().all(|&v| v == 1.0));
}

#[test]
fn bad_readings_are_errors_not_panics() {
    let g = empty_grid(1.0, 1.0);
    let cfg = CoopConfig::default();
    for (range, bearing, rel) in [
        (f32::NAN, 0.0, 1.0),
        (-1.0, 0.0, 1.0),
        (1.0, f32::INFINITY, 1.0),
        (1.0, 0.0, 1.5),
        (1.0, 0.0, f32::NAN),
    ] {
        let e = object_grid(&g, rel, ObjectReading { range, bearing }, &cfg).unwrap_err();
        assert!(matches!(e, CoopError::BadReading { .. }), "{e}");
    }
    // A huge range is fine: nothing falls on the grid, only the floor remains.
    let o = object_grid(
        &g,
        1.0,
        ObjectReading {
            range: 1e9,
            bearing: 0.0,
        },
        &cfg,
    )
    .unwrap();
    assert!(o.values().iter().all(|&v| (v - 0.1).abs() < 1e-6));
}

/// Trapezoid membership of a distance `u ≥ 0` from the centre, height 1, written out.
fn ramp(u: f32, core: f32, slope: f32) -> f32 {
    let half = 0.5 * core;
    if u <= half {
        1.0
    } else if slope > 0.0 && u < half + slope {
        1.0 - (u - half) / slope
    } else {
        0.0
    }
}

fn wrap(a: f32) -> f32 {
    let r = (a + PI).rem_euclid(2.0 * PI) - PI;
    if r <= -PI {
        r + 2.0 * PI
    } else {
        r
    }
}

/// Paper 002's sup formula evaluated the slow way: every cell p, every cell q, the headings θ
/// sampled every 2π/7200 (plus the two set centres).
fn brute_force(g: &FuzzyGrid, rel: f32, r: ObjectReading, cfg: &CoopConfig) -> Vec<f32> {
    let s = g.cell_size();
    let beta = 1.0 - (1.0 - cfg.range.bias.max(cfg.bearing.bias)).min(rel);
    let (rc, rs) = (
        cfg.range.core_abs + cfg.range.core_rel * r.range,
        cfg.range.slope_abs + cfg.range.slope_rel * r.range,
    );
    let (bc, bs) = (cfg.bearing.core_abs, cfg.bearing.slope_abs);
    let mut out = Vec::new();
    for pr in 0..g.ny() {
        for pc in 0..g.nx() {
            let (px, py) = g.cell_center(pc, pr);
            let mut best = beta;
            for qr in 0..g.ny() {
                for qc in 0..g.nx() {
                    let hs = g.heading_set(qc, qr).unwrap();
                    if hs.shape.height <= 0.0 {
                        continue;
                    }
                    let (qx, qy) = g.cell_center(qc, qr);
                    let d = (px - qx).hypot(py - qy);
                    let psi = (py - qy).atan2(px - qx);
                    // The cell spans d ± s/2 and ψ ± atan(s/2 / d).
                    let range_m = ramp(((d - r.range).abs() - 0.5 * s).max(0.0), rc, rs);
                    let delta = (0.5 * s).atan2(d);
                    let self_m = |th: f32| {
                        hs.shape.height
                            * hs.shape.bias.max(ramp(
                                wrap(th - hs.center).abs(),
                                hs.shape.core,
                                hs.shape.slope,
                            ))
                    };
                    let bear_m =
                        |th: f32| ramp((wrap(psi - th - r.bearing).abs() - delta).max(0.0), bc, bs);
                    let mut sup = 0.0f32;
                    let n = 7200;
                    for k in 0..n + 2 {
                        let th = match k {
                            k if k < n => -PI + 2.0 * PI * k as f32 / n as f32,
                            k if k == n => hs.center,
                            _ => psi - r.bearing,
                        };
                        sup = sup.max(self_m(th).min(bear_m(th)));
                    }
                    best = best.max(range_m.min(sup));
                }
            }
            out.push(best);
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    #[test]
    fn sup_formula_matches_brute_force(
        cells in proptest::collection::vec(
            (0.0f32..1.0, -3.1f32..3.1, 0.0f32..1.0, 0.2f32..1.0, 0.0f32..0.5), 36),
        rho in 0.05f32..0.7,
        phi in -3.1f32..3.1,
        rel in 0.0f32..1.0,
        widths in (0.0f32..0.3, 0.0f32..0.2, 0.0f32..0.3, 0.2f32..0.5, 0.0f32..0.3),
    ) {
        let mut g = empty_grid(0.6, 0.6);
        for (k, &(h, c, core, slope, b)) in cells.iter().enumerate() {
            // About a third of the cells impossible, as in a converged grid.
            let h = if h < 0.3 { 0.0 } else { h };
            put(&mut g, k % 6, k / 6, h, Trapezoid::new(c, core, slope, 1.0, b));
        }
        let (rcore, rslope, bcore, bslope, bias) = widths;
        let cfg = CoopConfig {
            range: SensorModel { core_abs: rcore, core_rel: 0.05, slope_abs: rslope, slope_rel: 0.1, bias },
            bearing: SensorModel { core_abs: bcore, core_rel: 0.0, slope_abs: bslope, slope_rel: 0.0, bias: 0.0 },
            ..CoopConfig::default()
        };
        let r = ObjectReading { range: rho, bearing: phi };
        let fast = object_grid(&g, rel, r, &cfg).unwrap();
        let slow = brute_force(&g, rel, r, &cfg);
        for (i, (&a, &b)) in fast.values().iter().zip(&slow).enumerate() {
            // Sampling can only miss the sup, by at most half a step times the steepest
            // flank (1/0.2): 5 · π/7200 ≈ 0.0022.
            prop_assert!(a - b >= -1e-4 && a - b <= 5e-3, "cell {i}: fast {a}, brute force {b}");
        }
    }
}

fn geo(nx: usize, ny: usize) -> GridGeometry {
    GridGeometry {
        nx,
        ny,
        x0: 0.0,
        y0: 0.0,
        cell: 1.0,
    }
}

#[test]
fn fusing_with_ignorance_changes_nothing() {
    let a = ObjectGrid::new(geo(4, 1), vec![0.1, 0.4, 1.0, 0.3]).unwrap();
    let b = ObjectGrid::new(geo(4, 1), vec![0.5, 1.0, 0.5, 0.2]).unwrap();
    let with = fuse(&[a.clone(), ObjectGrid::ignorance(geo(4, 1)), b.clone()]).unwrap();
    let without = fuse(&[a, b]).unwrap();
    assert_eq!(with, without);
}

#[test]
fn product_then_height_normalisation_by_hand() {
    // 0.5·0.8 = 0.4, 1.0·0.5 = 0.5, 0.2·1.0 = 0.2; height 0.5 → 0.8, 1, 0.4; conflict 0.5.
    let a = ObjectGrid::new(geo(3, 1), vec![0.5, 1.0, 0.2]).unwrap();
    let b = ObjectGrid::new(geo(3, 1), vec![0.8, 0.5, 1.0]).unwrap();
    let f = fuse(&[a, b]).unwrap();
    for (v, w) in f.grid.values().iter().zip([0.8, 1.0, 0.4]) {
        assert!((v - w).abs() < 1e-6, "{v} vs {w}");
    }
    assert!((f.conflict - 0.5).abs() < 1e-6);
    assert_eq!(fuse(&[]).unwrap_err(), CoopError::Empty);
    let odd = ObjectGrid::ignorance(geo(2, 1));
    assert!(matches!(
        fuse(&[ObjectGrid::ignorance(geo(3, 1)), odd]),
        Err(CoopError::GeometryMismatch { index: 1, .. })
    ));
}

/// A 1×10 grid with a peak of 1 at `at` over a floor `bias`.
fn peaked(at: usize, bias: f32) -> ObjectGrid {
    let mut v = vec![bias; 10];
    v[at] = 1.0;
    ObjectGrid::new(geo(10, 1), v).unwrap()
}

#[test]
fn an_unreliable_grid_is_discounted() {
    // Robot A (bias 0.1) sees the object at cell 2, robot B at cell 7. With B as reliable as A
    // the two peaks tie (0.1 · 1 each) and the estimate falls between them; with B's bias at
    // 0.8, cell 2 keeps 1 · 0.8 against 0.1 · 1 at cell 7 and the estimate stays at A's.
    let a = peaked(2, 0.1);
    let even = fuse(&[a.clone(), peaked(7, 0.1)]).unwrap();
    let (x_even, _) = even.grid.centre_of_gravity(0.5).unwrap();
    assert!((x_even - 5.0).abs() < 1e-4, "{x_even}"); // centres 2.5 and 7.5
    let discounted = fuse(&[a, peaked(7, 0.8)]).unwrap();
    let (x, _) = discounted.grid.centre_of_gravity(0.5).unwrap();
    assert!((x - 2.5).abs() < 1e-4, "{x}");
    // The averages cannot do that: B's estimate pulls them half way (plain) or by its weight.
    let pts = [(2.5, 0.5), (7.5, 0.5)];
    assert_eq!(average(&pts), Some((5.0, 0.5)));
    let (xw, _) = weighted_average(&pts, &[0.9, 0.2]).unwrap();
    assert!((xw - (0.9 * 2.5 + 0.2 * 7.5) / 1.1).abs() < 1e-5);
    assert_eq!(weighted_average(&pts, &[0.0, f32::NAN]), Some((5.0, 0.5)));
    assert_eq!(weighted_average(&[], &[]), None);
}

#[test]
fn a_flat_grid_has_no_estimate() {
    assert_eq!(
        ObjectGrid::ignorance(geo(3, 3)).centre_of_gravity(0.5),
        None
    );
    assert_eq!(ObjectGrid::new(geo(3, 3), vec![0.0; 8]), None);
}

proptest! {
    #[test]
    fn fusion_does_not_depend_on_the_order_of_robots(
        grids in proptest::collection::vec(proptest::collection::vec(0.0f32..=1.0, 12), 1..5),
        seed in any::<u64>(),
    ) {
        let gs: Vec<ObjectGrid> = grids.into_iter().map(|v| ObjectGrid::new(geo(4, 3), v).unwrap()).collect();
        let mut shuffled = gs.clone();
        // A permutation from the seed (Fisher–Yates with a small LCG).
        let mut x = seed | 1;
        for i in (1..shuffled.len()).rev() {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            shuffled.swap(i, (x >> 33) as usize % (i + 1));
        }
        let a = fuse(&gs).unwrap();
        let b = fuse(&shuffled).unwrap();
        for (u, v) in a.grid.values().iter().zip(b.grid.values()) {
            prop_assert!((u - v).abs() <= 1e-5 * u.abs().max(1e-3) + 1e-6, "{u} vs {v}");
        }
        prop_assert!((a.conflict - b.conflict).abs() < 1e-5);
    }

    #[test]
    fn run_length_code_round_trips(
        runs in proptest::collection::vec((1usize..600, any::<u8>()), 0..20),
        nx in 1usize..50,
    ) {
        let mut cells: Vec<u8> = runs.iter().flat_map(|&(n, v)| std::iter::repeat(v).take(n)).collect();
        let ny = cells.len().div_ceil(nx).max(1);
        cells.resize(nx * ny, 7);
        let code = encode(nx, ny, &cells).unwrap();
        prop_assert_eq!(decode(&code).unwrap(), (nx, ny, cells.clone()));
        // Never longer than two bytes per cell plus the header.
        prop_assert!(code.len() <= 8 + 2 * cells.len());
    }

    #[test]
    fn decoding_arbitrary_bytes_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..64)) {
        let _ = decode(&bytes);
    }

    #[test]
    fn object_grids_survive_the_exchange(values in proptest::collection::vec(0.0f32..=1.0, 20)) {
        let g = ObjectGrid::new(geo(5, 4), values).unwrap();
        let back = ObjectGrid::from_rle(geo(5, 4), &g.to_rle()).unwrap();
        for (a, b) in g.values().iter().zip(back.values()) {
            prop_assert!((a - b).abs() <= 0.5 / 255.0 + 1e-6);
        }
    }
}

#[test]
fn malformed_codes_say_where() {
    let header = |nx: u32, ny: u32| {
        let mut v = nx.to_le_bytes().to_vec();
        v.extend_from_slice(&ny.to_le_bytes());
        v
    };
    assert_eq!(decode(&[1, 0, 0]), Err(RleError::ShortHeader { len: 3 }));
    let mut c = header(3, 1);
    c.extend_from_slice(&[2, 9, 1]);
    assert_eq!(decode(&c), Err(RleError::CutRun { offset: 10 }));
    let mut c = header(3, 1);
    c.extend_from_slice(&[0, 9]);
    assert_eq!(decode(&c), Err(RleError::ZeroRun { offset: 8 }));
    let mut c = header(3, 1);
    c.extend_from_slice(&[2, 9, 2, 9]);
    assert_eq!(
        decode(&c),
        Err(RleError::Overrun {
            offset: 10,
            cells: 3
        })
    );
    let mut c = header(3, 1);
    c.extend_from_slice(&[2, 9]);
    assert_eq!(
        decode(&c),
        Err(RleError::Underrun {
            expected: 3,
            found: 2
        })
    );
    assert!(matches!(
        decode(&header(u32::MAX, u32::MAX)),
        Err(RleError::TooLarge { .. })
    ));
    assert!(matches!(
        encode(2, 2, &[1, 2, 3]),
        Err(RleError::CellCount { found: 3, .. })
    ));
    let code = encode(2, 1, &[255, 0]).unwrap();
    assert!(matches!(
        ObjectGrid::from_rle(geo(1, 2), &code),
        Err(RleError::WrongSize { nx: 2, ny: 1, .. })
    ));
    // Runs longer than 255 are split.
    let code = encode(300, 1, &[4; 300]).unwrap();
    assert_eq!(&code[8..], &[255, 4, 45, 4]);
}
