//! The tracker settings a rule file carries (`tracker { … }`, checked by
//! [`crate::rules::TrackerSettings`]) as a [`TrackerConfig`]: each key given replaces the
//! default of its field, and a `grid { … }` block asks for the grid tracker, its absent keys
//! taking [`GridTrackConfig`]'s defaults — what a RON tracker file with the same fields gives.

use super::grid_tracker::GridTrackConfig;
use super::tracker::TrackerConfig;
use crate::logic::{Normalisation, TNorm};
use crate::rules::{TrackerSettings, TrackerValue};

impl TrackerConfig {
    /// The configuration that `settings` describe, over the defaults.
    pub fn from_settings(settings: &TrackerSettings) -> TrackerConfig {
        let mut c = TrackerConfig::default();
        for (key, v) in &settings.fields {
            match (*key, *v) {
                ("tnorm", TrackerValue::Word(w)) => c.tnorm = tnorm(w),
                ("normalisation", TrackerValue::Word(w)) => {
                    c.normalisation = if w == "min" {
                        Normalisation::Min
                    } else {
                        Normalisation::Product
                    }
                }
                ("use_heading", TrackerValue::Word(w)) => c.use_heading = w == "true",
                (key, TrackerValue::Number(x)) => {
                    if let Some(field) = number_field(&mut c, key) {
                        *field = x;
                    }
                }
                // The checker gives each key the kind of value its field takes.
                _ => {}
            }
        }
        c.grid = settings.grid.as_ref().map(|g| {
            let mut grid = GridTrackConfig::default();
            for (key, x) in g {
                if let Some(field) = grid_field(&mut grid, key) {
                    *field = *x;
                }
            }
            grid
        });
        c
    }
}

fn tnorm(w: &str) -> TNorm {
    match w {
        "min" => TNorm::Min,
        "lukasiewicz" => TNorm::Lukasiewicz,
        _ => TNorm::Product,
    }
}

/// The numeric field of [`TrackerConfig`] named `key`.
fn number_field<'c>(c: &'c mut TrackerConfig, key: &str) -> Option<&'c mut f64> {
    Some(match key {
        "bias" => &mut c.bias,
        "tolerance" => &mut c.tolerance,
        "tolerance_rel" => &mut c.tolerance_rel,
        "slope" => &mut c.slope,
        "slope_rel" => &mut c.slope_rel,
        "anchor_support" => &mut c.anchor_support,
        "min_support" => &mut c.min_support,
        "hold" => &mut c.hold,
        "conflict" => &mut c.conflict,
        "tolerance_d" => &mut c.tolerance_d,
        "tolerance_d_rel" => &mut c.tolerance_d_rel,
        "slope_d" => &mut c.slope_d,
        "slope_d_rel" => &mut c.slope_d_rel,
        "evidence_length_m" => &mut c.evidence_length_m,
        "horizon_m" => &mut c.horizon_m,
        _ => return None,
    })
}

/// The field of [`GridTrackConfig`] named `key`.
fn grid_field<'c>(g: &'c mut GridTrackConfig, key: &str) -> Option<&'c mut f64> {
    Some(match key {
        "cell_size" => &mut g.cell_size,
        "margin" => &mut g.margin,
        "flank" => &mut g.flank,
        "flank_per_metre" => &mut g.flank_per_metre,
        "floor" => &mut g.floor,
        "evidence_length_m" => &mut g.evidence_length_m,
        "evidence_max_weight" => &mut g.evidence_max_weight,
        "evidence_scans" => &mut g.evidence_scans,
        "relative_floor" => &mut g.relative_floor,
        "start_radius" => &mut g.start_radius,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules::{GRID_KEYS, TRACKER_KEYS};

    /// Every key the checker accepts reaches a field: set alone to a value no default has, it
    /// changes the configuration (and a grid key, the grid's).
    #[test]
    fn every_checked_key_sets_its_field() {
        let words = [
            ("tnorm", "min"),
            ("normalisation", "min"),
            ("use_heading", "false"),
        ];
        for key in TRACKER_KEYS {
            let v = match words.iter().find(|(k, _)| k == key) {
                Some((_, w)) => TrackerValue::Word(w),
                None => TrackerValue::Number(0.123),
            };
            let s = TrackerSettings {
                fields: [(*key, v)].into_iter().collect(),
                grid: None,
            };
            assert_ne!(
                TrackerConfig::from_settings(&s),
                TrackerConfig::default(),
                "{key}"
            );
        }
        for key in GRID_KEYS {
            let s = TrackerSettings {
                fields: Default::default(),
                grid: Some([(*key, 0.123)].into_iter().collect()),
            };
            let g = TrackerConfig::from_settings(&s).grid.unwrap();
            assert_ne!(g, GridTrackConfig::default(), "{key}");
        }
    }

    /// As many keys as the RON form of the configuration has fields (so that none is missing).
    #[test]
    fn the_keys_cover_every_field() {
        let fields = |text: String| text.matches(':').count();
        let top = ron::to_string(&TrackerConfig::default()).unwrap();
        assert_eq!(fields(top), TRACKER_KEYS.len() + 1, "grid is the one more");
        let grid = ron::to_string(&GridTrackConfig::default()).unwrap();
        assert_eq!(fields(grid), GRID_KEYS.len());
    }
}
