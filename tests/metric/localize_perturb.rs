//! Properties of paper 001's perturbations (`localize::perturb`): 100 % keeps everything, the
//! kept fraction is met within binomial tolerance, noise 0 is the identity, the noise has the
//! asked standard deviation, the same seed gives the same stream, and bad levels are refused.

use lplace::core::{Odometry, Pose2};
use lplace::localize::perturb::{perturb, PerturbError, Perturbation, KEEP_LEVELS};
use lplace::localize::{LandmarkReading, MetricFrame};
use proptest::prelude::*;

/// `n` frames of `per` readings each, with varied ranges and bearings.
fn frames(n: usize, per: usize) -> Vec<MetricFrame> {
    (0..n)
        .map(|k| MetricFrame {
            t: k as f64 * 0.5,
            dt: 0.5,
            odometry: Odometry {
                forward: 0.01 * k as f64,
                left: 0.0,
                turn: 0.001,
            },
            observations: (0..per)
                .map(|j| LandmarkReading {
                    subject: 6 + (j as u32 % 15),
                    range: 1.0 + 0.37 * ((k * per + j) % 17) as f64,
                    bearing: -0.5 + 0.061 * ((k + j) % 17) as f64,
                })
                .collect(),
            truth: Some(Pose2 {
                x: k as f64,
                y: 0.0,
                theta: 0.0,
            }),
        })
        .collect()
}

fn count(f: &[MetricFrame]) -> usize {
    f.iter().map(|x| x.observations.len()).sum()
}

proptest! {
    #[test]
    fn keeping_all_without_noise_is_the_identity(seed in any::<u64>(), n in 0usize..20, per in 0usize..6) {
        let f = frames(n, per);
        let out = perturb(&f, &Perturbation::default(), seed).unwrap();
        prop_assert_eq!(out, f);
    }

    #[test]
    fn full_keep_keeps_every_reading_even_with_noise(seed in any::<u64>(), sr in 0.0f64..2.0, sb in 0.0f64..45.0) {
        let f = frames(30, 4);
        let out = perturb(&f, &Perturbation::noise(sr, sb), seed).unwrap();
        prop_assert_eq!(count(&out), count(&f));
        for (a, b) in out.iter().zip(&f) {
            // Only readings change: time, odometry and truth are the input's.
            prop_assert_eq!(a.t, b.t);
            prop_assert_eq!(a.odometry, b.odometry);
            prop_assert_eq!(a.truth, b.truth);
            for (ra, rb) in a.observations.iter().zip(&b.observations) {
                prop_assert_eq!(ra.subject, rb.subject);
                prop_assert!(ra.range >= 0.0);
                prop_assert!(ra.bearing > -std::f64::consts::PI && ra.bearing <= std::f64::consts::PI);
            }
        }
    }

    #[test]
    fn kept_fraction_is_within_binomial_tolerance(seed in any::<u64>(), level in 0usize..4) {
        let keep = KEEP_LEVELS[level];
        let f = frames(400, 5); // 2000 readings
        let n = count(&f) as f64;
        let kept = count(&perturb(&f, &Perturbation::sparsity(keep), seed).unwrap()) as f64;
        // 5 binomial standard deviations: a false failure about once in 3.5 million cases.
        let tol = 5.0 * (n * keep * (1.0 - keep)).sqrt();
        prop_assert!((kept - n * keep).abs() <= tol.max(0.5), "kept {} of {} at {}", kept, n, keep);
    }

    #[test]
    fn same_seed_same_stream(seed in any::<u64>(), sr in 0.0f64..1.0, keep in 0.05f64..1.0) {
        let f = frames(40, 3);
        let p = Perturbation { range_sigma: sr, bearing_sigma: 0.1, keep };
        prop_assert_eq!(perturb(&f, &p, seed).unwrap(), perturb(&f, &p, seed).unwrap());
    }

    #[test]
    fn sparser_levels_keep_subsets_of_denser_ones(seed in any::<u64>()) {
        let f = frames(100, 3);
        let kept = |keep: f64| -> Vec<Vec<(u32, u64)>> {
            perturb(&f, &Perturbation::sparsity(keep), seed)
                .unwrap()
                .iter()
                .map(|x| x.observations.iter().map(|r| (r.subject, r.range.to_bits())).collect())
                .collect()
        };
        let (half, quarter) = (kept(0.5), kept(0.25));
        for (h, q) in half.iter().zip(&quarter) {
            for r in q {
                prop_assert!(h.contains(r));
            }
        }
    }
}

#[test]
fn noise_has_the_asked_standard_deviation() {
    // Ranges far from 0 so clamping never acts; bearings near 0 so wrapping never acts.
    let f = frames(1000, 4);
    let (sr, sb_deg) = (0.2, 3.0);
    let out = perturb(&f, &Perturbation::noise(sr, sb_deg), 11).unwrap();
    let mut dr = Vec::new();
    let mut db = Vec::new();
    for (a, b) in out.iter().zip(&f) {
        for (ra, rb) in a.observations.iter().zip(&b.observations) {
            dr.push(ra.range - rb.range);
            db.push(ra.bearing - rb.bearing);
        }
    }
    let stats = |v: &[f64]| {
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        (
            m,
            (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n).sqrt(),
        )
    };
    let (mr, sdr) = stats(&dr);
    let (mb, sdb) = stats(&db);
    // 4000 samples: the sample sd is within ~2 % of σ (1σ ≈ 1.1 %); the mean within 3σ/√n.
    assert!(mr.abs() < 3.0 * sr / 63.0, "range mean {mr}");
    assert!((sdr / sr - 1.0).abs() < 0.05, "range sd {sdr}");
    let sb = sb_deg.to_radians();
    assert!(mb.abs() < 3.0 * sb / 63.0, "bearing mean {mb}");
    assert!((sdb / sb - 1.0).abs() < 0.05, "bearing sd {sdb}");
    // Twice the level is exactly twice the noise on each reading (common random numbers).
    let out2 = perturb(&f, &Perturbation::noise(2.0 * sr, 0.0), 11).unwrap();
    let d1 = out[3].observations[1].range - f[3].observations[1].range;
    let d2 = out2[3].observations[1].range - f[3].observations[1].range;
    assert!((d2 - 2.0 * d1).abs() < 1e-9, "{d1} {d2}");
}

#[test]
fn ranges_are_clamped_at_zero_and_bad_levels_refused() {
    let f = frames(50, 4);
    let out = perturb(&f, &Perturbation::noise(50.0, 0.0), 3).unwrap();
    assert!(out
        .iter()
        .flat_map(|x| &x.observations)
        .any(|r| r.range == 0.0));
    assert!(out
        .iter()
        .flat_map(|x| &x.observations)
        .all(|r| r.range >= 0.0));
    assert!(matches!(
        perturb(&f, &Perturbation::sparsity(0.0), 1),
        Err(PerturbError::BadKeep { .. })
    ));
    assert!(matches!(
        perturb(&f, &Perturbation::sparsity(1.5), 1),
        Err(PerturbError::BadKeep { .. })
    ));
    assert!(matches!(
        perturb(&f, &Perturbation::noise(-0.1, 0.0), 1),
        Err(PerturbError::BadSigma {
            field: "range_sigma",
            ..
        })
    ));
    assert!(matches!(
        perturb(&f, &Perturbation::noise(0.0, f64::NAN), 1),
        Err(PerturbError::BadSigma {
            field: "bearing_sigma",
            ..
        })
    ));
}
