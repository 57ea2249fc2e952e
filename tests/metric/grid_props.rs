//! Property tests of the grid against brute-force reference implementations
//! written straight from paper 000's formulas, and its invariants.

#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use lplace::core::Odometry;
use lplace::grid::dilate::{dilate_line, Profile};
use lplace::grid::{Combine, ElementShape, FuzzyGrid, GridConfig, Trapezoid};
use proptest::prelude::*;

/// Trapezoid membership written independently of the library.
fn trap(x: f32, center: f32, core: f32, slope: f32, bias: f32) -> f32 {
    let u = (x - center).abs() - core / 2.0;
    let ramp = if u <= 0.0 {
        1.0
    } else if slope > 0.0 {
        (1.0 - u / slope).max(0.0)
    } else {
        0.0
    };
    ramp.max(bias)
}

fn prof(u: f32, core: f32, flank: f32) -> f32 {
    let over = u.abs() - core;
    if over <= 0.0 {
        1.0
    } else if flank > 0.0 {
        (1.0 - over / flank).max(0.0)
    } else {
        0.0
    }
}

fn raw_cfg(element: ElementShape) -> GridConfig {
    GridConfig {
        normalize: false,
        flush_below: 0.0,
        floor: 0.0,
        element,
        ..GridConfig::default()
    }
}

fn grid_with(cfg: GridConfig, nx: usize, ny: usize, vals: &[f32]) -> FuzzyGrid {
    let s = cfg.cell_size;
    let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, nx as f32 * s, ny as f32 * s]).unwrap();
    g.possibilities_mut().copy_from_slice(&vals[..nx * ny]);
    g
}

/// `sup_q min(G(q), B(p − q))` by enumeration.
fn brute_dilate(g: &[f32], nx: usize, ny: usize, b: impl Fn(i32, i32) -> f32) -> Vec<f32> {
    let mut out = vec![0.0; nx * ny];
    for py in 0..ny {
        for px in 0..nx {
            let mut m = 0.0f32;
            for qy in 0..ny {
                for qx in 0..nx {
                    m = m.max(g[qy * nx + qx].min(b(px as i32 - qx as i32, py as i32 - qy as i32)));
                }
            }
            out[py * nx + px] = m;
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn line_dilation_is_brute_force(g in prop::collection::vec(0.0f32..=1.0, 1..40), core in 0.0f32..6.0, flank in 0.0f32..12.0) {
        let mut out = vec![0.0; g.len()];
        let mut dq = vec![0u32; g.len()];
        dilate_line(&g, &mut out, Profile { core, flank }, &mut dq);
        for x in 0..g.len() {
            let e = (0..g.len()).map(|y| g[y].min(prof(x as f32 - y as f32, core, flank))).fold(0.0, f32::max);
            prop_assert!((out[x] - e).abs() < 1e-5, "x={} got {} want {}", x, out[x], e);
        }
    }

    /// The square element is the L∞ trapezoid: exact everywhere, border included.
    #[test]
    fn square_dilation_is_brute_force(vals in prop::collection::vec(0.0f32..=1.0, 11 * 9), core in 0.0f32..0.3, flank in 0.0f32..0.6) {
        let (nx, ny) = (11, 9);
        let mut g = grid_with(raw_cfg(ElementShape::Square), nx, ny, &vals);
        g.dilate(core, flank);
        let (c, f) = (core / 0.1, flank / 0.1);
        let want = brute_dilate(&vals, nx, ny, |u, v| prof(u.abs().max(v.abs()) as f32, c, f));
        for (a, b) in g.possibilities().iter().zip(&want) {
            prop_assert!((a - b).abs() < 1e-4, "{} vs {}", a, b);
        }
    }

    /// The octagon is the sup-min sum of row, column and two diagonal 1-D
    /// trapezoids (apothem split a/(1+√2) for the square part, √2·a/(1+√2)
    /// L1 radius for the diamond, i.e. half that per diagonal step).
    /// Values sit in the middle of a zero border so that no clipping occurs.
    #[test]
    fn octagon_dilation_is_brute_force(vals in prop::collection::vec(0.0f32..=1.0, 8 * 8), core in 0.0f32..0.25, flank in 0.0f32..0.45) {
        let (nx, ny) = (18, 18);
        let mut full = vec![0.0f32; nx * ny];
        for j in 0..8 { for i in 0..8 { full[(j + 5) * nx + i + 5] = vals[j * 8 + i]; } }
        let mut g = grid_with(raw_cfg(ElementShape::Octagon), nx, ny, &full);
        g.dilate(core, flank);
        let k = 1.0 / (1.0 + 2f32.sqrt());
        let (ca, fa) = (core / 0.1 * k, flank / 0.1 * k);
        let (cd, fd) = (ca / 2f32.sqrt(), fa / 2f32.sqrt());
        let elem = |u: i32, v: i32| {
            let mut m = 0.0f32;
            for k3 in -8..=8 { for k4 in -8..=8 {
                // u = k1 + k3 − k4, v = k2 + k3 + k4 (diagonal (1,1), anti-diagonal (−1,1)).
                let k1 = u - k3 + k4;
                let k2 = v - k3 - k4;
                let val = prof(k1 as f32, ca, fa).min(prof(k2 as f32, ca, fa)).min(prof(k3 as f32, cd, fd)).min(prof(k4 as f32, cd, fd));
                m = m.max(val);
            }}
            m
        };
        let want = brute_dilate(&full, nx, ny, elem);
        for (i, (a, b)) in g.possibilities().iter().zip(&want).enumerate() {
            prop_assert!((a - b).abs() < 1e-4, "cell {}: {} vs {}", i, a, b);
        }
    }

    #[test]
    fn dilation_is_extensive_monotone_and_bounded(vals in prop::collection::vec(0.0f32..=1.0, 20 * 30), lift in prop::collection::vec(0.0f32..=0.5, 20 * 30), core in 0.0f32..1.0, flank in 0.0f32..3.0) {
        let bigger: Vec<f32> = vals.iter().zip(&lift).map(|(a, b)| (a + b).min(1.0)).collect();
        let mut g1 = grid_with(raw_cfg(ElementShape::Octagon), 20, 30, &vals);
        let mut g2 = grid_with(raw_cfg(ElementShape::Octagon), 20, 30, &bigger);
        g1.dilate(core, flank);
        g2.dilate(core, flank);
        for i in 0..600 {
            let (a, b) = (g1.possibilities()[i], g2.possibilities()[i]);
            prop_assert!(a >= vals[i] - 1e-7, "not extensive");
            prop_assert!(a <= b + 1e-7, "not monotone");
            prop_assert!((0.0..=1.0).contains(&a));
        }
    }

    #[test]
    fn range_update_is_brute_force_and_never_raises(vals in prop::collection::vec(0.0f32..=1.0, 20 * 30), lx in -1.0f32..3.0, ly in -1.0f32..4.0, r in 0.0f32..3.0, min in any::<bool>()) {
        let cfg = GridConfig { combine: if min { Combine::Min } else { Combine::Product }, ..raw_cfg(ElementShape::Octagon) };
        let m = cfg.range;
        let mut g = grid_with(cfg, 20, 30, &vals);
        g.update_range(lx, ly, r).unwrap();
        let (core, slope) = (m.core_abs + m.core_rel * r, m.slope_abs + m.slope_rel * r);
        for j in 0..30 { for i in 0..20 {
            let (x, y) = ((i as f32 + 0.5) * 0.1, (j as f32 + 0.5) * 0.1);
            let s = trap(((x - lx).powi(2) + (y - ly).powi(2)).sqrt(), r, core, slope, m.bias);
            let h = vals[j * 20 + i];
            let want = if min { h.min(s) } else { h * s };
            let got = g.possibilities()[j * 20 + i];
            prop_assert!((got - want).abs() < 1e-5, "({},{}) {} vs {}", i, j, got, want);
            prop_assert!(got <= h + 1e-7);
        }}
    }

    #[test]
    fn bearing_update_is_brute_force(vals in prop::collection::vec(0.0f32..=1.0, 12 * 10), heads in prop::collection::vec(-3.2f32..3.2, 12 * 10), lx in -1.0f32..2.0, ly in -1.0f32..2.0, r in 0.1f32..2.0, beta in -3.0f32..3.0) {
        let cfg = raw_cfg(ElementShape::Octagon);
        let (rm, bm) = (cfg.range, cfg.bearing);
        let mut g = grid_with(cfg, 12, 10, &vals);
        // Give every cell a definite heading belief.
        for j in 0..10 { for i in 0..12 {
            g.set_heading_set(i, j, Trapezoid::new(heads[j * 12 + i], 0.3, 0.2, 1.0, 0.2));
        }}
        g.update_range_bearing(lx, ly, r, beta).unwrap();
        for j in 0..10 { for i in 0..12 {
            let (x, y) = ((i as f32 + 0.5) * 0.1, (j as f32 + 0.5) * 0.1);
            let sr = trap(((x - lx).powi(2) + (y - ly).powi(2)).sqrt(), r, rm.core_abs + rm.core_rel * r, rm.slope_abs + rm.slope_rel * r, rm.bias);
            let want_heading = (ly - y).atan2(lx - x) - beta;
            // sup over θ of min(cell set, observation set), by sampling the circle.
            let cell = Trapezoid::new(heads[j * 12 + i], 0.3, 0.2, 1.0, 0.2);
            let obs = Trapezoid::new(want_heading, bm.core_abs, bm.slope_abs, 1.0, bm.bias);
            let sb = (0..20000).map(|k| { let th = -std::f32::consts::PI + k as f32 * (std::f32::consts::TAU / 20000.0); cell.angular(th).min(obs.angular(th)) }).fold(0.0, f32::max);
            let want = vals[j * 12 + i] * sr * sb;
            let got = g.possibilities()[j * 12 + i];
            prop_assert!((got - want).abs() < 2e-3, "({},{}) {} vs {}", i, j, got, want);
        }}
    }

    #[test]
    fn cog_is_brute_force(vals in prop::collection::vec(0.0f32..=1.0, 20 * 30)) {
        let cfg = raw_cfg(ElementShape::Octagon);
        let (cut, top, aref) = (cfg.cog_cut, cfg.top_cut, cfg.reliability_area);
        let g = grid_with(cfg, 20, 30, &vals);
        let e = g.estimate();
        let max = vals.iter().cloned().fold(0.0, f32::max);
        prop_assume!(max > 0.0);
        let (mut w, mut sx, mut sy, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
        for j in 0..30 { for i in 0..20 {
            let v = vals[j * 20 + i];
            if v >= cut * max { w += v as f64; sx += v as f64 * (i as f64 + 0.5) * 0.1; sy += v as f64 * (j as f64 + 0.5) * 0.1; }
            if v >= top * max { n += 1; }
        }}
        prop_assert!((e.x as f64 - sx / w).abs() < 1e-4);
        prop_assert!((e.y as f64 - sy / w).abs() < 1e-4);
        let area = n as f32 * 0.01;
        prop_assert!((e.reliability - max * aref / (aref + area)).abs() < 1e-5);
    }

    /// With the default configuration (flush, normalise, floor): the plane
    /// after a range update is the brute-force product, flushed, clamped,
    /// rescaled to height 1 and raised to the floor, and cells raised to the
    /// floor forget their heading (bias 1, Δ = 2π) while the others keep
    /// h · b ≥ floor.
    #[test]
    fn normalise_and_floor_are_brute_force(vals in prop::collection::vec(0.0f32..=1.0, 20 * 30), tiny in prop::collection::vec(any::<bool>(), 20 * 30), lx in -1.0f32..3.0, ly in -1.0f32..4.0, r in 0.0f32..3.0) {
        let cfg = GridConfig::default();
        let (m, floor, flush) = (cfg.range, cfg.floor, cfg.flush_below);
        // Some cells far below the floor, so that every branch is taken.
        let vals: Vec<f32> = vals.iter().zip(&tiny).map(|(&v, &t)| if t { v * 1e-9 } else { v }).collect();
        let mut g = grid_with(cfg, 20, 30, &vals);
        for j in 0..30 { for i in 0..20 {
            g.set_heading_set(i, j, Trapezoid::new(0.5, 1.0, 0.2, 1.0, vals[j * 20 + i]));
        }}
        g.update_range(lx, ly, r).unwrap();
        let (core, slope) = (m.core_abs + m.core_rel * r, m.slope_abs + m.slope_rel * r);
        let prod: Vec<f32> = (0..600).map(|c| {
            let (x, y) = ((c % 20) as f32 * 0.1 + 0.05, (c / 20) as f32 * 0.1 + 0.05);
            let v = vals[c] * trap(((x - lx).powi(2) + (y - ly).powi(2)).sqrt(), r, core, slope, m.bias);
            if v < flush { 0.0 } else { v.min(1.0) }
        }).collect();
        let max = prod.iter().cloned().fold(0.0, f32::max);
        prop_assume!(max > 0.0);
        // Relative, as for the cells below: the grid and this reference compute distances and
        // flanks in f32 in a different order, ~10 ulps apart (1.1e-6 at a height of 0.83 found).
        prop_assert!((g.last_height() - max).abs() <= 1e-5 * max, "height {} vs {}", g.last_height(), max);
        for c in 0..600 {
            let n = (prod[c] / max).min(1.0);
            let got = g.possibilities()[c];
            let t = g.heading_set(c % 20, c / 20).unwrap();
            if n < floor * 0.999 {
                prop_assert_eq!(got, floor);
                prop_assert!(t.shape.bias == 1.0 && t.shape.core >= 2.0 * std::f32::consts::PI);
            } else if n > floor * 1.001 {
                prop_assert!((got - n).abs() <= 1e-4 * n, "cell {}: {} vs {}", c, got, n);
                prop_assert!((t.shape.core - 1.0).abs() < 1e-6);
                let b = vals[c];
                let want_b = if n * b < floor { floor / n } else { b };
                prop_assert!((t.shape.bias - want_b).abs() <= 1e-4 * want_b.max(1e-6), "cell {}: bias {} vs {}", c, t.shape.bias, want_b);
            }
            prop_assert!((0.0..=1.0).contains(&got));
        }
    }

    /// The CoG on a concentrated belief (most rows far below the cut, which
    /// the estimate skips) against brute force.
    #[test]
    fn cog_of_a_concentrated_belief_is_brute_force(vals in prop::collection::vec(0.0f32..=1.0, 20 * 30), band in 0usize..28) {
        let cfg = raw_cfg(ElementShape::Octagon);
        let (cut, top) = (cfg.cog_cut, cfg.top_cut);
        let vals: Vec<f32> = vals.iter().enumerate().map(|(c, &v)| if (band..band + 3).contains(&(c / 20)) { v } else { v * 0.3 }).collect();
        let g = grid_with(cfg, 20, 30, &vals);
        let e = g.estimate();
        let max = vals.iter().cloned().fold(0.0, f32::max);
        prop_assume!(max > 0.0);
        let (mut w, mut sx, mut sy, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
        for j in 0..30 { for i in 0..20 {
            let v = vals[j * 20 + i];
            if v >= cut * max { w += v as f64; sx += v as f64 * (i as f64 + 0.5) * 0.1; sy += v as f64 * (j as f64 + 0.5) * 0.1; }
            if v >= top * max { n += 1; }
        }}
        prop_assert!((e.x as f64 - sx / w).abs() < 1e-4);
        prop_assert!((e.y as f64 - sy / w).abs() < 1e-4);
        prop_assert!((e.top_area - n as f32 * 0.01).abs() < 1e-6);
    }

    #[test]
    fn intersection_stays_under_min_and_in_range(ca in -4.0f32..4.0, da in 0.0f32..3.0, aa in 0.0f32..2.0, ba in 0.0f32..=1.0,
                                                 cb in -4.0f32..4.0, db in 0.0f32..3.0, ab in 0.0f32..2.0, bb in 0.0f32..=1.0) {
        let a = Trapezoid::new(ca, da, aa, 1.0, ba);
        let b = Trapezoid::new(cb, db, ab, 1.0, bb);
        let c = a.intersect_angle(&b);
        prop_assert!((0.0..=1.0).contains(&c.shape.height) && (0.0..=1.0).contains(&c.shape.bias));
        prop_assert!(c.shape.core >= 0.0 && c.shape.slope >= 0.0 && c.center.is_finite());
        if a.overlap_level(&b) > 0.0 {
            // Inner envelope: the trapezoid part lies under min(A, B).
            let tp = Trapezoid::raw(c.center, c.shape.core, c.shape.slope, c.shape.height, 0.0);
            for k in 0..2000 {
                let th = -3.2 + k as f32 * 0.0032;
                prop_assert!(tp.angular(th) <= a.angular(th).min(b.angular(th)) + 2e-3, "θ={} {:?}", th, c);
            }
            prop_assert!((c.shape.bias - ba * bb).abs() < 1e-6);
        } else {
            // Outer envelope: covers max(A, B) (trapezoid parts).
            for k in 0..2000 {
                let th = -3.2 + k as f32 * 0.0032;
                let unbiased = |t: &Trapezoid| Trapezoid::raw(t.center, t.shape.core, t.shape.slope, t.shape.height, 0.0);
                let m = unbiased(&a).angular(th).max(unbiased(&b).angular(th));
                prop_assert!(c.angular(th) >= m - 2e-3, "θ={} {:?}", th, c);
            }
            prop_assert!(c.shape.bias >= ba.max(bb) - 1e-6);
        }
    }
}

#[test]
fn nan_observations_are_rejected_and_leave_the_grid_alone() {
    let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 2.0, 3.0]).unwrap();
    g.update_range(0.0, 0.0, 1.0).unwrap();
    let before = g.possibilities().to_vec();
    assert!(g.update_range(0.0, 0.0, f32::NAN).is_err());
    assert!(g.update_range(0.0, 0.0, -1.0).is_err());
    assert!(g.update_bearing(f32::INFINITY, 0.0, 0.1).is_err());
    assert!(g.update_range_bearing(0.0, 0.0, 1.0, f32::NAN).is_err());
    assert_eq!(before, g.possibilities());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Wild but accepted inputs (huge, tiny, negative) never panic and keep
    /// every value in [0, 1].
    #[test]
    fn wild_inputs_do_not_panic(lx in prop::num::f32::ANY, ly in prop::num::f32::ANY, r in prop::num::f32::ANY,
                                 b in prop::num::f32::ANY, fwd in prop::num::f32::ANY, turn in prop::num::f32::ANY,
                                 dt in prop::num::f32::ANY, core in prop::num::f32::ANY, flank in prop::num::f32::ANY) {
        let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, 2.0, 3.0]).unwrap();
        let _ = g.update_range(lx, ly, r);
        let _ = g.update_range_bearing(lx, ly, r, b);
        let _ = g.update_bearing(lx, ly, b);
        let _ = g.predict(&Odometry { forward: fwd as f64, left: -fwd as f64, turn: turn as f64 }, dt as f64);
        g.apply_pending();
        let _ = g.predict(&Odometry { forward: 1e30, left: -1e30, turn: 1e30 }, 1e30);
        let _ = g.update_range(1.0, 1.0, 1.0);
        g.dilate(core, flank);
        let e = g.estimate();
        prop_assert!(e.x.is_finite() && e.y.is_finite() && e.theta.is_finite());
        prop_assert!(g.possibilities().iter().all(|v| (0.0..=1.0).contains(v)));
    }
}
