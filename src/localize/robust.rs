//! Perturbations of what a localizer is *given* rather than what it reads, for robustness
//! measurements: the landmark map moved by a bounded, seeded amount ([`jitter_landmarks`]), and
//! a grid configuration with one value changed at a time ([`nudged_configs`]). A localizer
//! whose error moves by much more than such changes warrant is fitted to noise in its inputs
//! (a survey is good to a millimetre or so; a tuned value is not known to 1 %).
//! The readings' perturbations (paper 001's noisy and sparse data) are [`super::perturb`]'s.
//!
//! # Complexity
//!
//! [`jitter_landmarks`]: O(landmarks). [`nudged_configs`]: O(values²) (one copy of the
//! configuration per value).
//!
//! # Example
//!
//! ```
//! use lplace::grid::{GridConfig, Landmark, LandmarkTable};
//! use lplace::localize::robust::{jitter_landmarks, nudged_configs};
//! let t = LandmarkTable::new(vec![Landmark { id: 6, x: 1.0, y: 2.0 }]).unwrap();
//! let j = jitter_landmarks(&t, 0.001, 7).unwrap();
//! assert!((j.landmarks()[0].x - 1.0).abs() <= 0.001 + 1e-6);
//! let nudged = nudged_configs(&GridConfig::default(), 1.01);
//! let (name, cfg) = nudged.iter().find(|(n, _)| n == "cell_size").unwrap();
//! assert!((cfg.cell_size - 0.101).abs() < 1e-6, "{name}");
//! ```

use crate::core::rng::SplitMix64;
use crate::grid::{GridConfig, GridError, Landmark, LandmarkTable};
use serde_json::Value;

/// `table` with every landmark's x and y moved by independent uniform draws in
/// `[−amplitude, amplitude]` metres, from `seed` (same seed, same map).
///
/// # Errors
/// [`GridError`] when the moved table is rejected (a non-finite amplitude).
pub fn jitter_landmarks(
    table: &LandmarkTable,
    amplitude: f64,
    seed: u64,
) -> Result<LandmarkTable, GridError> {
    let mut rng = SplitMix64::new(seed);
    let moved = table
        .landmarks()
        .iter()
        .map(|m| Landmark {
            id: m.id,
            x: (m.x as f64 + rng.uniform(-amplitude, amplitude)) as f32,
            y: (m.y as f64 + rng.uniform(-amplitude, amplitude)) as f32,
        })
        .collect();
    LandmarkTable::new(moved)
}

/// One copy of `cfg` per non-zero number in it (nested ones included, e.g. `range.core_abs`),
/// that number multiplied by `factor`, named by its path; copies the configuration's checks
/// reject (a value pushed out of its range) are left out.
pub fn nudged_configs(cfg: &GridConfig, factor: f64) -> Vec<(String, GridConfig)> {
    let Ok(base) = serde_json::to_value(cfg) else {
        return Vec::new();
    };
    let mut paths = Vec::new();
    number_paths(&base, String::new(), &mut paths);
    paths
        .into_iter()
        .filter_map(|path| {
            let mut v = base.clone();
            let leaf = path
                .split('.')
                .try_fold(&mut v, |node, key| node.get_mut(key))?;
            let x = leaf.as_f64()? * factor;
            *leaf = Value::from(x);
            let nudged: GridConfig = serde_json::from_value(v).ok()?;
            nudged.validate().ok()?;
            Some((path, nudged))
        })
        .collect()
}

/// Dotted paths of the non-zero finite numbers under `v`, in document order.
fn number_paths(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Number(n) if n.as_f64().is_some_and(|x| x != 0.0 && x.is_finite()) => out.push(at),
        Value::Object(fields) => {
            for (k, child) in fields {
                let path = if at.is_empty() {
                    k.clone()
                } else {
                    format!("{at}.{k}")
                };
                number_paths(child, path, out);
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Blur;

    #[test]
    fn every_nonzero_value_is_nudged_once_and_alone() {
        let cfg = GridConfig {
            blur: Blur::Carry { level: 0.5 },
            ..GridConfig::default()
        };
        let nudged = nudged_configs(&cfg, 1.01);
        let names: Vec<&str> = nudged.iter().map(|(n, _)| n.as_str()).collect();
        for name in [
            "cell_size",
            "range.core_abs",
            "bearing.bias",
            "blur.Carry.level",
            "floor",
        ] {
            assert!(names.contains(&name), "{name} in {names:?}");
        }
        // Zero values (bearing.core_rel) are not nudged.
        assert!(!names.contains(&"bearing.core_rel"));
        let (_, c) = nudged.iter().find(|(n, _)| n == "range.bias").unwrap();
        assert!((c.range.bias - 0.101).abs() < 1e-6);
        assert_eq!(c.range.core_abs, cfg.range.core_abs);
        assert_eq!(c.cell_size, cfg.cell_size);
        // fix_reliability 0.5 → 0.505 is valid; a level of 1 pushed above 1 is not.
        let edge = GridConfig {
            blur: Blur::Carry { level: 1.0 },
            ..GridConfig::default()
        };
        assert!(!nudged_configs(&edge, 1.01)
            .iter()
            .any(|(n, _)| n == "blur.Carry.level"));
    }

    #[test]
    fn jitter_is_bounded_seeded_and_keeps_ids() {
        let t = LandmarkTable::new(
            (0..20)
                .map(|i| Landmark {
                    id: i + 6,
                    x: i as f32,
                    y: -(i as f32),
                })
                .collect(),
        )
        .unwrap();
        let a = jitter_landmarks(&t, 0.001, 3).unwrap();
        assert_eq!(a, jitter_landmarks(&t, 0.001, 3).unwrap());
        assert_ne!(a, jitter_landmarks(&t, 0.001, 4).unwrap());
        let mut moved = 0;
        for (m, j) in t.landmarks().iter().zip(a.landmarks()) {
            assert_eq!(m.id, j.id);
            let (dx, dy) = ((j.x - m.x).abs(), (j.y - m.y).abs());
            assert!(dx <= 0.001 + 1e-5 && dy <= 0.001 + 1e-5, "{dx} {dy}");
            moved += (dx > 1e-4) as usize;
        }
        assert!(moved > 10, "{moved}");
    }
}
