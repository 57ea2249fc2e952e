//! Time per step of the four methods of `lplace compare` — the Fuzzy Position Grid, the
//! particle filter with 500 and 2000 particles, Fuzzy R-MCL — on the same MRCLAM dataset 7
//! robot-1 stream (2745 frames), in one run, each driven by the same `localize::Drive`.
//! Goal (issue 6): the grid at ≤ 1/10 of PF(2000)'s time with an ATE no worse. Criterion's
//! throughput is in frames: time per step = 1 / (elements per second).
//!
//! Configurations: config/grid-mrclam.ron, config/pf.ron, config/rmcl.ron; seed 1 (as
//! `lplace compare`). Building a method is left out of the timing (`iter_batched`).
//! Skips with a message when the data is absent (`$LPLACE_DATA`, else `../shared/data`).
//!
//! `cargo bench --bench compare -- --warm-up-time 1 --measurement-time 20`

use std::fs::File;
use std::hint::black_box;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use lplace::baseline::{FuzzyRmcl, ParticleFilter, PfConfig, RmclConfig};
use lplace::grid::{GridConfig, Landmark, LandmarkTable};
use lplace::io::mrclam::{self, MergeOptions};
use lplace::localize::grid::GridLocalizer;
use lplace::localize::{Drive, Localizer, MetricFrame, RunOptions};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

fn data_dir() -> PathBuf {
    match std::env::var_os("LPLACE_DATA") {
        Some(d) => PathBuf::from(d).join("mrclam-dataset7"),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/mrclam-dataset7"),
    }
}

fn open(dir: &Path, name: &str) -> Res<BufReader<File>> {
    Ok(BufReader::new(File::open(dir.join(name))?))
}

/// Robot 1's frames and the surveyed landmarks.
fn load(dir: &Path) -> Res<(LandmarkTable, Vec<MetricFrame>)> {
    let codes = mrclam::read_barcodes(open(dir, "Barcodes.dat")?)?;
    let marks = mrclam::read_landmarks(open(dir, "Landmark_Groundtruth.dat")?)?;
    let table = LandmarkTable::new(
        marks
            .iter()
            .map(|m| Landmark {
                id: m.subject,
                x: m.x as f32,
                y: m.y as f32,
            })
            .collect(),
    )?;
    let odo = mrclam::read_odometry(open(dir, "Robot1_Odometry.dat")?)?;
    let meas = mrclam::read_measurements(open(dir, "Robot1_Measurement.dat")?, &codes)?;
    let truth = mrclam::read_groundtruth(open(dir, "Robot1_Groundtruth.dat")?)?;
    let frames = mrclam::merge(&odo, &meas.rows, &truth, &MergeOptions::default());
    Ok((table, frames))
}

fn config(rel: &str) -> Res<String> {
    Ok(std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel),
    )?)
}

/// One whole run: every frame through a fresh driver; returns the last estimate's x.
fn run<L: Localizer>(mut loc: L, table: &LandmarkTable, frames: &[MetricFrame]) -> f64 {
    let mut d = Drive::new(table, RunOptions::default());
    let mut x = 0.0;
    for f in frames {
        x = d.step(&mut loc, f).pose.x;
    }
    x
}

fn bench(c: &mut Criterion) {
    let dir = data_dir();
    let (table, frames) = match load(&dir) {
        Ok(v) => v,
        Err(e) => {
            eprintln!(
                "SKIP: MRCLAM dataset 7 robot 1 not readable at {} ({e}); set LPLACE_DATA",
                dir.display()
            );
            return;
        }
    };
    let cfgs = (|| -> Res<_> {
        let grid = GridConfig::from_ron(&config("config/grid-mrclam.ron")?)?;
        let pf = PfConfig::from_ron(&config("config/pf.ron")?)?;
        let rmcl = RmclConfig::from_ron(&config("config/rmcl.ron")?)?;
        Ok((grid, pf, rmcl))
    })();
    let Ok((grid, pf, rmcl)) = cfgs else {
        eprintln!("SKIP: config/grid-mrclam.ron, pf.ron or rmcl.ron missing or invalid");
        return;
    };
    // The sampling methods start spread over the grid's area, as in `lplace compare`.
    let Some(bounds) = grid.bounds.or_else(|| table.bounds(grid.margin)) else {
        eprintln!("SKIP: no landmarks");
        return;
    };
    let pf_n = |n: usize| PfConfig {
        particles: n,
        ..pf.clone()
    };
    let mut g = c.benchmark_group("compare/mrclam-robot1");
    g.throughput(Throughput::Elements(frames.len() as u64));
    // Whole runs of up to a few seconds: the fewest samples criterion allows.
    g.sample_size(10);
    let f = &frames[..];
    let t = &table;
    g.bench_function("fpg", |b| {
        b.iter_batched(
            || GridLocalizer::new(t, &grid).unwrap(),
            |loc| black_box(run(loc, t, f)),
            BatchSize::PerIteration,
        )
    });
    for n in [500usize, 2000] {
        let cfg = pf_n(n);
        g.bench_function(format!("pf:{n}"), |b| {
            b.iter_batched(
                || ParticleFilter::new(t, &cfg, bounds, 1).unwrap(),
                |loc| black_box(run(loc, t, f)),
                BatchSize::PerIteration,
            )
        });
    }
    g.bench_function("rmcl", |b| {
        b.iter_batched(
            || FuzzyRmcl::new(t, &rmcl, &grid, bounds, 1).unwrap(),
            |loc| black_box(run(loc, t, f)),
            BatchSize::PerIteration,
        )
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
