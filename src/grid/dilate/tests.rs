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
