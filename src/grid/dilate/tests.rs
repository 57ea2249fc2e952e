//! The dilation's tests: the 1-D pass against brute force, the offset and
//! window-maximum passes against the deque passes (bit for bit where the
//! claim is bit for bit), whole dilations against the deque passes alone.

use super::*;

/// The passes as methods of the grid, so that the tests read as before the
/// split into one file per algorithm.
impl FuzzyGrid {
    fn measure_extrema(&mut self) {
        offsets::measure_extrema(&self.h, (self.nx, self.ny), &mut self.work);
    }

    fn offset_pass(&mut self, b: &[f32], dir: (isize, isize), keep: bool, maxima_ok: bool) {
        let dims = (self.nx, self.ny);
        offsets::offset_pass(&mut self.h, dims, &mut self.work, b, dir, (keep, maxima_ok));
    }

    fn row_pass(&mut self, p: Profile) {
        deque::row_pass(&mut self.h, self.nx, p, &mut self.work);
    }

    fn skew_pass(&mut self, p: Profile, s: isize) {
        deque::skew_pass(&mut self.h, (self.nx, self.ny), p, s, &mut self.work);
    }
}

impl FuzzyGrid {
    /// [`FuzzyGrid::dilate_xy`] with every pass by deques: the reference
    /// the offset passes are tested against.
    fn dilate_by_deques(&mut self, core: [f32; 2], flank: [f32; 2]) {
        let cells = |v: f32| v.max(0.0) / self.cell;
        let (k, diag) = match self.cfg.element {
            ElementShape::Octagon => (1.0 / (1.0 + SQRT_2), true),
            ElementShape::Square => (1.0, false),
        };
        let px = Profile {
            core: cells(core[0]) * k,
            flank: cells(flank[0]) * k,
        };
        let py = Profile {
            core: cells(core[1]) * k,
            flank: cells(flank[1]) * k,
        };
        let pd = Profile {
            core: 0.5 * (px.core + py.core) / SQRT_2,
            flank: 0.5 * (px.flank + py.flank) / SQRT_2,
        };
        for v in self.h.iter_mut() {
            *v = v.clamp(0.0, 1.0);
        }
        self.row_pass(px);
        self.skew_pass(py, 0);
        if diag {
            self.skew_pass(pd, 1);
            self.skew_pass(pd, -1);
        }
    }
}

fn brute(g: &[f32], p: Profile) -> Vec<f32> {
    (0..g.len())
        .map(|x| {
            (0..g.len())
                .map(|y| g[y].min(p.at(x as f32 - y as f32)))
                .fold(0.0, f32::max)
        })
        .collect()
}

/// The offset passes (short reach) and the deque passes (long reach)
/// are two evaluations of the same 1-D dilations: they must agree on
/// every line, border lines included, on random values and on plateaus
/// with spikes (where blocks stop early, at different offsets).
#[test]
fn offset_and_deque_passes_agree() {
    use crate::grid::GridConfig;
    let mut rnd = crate::grid::test_rng(12345u32);
    for (w, h) in [(2.3, 1.7), (0.7, 3.1), (4.1, 0.3)] {
        let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, w, h]).unwrap();
        for pattern in 0..3 {
            for v in g.possibilities_mut() {
                let r = rnd();
                *v = match pattern {
                    0 => r,
                    1 => 0.03 * r,
                    _ if r < 0.03 => 1.0,
                    _ if r < 0.1 => 0.4,
                    _ => 0.02,
                };
            }
            for p in [
                Profile {
                    core: 0.0,
                    flank: 2.5,
                },
                Profile {
                    core: 1.3,
                    flank: 0.0,
                },
                Profile {
                    core: 0.7,
                    flank: 4.2,
                },
                Profile {
                    core: 3.0,
                    flank: 9.0,
                },
                Profile {
                    core: 0.0,
                    flank: 24.9,
                },
            ] {
                for s in [None, Some(0), Some(1), Some(-1)] {
                    let (mut a, mut b) = (g.clone(), g.clone());
                    let cap = match s {
                        None => g.nx(),
                        Some(0) => g.ny(),
                        _ => g.nx().min(g.ny()),
                    };
                    let (lv, k) = levels(p, cap);
                    match s {
                        None => {
                            {
                                a.measure_extrema();
                                a.offset_pass(&lv[..=k], (1, 0), false, true);
                            }
                            b.row_pass(p);
                        }
                        Some(s) => {
                            {
                                a.measure_extrema();
                                a.offset_pass(&lv[..=k], (s, 1), false, true);
                            }
                            b.skew_pass(p, s);
                        }
                    }
                    for (x, y) in a.possibilities().iter().zip(b.possibilities()) {
                        assert!((x - y).abs() < 1e-6, "{p:?} {s:?}: {x} vs {y}");
                    }
                }
            }
        }
    }
}

/// Window maxima (flat groups) against the offsets on the same
/// blocks, bit for bit: low noise (every group flat), noise with a few
/// peaks (flat groups beside others), along all four directions, reaches
/// from below [`EXACT_REACH`] to [`LEVEL_MAX`], grids narrower than a
/// block and shorter than a window.
#[test]
fn window_maxima_match_the_offsets_bit_for_bit() {
    use crate::grid::GridConfig;
    let mut rnd = crate::grid::test_rng(777u32);
    for (w, h) in [(20.0, 30.0), (3.3, 1.2), (1.1, 4.0), (6.4, 2.5)] {
        let mut g = FuzzyGrid::new(GridConfig::default(), [0.0, 0.0, w, h]).unwrap();
        for pattern in 0..2 {
            for v in g.possibilities_mut() {
                let r = rnd();
                *v = match pattern {
                    0 => 0.01 * r,
                    _ if r < 0.001 => 1.0,
                    _ => 0.01 * r,
                };
            }
            for flank in [3.5f32, 5.0, 9.0, 14.0, 40.0] {
                let p = Profile { core: 0.0, flank };
                for (dx, dy) in [(1, 0), (0, 1), (1, 1), (-1, 1)] {
                    let cap = match (dx, dy) {
                        (_, 0) => g.nx(),
                        (0, _) => g.ny(),
                        _ => g.nx().min(g.ny()),
                    };
                    let (lv, k) = levels(p, cap);
                    let (mut a, mut b) = (g.clone(), g.clone());
                    a.measure_extrema();
                    a.offset_pass(&lv[..=k], (dx, dy), false, true);
                    b.measure_extrema();
                    b.offset_pass(&lv[..=k], (dx, dy), false, false);
                    for (i, (x, y)) in a.possibilities().iter().zip(b.possibilities()).enumerate() {
                        assert!(
                            x.to_bits() == y.to_bits(),
                            "{w}×{h} pattern {pattern} flank {flank} ({dx}, {dy}) cell {i}: {x} vs {y}"
                        );
                    }
                }
            }
        }
    }
}

/// Whole dilations (every pass, the group extrema carried from pass to
/// pass, groups left alone) against the same 1-D elements applied by
/// the deque passes alone, borders included, on beliefs where groups
/// are left alone, where blocks stop early and where none do, with
/// anisotropic elements and both shapes.
#[test]
fn whole_dilations_match_the_deque_passes() {
    use crate::grid::GridConfig;
    let mut rnd = crate::grid::test_rng(4242u32);
    for element in [ElementShape::Octagon, ElementShape::Square] {
        for (w, h) in [(12.0, 10.3), (5.3, 4.1), (1.3, 2.9), (2.0, 0.9)] {
            let cfg = GridConfig {
                element,
                ..GridConfig::default()
            };
            let mut g = FuzzyGrid::new(cfg, [0.0, 0.0, w, h]).unwrap();
            for pattern in 0..6 {
                for v in g.possibilities_mut() {
                    let r = rnd();
                    *v = match pattern {
                        0 => r,
                        1 => 0.03 * r,
                        // A few peaks on the floor: most groups left alone.
                        2 if r < 0.002 => 1.0,
                        2 if r < 0.005 => 0.3,
                        2 => 1e-8,
                        3 if r < 0.2 => 0.2 + 0.8 * r,
                        3 => 0.016,
                        4 => 0.9 + 0.1 * r,
                        // Groups whose minimum is just under their bound.
                        _ if r < 0.03 => 0.504,
                        _ => 0.5,
                    };
                }
                for (core, flank) in [
                    ([0.0, 0.0], [0.3, 0.3]),
                    ([0.05, 0.0], [1.0, 0.4]),
                    ([0.2, 0.3], [2.5, 2.5]),
                    ([0.0, 0.1], [0.0, 3.0]),
                ] {
                    let mut a = g.clone();
                    a.dilate_xy(core, flank);
                    let mut b = g.clone();
                    b.dilate_by_deques(core, flank);
                    for (i, (x, y)) in a.possibilities().iter().zip(b.possibilities()).enumerate() {
                        assert!(
                            (x - y).abs() < 1e-6,
                            "{element:?} {w}×{h} pattern {pattern} {core:?} {flank:?} cell {i}: {x} vs {y}"
                        );
                    }
                }
            }
        }
    }
}

/// A lone peak next to a chunk edge on a floor: its rise into the next
/// chunk must reach the next passes' bounds (the extrema they measure
/// again), or the groups around would be left alone wrongly.
#[test]
fn lone_peaks_spread_across_chunk_edges() {
    use crate::grid::GridConfig;
    for element in [ElementShape::Octagon, ElementShape::Square] {
        let cfg = GridConfig {
            element,
            ..GridConfig::default()
        };
        lone_peaks(FuzzyGrid::new(cfg, [0.0, 0.0, 12.0, 10.3]).unwrap());
    }
}

fn lone_peaks(mut g: FuzzyGrid) {
    for (c, r) in [(14usize, 20usize), (47, 63), (80, 7), (112, 95)] {
        g.possibilities_mut().fill(1e-8);
        let nx = g.nx();
        g.possibilities_mut()[r * nx + c] = 1.0;
        for flank in [0.6, 1.0, 2.0, 3.0] {
            let mut a = g.clone();
            a.dilate(0.0, flank);
            let mut b = g.clone();
            b.dilate_by_deques([0.0; 2], [flank; 2]);
            for (i, (x, y)) in a.possibilities().iter().zip(b.possibilities()).enumerate() {
                assert!(
                    (x - y).abs() < 1e-6,
                    "peak ({c}, {r}) flank {flank} cell {i}: {x} vs {y}"
                );
            }
        }
    }
}

#[test]
fn line_matches_brute_force_on_fixed_cases() {
    let g = [0.1, 0.9, 0.2, 0.0, 0.7, 0.7, 0.3, 1.0, 0.0, 0.05, 0.5];
    for p in [
        Profile {
            core: 0.0,
            flank: 0.0,
        },
        Profile {
            core: 0.0,
            flank: 3.0,
        },
        Profile {
            core: 1.5,
            flank: 0.0,
        },
        Profile {
            core: 1.0,
            flank: 2.5,
        },
        Profile {
            core: 20.0,
            flank: 20.0,
        },
    ] {
        let mut out = vec![0.0; g.len()];
        let mut dq = vec![0u32; g.len()];
        dilate_line(&g, &mut out, p, &mut dq);
        let b = brute(&g, p);
        for (a, e) in out.iter().zip(&b) {
            assert!((a - e).abs() < 1e-6, "{p:?}: {out:?} vs {b:?}");
        }
    }
}

/// Łukasiewicz dilation `max(0, sup_q G(q) + B(p − q) − 1)` by the element of `s` with bias
/// `bias`, evaluated from its definition: the core as the set of integer Minkowski sums of its
/// segments, the distance to it as a shortest path over the eight grid steps (Bellman–Ford),
/// the supremum over every cell.
fn lukasiewicz_brute(
    g: &[f32],
    (nx, ny): (usize, usize),
    s: lukasiewicz::Steps,
    bias: f32,
) -> Vec<f32> {
    let (wx, wy) = (2 * nx + 1, 2 * ny + 1); // offsets −nx..=nx, −ny..=ny
    let idx = |dx: isize, dy: isize| -> Option<usize> {
        let (i, j) = (dx + nx as isize, dy + ny as isize);
        (i >= 0 && j >= 0 && (i as usize) < wx && (j as usize) < wy)
            .then(|| j as usize * wx + i as usize)
    };
    let mut dist = vec![f64::INFINITY; wx * wy];
    let [mx, my, md] = s.half.map(|m| m as isize);
    for a in -mx..=mx {
        for b in -my..=my {
            for c in -md..=md {
                for d in -md..=md {
                    if let Some(i) = idx(a + c - d, b + c + d) {
                        dist[i] = 0.0;
                    }
                }
            }
        }
    }
    let [ax, ay, ad] = s.cost.map(f64::from);
    let moves = [
        (1, 0, ax),
        (-1, 0, ax),
        (0, 1, ay),
        (0, -1, ay),
        (1, 1, ad),
        (-1, -1, ad),
        (1, -1, ad),
        (-1, 1, ad),
    ];
    loop {
        let mut changed = false;
        for dy in -(ny as isize)..=ny as isize {
            for dx in -(nx as isize)..=nx as isize {
                let Some(i) = idx(dx, dy) else { continue };
                for &(mx, my, c) in &moves {
                    if let Some(j) = idx(dx + mx, dy + my) {
                        if dist[j] + c < dist[i] {
                            dist[i] = dist[j] + c;
                            changed = true;
                        }
                    }
                }
            }
        }
        if !changed {
            break;
        }
    }
    let element = |dx: isize, dy: isize| -> f64 {
        let d = idx(dx, dy).map_or(f64::INFINITY, |i| dist[i]);
        f64::from(bias).max((1.0 - d).max(0.0))
    };
    let mut out = vec![0.0f32; nx * ny];
    for py in 0..ny {
        for px in 0..nx {
            let mut best = 0.0f64;
            for qy in 0..ny {
                for qx in 0..nx {
                    let e = element(px as isize - qx as isize, py as isize - qy as isize);
                    best = best.max(f64::from(g[qy * nx + qx]) + e - 1.0);
                }
            }
            out[py * nx + px] = best as f32;
        }
    }
    out
}

/// The split (flat core, cone sweeps, floor) equals the Łukasiewicz dilation's definition
/// evaluated by brute force: exactly where the belief keeps away from the border by the
/// core's reach (the core's segments only see the grid), and never above it anywhere.
#[test]
fn lukasiewicz_split_is_the_definition() {
    let mut rnd = crate::grid::test_rng(2024);
    let mut exact_cases = 0;
    for case in 0..160 {
        let nx = 4 + (rnd() * 9.0) as usize;
        let ny = 4 + (rnd() * 9.0) as usize;
        let element = if case % 3 == 0 {
            ElementShape::Square
        } else {
            ElementShape::Octagon
        };
        let core = if case % 4 == 0 {
            [0.0, 0.0]
        } else {
            [rnd() * 6.0, rnd() * 6.0]
        };
        let flank = match case % 5 {
            0 => [0.0, 0.0],
            1 => {
                let f = 0.2 + rnd() * 9.0;
                [f, f]
            }
            _ => [0.2 + rnd() * 9.0, 0.2 + rnd() * 9.0],
        };
        let bias = if case % 2 == 0 { 0.0 } else { rnd() * 0.6 };
        let s = lukasiewicz::steps(element, lukasiewicz::Radii { core, flank });
        let margin_x = s.half[0] + 2 * s.half[2];
        let margin_y = s.half[1] + 2 * s.half[2];
        let sparse = case % 2 == 1;
        let mut g: Vec<f32> = (0..nx * ny)
            .map(|_| {
                let v = rnd();
                if sparse && v < 0.8 {
                    0.0
                } else {
                    v
                }
            })
            .collect();
        let whole = lukasiewicz_brute(&g, (nx, ny), s, bias);
        let mut got = g.clone();
        lukasiewicz::dilate(&mut got, (nx, ny), s, bias, &mut vec![0.0; nx]);
        for (i, (&a, &b)) in got.iter().zip(&whole).enumerate() {
            assert!(
                a <= b + 1e-5,
                "case {case}: cell {i}: {a} above the definition's {b}"
            );
            assert!(
                a >= g[i] - 1e-6 || a >= b - 1e-5,
                "case {case}: cell {i} lowered"
            );
        }
        if s.half == [0, 0, 0] || (2 * margin_x < nx && 2 * margin_y < ny) {
            for j in 0..ny {
                for i in 0..nx {
                    let inside = (margin_x..nx - margin_x).contains(&i)
                        && (margin_y..ny - margin_y).contains(&j);
                    if !inside {
                        g[j * nx + i] = 0.0;
                    }
                }
            }
            let want = lukasiewicz_brute(&g, (nx, ny), s, bias);
            let mut got = g.clone();
            lukasiewicz::dilate(&mut got, (nx, ny), s, bias, &mut vec![0.0; nx]);
            for (i, (&a, &b)) in got.iter().zip(&want).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-5,
                    "case {case} {s:?}: cell {i}: {a} vs {b}"
                );
            }
            exact_cases += 1;
        }
    }
    assert!(exact_cases > 60, "only {exact_cases} exact comparisons");
}

/// Hand-worked: a single 1 under the isotropic octagon of flank 4 cells and no core: the
/// chamfer cone, 1 − 1/4 per axis step and 1 − √2/4 per diagonal step, 0 from 4 axis steps.
#[test]
fn lukasiewicz_cone_by_hand() {
    let (nx, ny) = (11, 11);
    let mut g = vec![0.0f32; nx * ny];
    g[5 * nx + 5] = 1.0;
    let s = lukasiewicz::steps(
        ElementShape::Octagon,
        lukasiewicz::Radii {
            core: [0.0; 2],
            flank: [4.0; 2],
        },
    );
    lukasiewicz::dilate(&mut g, (nx, ny), s, 0.0, &mut [0.0; 11]);
    let at = |x: usize, y: usize| g[y * nx + x];
    assert_eq!(at(5, 5), 1.0);
    assert!((at(7, 5) - 0.5).abs() < 1e-6);
    assert!((at(5, 2) - 0.25).abs() < 1e-6);
    assert_eq!(at(9, 5), 0.0);
    assert!((at(6, 6) - (1.0 - SQRT_2 / 4.0)).abs() < 1e-6);
    // (2, 1) away: one diagonal and one axis step.
    assert!((at(7, 6) - (1.0 - (1.0 + SQRT_2) / 4.0)).abs() < 1e-6);
    // A bias of 0.3 floors the plane at max g + b − 1 = 0.3.
    let mut h = vec![0.0f32; nx * ny];
    h[0] = 1.0;
    lukasiewicz::dilate(&mut h, (nx, ny), s, 0.3, &mut [0.0; 11]);
    assert!((h[nx * ny - 1] - 0.3).abs() < 1e-6);
}
