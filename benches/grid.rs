//! Costs of the Fuzzy Position Grid on paper 000's two sizes (20×30 and
//! 200×300 cells of 10 cm), each next to a plain clone of the same grid.
//!
//! `cargo bench --bench grid -- --warm-up-time 1 --measurement-time 3`

use criterion::{black_box, criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use lplace::grid::{FuzzyGrid, GridConfig, Motion, Trapezoid};

fn grid(nx: usize, ny: usize) -> FuzzyGrid {
    let s = 0.1;
    let mut g = FuzzyGrid::new(
        GridConfig::default(),
        [0.0, 0.0, nx as f32 * s, ny as f32 * s],
    )
    .unwrap();
    // A realistic, non-uniform belief: two range circles and a bearing.
    let (w, h) = (nx as f32 * s, ny as f32 * s);
    g.update_range(0.2 * w, 0.3 * h, 0.4 * w).unwrap();
    g.update_range_bearing(0.8 * w, 0.6 * h, 0.3 * w, 0.4)
        .unwrap();
    g
}

fn bench(c: &mut Criterion) {
    for (nx, ny) in [(20usize, 30usize), (200, 300)] {
        let name = format!("{nx}x{ny}");
        let mut grp = c.benchmark_group(format!("grid/{name}"));
        let base = grid(nx, ny);
        let (w, h) = (nx as f32 * 0.1, ny as f32 * 0.1);
        grp.bench_function("clone", |b| b.iter(|| black_box(base.clone())));
        let mut g = base.clone();
        grp.bench_function("update_range", |b| {
            b.iter(|| {
                g.update_range(black_box(0.5 * w), 0.5 * h, 0.3 * w.min(h))
                    .unwrap()
            })
        });
        let mut g = base.clone();
        grp.bench_function("update_range_bearing", |b| {
            b.iter(|| {
                g.update_range_bearing(black_box(0.5 * w), 0.5 * h, 0.3 * w.min(h), 0.2)
                    .unwrap()
            })
        });
        // Same, every cell with a definite heading: no block of unknown
        // headings to skip, the bearing update's worst case. Each
        // iteration updates a fresh copy (made outside the timing).
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
                BatchSize::LargeInput,
            )
        });
        for r in [1usize, 5, 10, 30] {
            let mut g = base.clone();
            let radius = r as f32 * 0.1;
            grp.bench_with_input(BenchmarkId::new("dilate", r), &radius, |b, &radius| {
                b.iter(|| g.dilate(0.0, black_box(radius)))
            });
        }
        grp.bench_function("estimate", |b| b.iter(|| black_box(base.estimate())));
        let mut g = base.clone();
        let mut k = 0u32;
        grp.bench_function("step", |b| {
            b.iter(|| {
                k = k.wrapping_add(1);
                let turn = if k % 2 == 0 { 0.05 } else { -0.05 };
                g.predict(&Motion {
                    forward: 0.05,
                    lateral: 0.0,
                    turn,
                    dt: 0.2,
                })
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
