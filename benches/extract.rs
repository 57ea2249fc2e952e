//! Extraction cost per laser scan: the front-sector line fits (L1, L2, L3),
//! eq. (3), the two side-beam readings and the two sonar-wall fits of
//! eq. (4) — everything `ScanExtractor::step` does — on synthetic 180-beam
//! scans of a corridor with noise, as in the Intel log. The project goal is
//! extraction + evaluation of the whole Intel log (910 scans over 2,651 s)
//! at ≥ 10,000× real time, i.e. ≤ 29 ms per scan for both together.

use std::f64::consts::{FRAC_PI_2, PI};
use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use lplace::core::Pose2;
use lplace::percept::line_fit::fit_line;
use lplace::percept::scan::ScanView;
use lplace::percept::{ExtractConfig, ScanExtractor};
use nalgebra::Point2;

/// 180 beams in a 2 m wide corridor ending in a wall 6 m ahead, with ±1 cm
/// deterministic pseudo-noise.
fn corridor_scan(seed: u64) -> Vec<f64> {
    let mut s = seed | 1;
    (0..180)
        .map(|i| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let noise = ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.02;
            let b = -FRAC_PI_2 + i as f64 * PI / 180.0;
            let (sn, c) = b.sin_cos();
            let side = if sn.abs() > 1e-9 {
                1.0 / sn.abs()
            } else {
                f64::INFINITY
            };
            let front = if c > 1e-9 { 6.0 / c } else { f64::INFINITY };
            side.min(front).min(81.91) + noise
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let scans: Vec<Vec<f64>> = (0..64).map(corridor_scan).collect();
    let mut ex = ScanExtractor::new(ExtractConfig::default()).expect("default config is valid");
    let mut k = 0usize;
    c.bench_function("scan_extract_180_beams", |b| {
        b.iter(|| {
            k += 1;
            let view = ScanView {
                pose: Pose2 {
                    x: 0.3 * k as f64,
                    y: 0.0,
                    theta: 0.0,
                },
                ranges: &scans[k % scans.len()],
                first_bearing: -FRAC_PI_2,
                bearing_step: PI / 180.0,
                laser_offset_x: 0.0,
            };
            black_box(ex.step(black_box(&view)))
        })
    });
    let pts: Vec<Point2<f64>> = (0..90)
        .map(|i| Point2::new(i as f64 * 0.05, 2.0 + (i % 3) as f64 * 0.01))
        .collect();
    c.bench_function("fit_line_90_points", |b| {
        b.iter(|| black_box(fit_line(black_box(&pts))))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
