//! Costs of the Fuzzy Position Grid on paper 000's two sizes (20×30 and
//! 200×300 cells of 10 cm), each next to a plain clone of the same grid.
//!
//! `cargo bench --bench grid -- --warm-up-time 1 --measurement-time 3`
//!
//! Operations whose cost depends on the belief run on three of them:
//! * `base`: two range rings and a bearing from total ignorance (an early
//!   belief: rings, their flanks and a low plateau);
//! * `peak`: a concentrated belief after consistent sightings of four
//!   landmarks (most cells at the floor, as on MRCLAM after the first fix);
//! * `noise`: low random values (below every element level), the worst case
//!   of the dilation's early exits: no lane of a block finds its window
//!   maximum, so every block runs every offset.
//!
//! Every dilation runs at r = 1, 2, 5, 10, 20, 30 cells under both rules
//! (`dilate*`: sup-min; `luk_dilate*`: Łukasiewicz, issue 20's goal of
//! ≤ 2.5× the clone at every radius), next to `clone` (the whole grid) and
//! `copy_plane` (the possibility plane alone). Under a loaded host compare
//! CPU times instead (`docs/grid-bench.md`).
//!
//! Updates in place (`update_range`, `update_range_bearing`) reach the steady
//! state of a repeated sighting (≈ 96 % of the cells at the floor); the
//! `_fresh` and `_known` variants and every dilation work on a fresh copy per
//! iteration, made outside the timing (dilating in place would soon measure
//! a saturated, almost uniform plane).

use criterion::{black_box, criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use lplace::core::angle::wrap_pi_f32 as wrap_pi;
use lplace::core::Odometry;
use lplace::grid::{Dilation, FuzzyGrid, GridConfig, Trapezoid};

fn empty(nx: usize, ny: usize) -> FuzzyGrid {
    let s = 0.1;
    FuzzyGrid::new(
        GridConfig::default(),
        [0.0, 0.0, nx as f32 * s, ny as f32 * s],
    )
    .unwrap()
}

/// Two range circles and a bearing from total ignorance.
fn base(nx: usize, ny: usize) -> FuzzyGrid {
    let mut g = empty(nx, ny);
    let (w, h) = (nx as f32 * 0.1, ny as f32 * 0.1);
    g.update_range(0.2 * w, 0.3 * h, 0.4 * w).unwrap();
    g.update_range_bearing(0.8 * w, 0.6 * h, 0.3 * w, 0.4)
        .unwrap();
    g
}

/// Three rounds of exact range and bearing readings of four landmarks from
/// a pose at (0.4 w, 0.55 h), heading 0.3 rad.
fn peak(nx: usize, ny: usize) -> FuzzyGrid {
    let mut g = empty(nx, ny);
    let (w, h) = (nx as f32 * 0.1, ny as f32 * 0.1);
    let (px, py, th) = (0.4 * w, 0.55 * h, 0.3f32);
    let marks = [(0.1, 0.1), (0.9, 0.2), (0.8, 0.9), (0.15, 0.8)];
    for _ in 0..3 {
        for &(mx, my) in &marks {
            let (lx, ly) = (mx * w, my * h);
            let (dx, dy) = (lx - px, ly - py);
            let bearing = wrap_pi(dy.atan2(dx) - th);
            g.update_range_bearing(lx, ly, dx.hypot(dy), bearing)
                .unwrap();
        }
    }
    g
}

/// Values in [0, 0.03): below the lowest level of every element benched.
fn noise(nx: usize, ny: usize) -> FuzzyGrid {
    let mut g = empty(nx, ny);
    let mut seed = 0x2545_f491u32;
    for v in g.possibilities_mut() {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        *v = 0.03 * (seed >> 8) as f32 / (1u32 << 24) as f32;
    }
    g
}

/// The same belief under another dilation rule.
fn with_rule(g: &FuzzyGrid, rule: Dilation) -> FuzzyGrid {
    let cfg = GridConfig {
        dilation: rule,
        ..g.config().clone()
    };
    let (x0, y0) = g.origin();
    let s = g.cell_size();
    let bounds = [x0, y0, x0 + g.nx() as f32 * s, y0 + g.ny() as f32 * s];
    let mut out = FuzzyGrid::new(cfg, bounds).unwrap();
    assert_eq!((out.nx(), out.ny()), (g.nx(), g.ny()));
    out.possibilities_mut().copy_from_slice(g.possibilities());
    out
}

fn bench(c: &mut Criterion) {
    for (nx, ny) in [(20usize, 30usize), (200, 300)] {
        let name = format!("{nx}x{ny}");
        let mut grp = c.benchmark_group(format!("grid/{name}"));
        let base = base(nx, ny);
        let (w, h) = (nx as f32 * 0.1, ny as f32 * 0.1);
        grp.bench_function("clone", |b| b.iter(|| black_box(base.clone())));
        let mut g = base.clone();
        grp.bench_function("update_range", |b| {
            b.iter(|| {
                g.update_range(black_box(0.5 * w), 0.5 * h, 0.3 * w.min(h))
                    .unwrap()
            })
        });
        grp.bench_function("update_range_fresh", |b| {
            b.iter_batched_ref(
                || base.clone(),
                |g| {
                    g.update_range(black_box(0.5 * w), 0.5 * h, 0.3 * w.min(h))
                        .unwrap()
                },
                BatchSize::PerIteration,
            )
        });
        let mut g = base.clone();
        grp.bench_function("update_range_bearing", |b| {
            b.iter(|| {
                g.update_range_bearing(black_box(0.5 * w), 0.5 * h, 0.3 * w.min(h), 0.2)
                    .unwrap()
            })
        });
        // Every cell with a definite heading: no block of unknown headings
        // to skip, the bearing update's worst case.
        let mut known = base.clone();
        for j in 0..ny {
            for i in 0..nx {
                known.set_heading_set(i, j, Trapezoid::new(0.3, 0.4, 0.3, 1.0, 0.2));
            }
        }
        grp.bench_function("update_range_bearing_known", |b| {
            b.iter_batched_ref(
                || known.clone(),
                |g| {
                    g.update_range_bearing(black_box(0.5 * w), 0.5 * h, 0.3 * w.min(h), 0.2)
                        .unwrap()
                },
                BatchSize::PerIteration,
            )
        });
        // The plane alone, the dilation's own input and output.
        let plane = base.possibilities().to_vec();
        grp.bench_function("copy_plane", |b| b.iter(|| black_box(plane.clone())));
        for (rule, tag) in [(Dilation::SupMin, ""), (Dilation::Lukasiewicz, "luk_")] {
            for (belief, grid) in [
                ("dilate", &base),
                ("dilate_peak", &peak(nx, ny)),
                ("dilate_noise", &noise(nx, ny)),
            ] {
                let grid = with_rule(grid, rule);
                for r in [1usize, 2, 5, 10, 20, 30] {
                    let radius = r as f32 * 0.1;
                    let id = BenchmarkId::new(format!("{tag}{belief}"), r);
                    grp.bench_with_input(id, &radius, |b, &radius| {
                        b.iter_batched_ref(
                            || grid.clone(),
                            |g| g.dilate(0.0, black_box(radius)),
                            BatchSize::PerIteration,
                        )
                    });
                }
            }
        }
        grp.bench_function("estimate", |b| b.iter(|| black_box(base.estimate())));
        let mut g = base.clone();
        let mut k = 0u32;
        grp.bench_function("step", |b| {
            b.iter(|| {
                k = k.wrapping_add(1);
                let turn = if k % 2 == 0 { 0.05 } else { -0.05 };
                g.predict(
                    &Odometry {
                        forward: 0.05,
                        left: 0.0,
                        turn,
                    },
                    0.2,
                )
                .unwrap();
                g.update_range_bearing(0.5 * w, 0.5 * h, 0.3 * w.min(h), 0.2)
                    .unwrap();
                black_box(g.estimate())
            })
        });
        grp.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
