//! A simulated run shared by the baseline tests: a robot drives a circle among four landmarks,
//! reads range and bearing to each with seeded Gaussian noise, and reports odometry with seeded
//! multiplicative noise. Truth is exact.

#![allow(dead_code)]

use lplace::core::angle::wrap_pi_f32 as wrap_pi;
use lplace::core::rng::SplitMix64;
use lplace::core::{Odometry, Pose2};
use lplace::grid::{Landmark, LandmarkTable};
use lplace::localize::{LandmarkReading, MetricFrame};

/// Range noise σ (m) of the simulated camera.
pub const RANGE_SIGMA: f64 = 0.05;
/// Bearing noise σ (rad).
pub const BEARING_SIGMA: f64 = 0.03;
/// Odometry noise: σ of the multiplicative error.
pub const ODO_SIGMA: f64 = 0.05;
/// Frame period (s).
pub const DT: f64 = 0.2;

pub fn table() -> LandmarkTable {
    LandmarkTable::new(vec![
        Landmark {
            id: 1,
            x: 0.0,
            y: 0.0,
        },
        Landmark {
            id: 2,
            x: 6.0,
            y: 0.0,
        },
        Landmark {
            id: 3,
            x: 6.0,
            y: 6.0,
        },
        Landmark {
            id: 4,
            x: 0.0,
            y: 6.0,
        },
    ])
    .unwrap()
}

/// Extent of the simulated world.
pub const BOUNDS: [f32; 4] = [-1.0, -1.0, 7.0, 7.0];

/// True pose at frame `k`: a circle of radius 1.5 m about (3, 3), counter-clockwise at
/// 0.3 m/s, starting at (4.5, 3) heading +y.
pub fn truth(k: usize) -> Pose2 {
    let a = 0.2 * DT * k as f64; // ω = v / R = 0.3 / 1.5 = 0.2 rad/s
    Pose2 {
        x: 3.0 + 1.5 * a.cos(),
        y: 3.0 + 1.5 * a.sin(),
        theta: wrap_pi((a + std::f64::consts::FRAC_PI_2) as f32) as f64,
    }
}

/// `frames` frames of the run, noise drawn from `seed`.
pub fn run(frames: usize, seed: u64) -> Vec<MetricFrame> {
    let mut rng = SplitMix64::new(seed);
    let table = table();
    (0..frames)
        .map(|k| {
            let p = truth(k);
            let (odometry, dt) = if k == 0 {
                (Odometry::default(), 0.0)
            } else {
                // The true increment in the previous robot frame, with multiplicative noise.
                let q = truth(k - 1);
                let (dx, dy) = (p.x - q.x, p.y - q.y);
                let (c, s) = (q.theta.cos(), q.theta.sin());
                let o = Odometry {
                    forward: (c * dx + s * dy) * (1.0 + ODO_SIGMA * rng.normal()),
                    left: (-s * dx + c * dy) * (1.0 + ODO_SIGMA * rng.normal()),
                    turn: wrap_pi((p.theta - q.theta) as f32) as f64
                        * (1.0 + ODO_SIGMA * rng.normal()),
                };
                (o, DT)
            };
            let observations = table
                .landmarks()
                .iter()
                .map(|m| {
                    let (dx, dy) = (m.x as f64 - p.x, m.y as f64 - p.y);
                    LandmarkReading {
                        subject: m.id,
                        range: (dx.hypot(dy) + RANGE_SIGMA * rng.normal()).max(0.0),
                        bearing: wrap_pi(
                            (dy.atan2(dx) - p.theta + BEARING_SIGMA * rng.normal()) as f32,
                        ) as f64,
                    }
                })
                .collect();
            MetricFrame {
                t: DT * k as f64,
                dt,
                odometry,
                observations,
                truth: Some(p),
            }
        })
        .collect()
}

/// Mean position error over the last `n` frames of a report.
pub fn tail_error(frames: &[lplace::localize::FrameEstimate], n: usize) -> f64 {
    let tail = &frames[frames.len() - n..];
    tail.iter().filter_map(|f| f.error).sum::<f64>() / n as f64
}
