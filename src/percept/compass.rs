//! Compass percepts for a robot in a rectilinear (Manhattan) building: a heading estimate that
//! stays locked to the building's axes, and the free range towards each compass direction.
//! Depends on the scan view and [`Pose2`] only; knows nothing about maps or rules.
//!
//! # Heading
//! Raw odometry heading drifts without bound, but in a building whose walls run along two
//! perpendicular axes a single scan fixes the heading *modulo 90°*: the dominant direction of
//! its wall segments. [`CompassTracker`] keeps a heading state `θ_k` and, for each scan,
//! predicts `θ_k⁻ = θ_{k−1} + Δθ_odometry`, measures the scan's wall orientation `α` (robot
//! frame, mod 90°) and takes the value `θ ≡ axis − α (mod 90°)` nearest to the prediction.
//! This stays locked as long as the odometry's heading error *between two scans* is below 45°;
//! a scan whose candidate is farther from the prediction than a gate (clutter, a diagonal
//! wall) is ignored, so one bad scan cannot flip the heading by a quarter-turn. The gate is
//! `max_correction_deg`, widened by `gate_growth_deg_per_m` for every metre travelled and by
//! `gate_growth_per_deg` for every degree turned since the last accepted correction (odometry
//! drifts with motion, not with the number of scans), and never wider than 40°; a weak scan (share of
//! the vote between `weak_peak_fraction` and `min_peak_fraction`) may only correct by up to
//! `max_correction_deg`.
//! Odometry heading also drifts *systematically* (unequal wheel diameters turn every straight
//! metre by a few degrees: ≈ −3.6°/m in the Intel log), and that bias, not noise, is what walks
//! the prediction past 45° while the scans are too weak to correct it. So the tracker keeps an
//! estimate `δ` of the drift per metre travelled: the prediction is `θ_{k−1} + Δθ + δ·|Δxy|`,
//! and each strong correction `c` accepted after `d ≥ drift_min_distance_m` metres updates
//! `δ ← δ + drift_gain · c / d` (an integral controller on the residual; `drift_gain = 0`
//! turns it off).
//! The initial quarter-turn is taken from the first frame's odometry heading (in a raw log,
//! the odometry frame the map is drawn in; see `initial_heading_deg` to state it instead).
//!
//! # Turn between scans
//! The lock holds only while the prediction's error stays under 45°, and some logs' odometry
//! turns up to 30° wrong between two scans where the walls are curved and give the lock no
//! right angle to correct it with (CSAIL: more than 10° wrong on 18 % of the steps). With
//! `scan_rotation` the prediction's turn is measured on the scans instead, by correlating the
//! directions of the previous and the current scan's segments within
//! `±scan_rotation_window_deg` of the odometry's turn ([`super::scan_rotation`]), which needs no
//! right angle; when their correlation has no clear peak the odometry's turn (and the learnt
//! drift) is kept, and with `scan_rotation_min_disagreement_deg > 0` it is kept too unless the
//! two differ by more than that. It is off by default: measured with the heading against the
//! true poses (within 10°, 2026-12-03), it lifts CSAIL from 5.2 % to 47.0 % of the scans and
//! Freiburg 101 from 90.4 % to 93.2 %, leaves Seattle at 100 %, but lowers the Intel lab from
//! 98.5 % to 95.9 %, whose odometry turns right between scans and only drifts, and its
//! rows of the buildings table with it, and Freiburg 101's too (`docs/new-building.md`, section 5).
//!
//! # Motion between scans
//! With `scan_match` the prediction's motion is measured on the scans by a point-to-line ICP
//! of the current scan onto the previous one ([`super::scan_match`]), started from the
//! odometry's motion and from up to `scan_match_starts` candidate turns of the scans'
//! line-direction correlation within `±scan_match_window_deg` of the odometry's turn; its turn
//! (and with `scan_match_translation` its translation) replaces the odometry's when the match
//! is accepted. A match refused only because the walls leave its motion free (a corridor:
//! it converged onto the previous scan's lines, residual and overlap pass) still gives the
//! step its turn, with the odometry's translation, when that turn agrees with the odometry's
//! within `scan_match_agreement_deg`: two independent measurements of one turn agree. Otherwise
//! the odometry is kept, and counted ([`CompassTracker::scan_matches`]). `scan_match` takes
//! precedence over `scan_rotation`, which is tried when the match is refused. A matched turn is
//! the robot's to within a degree or two, so with `scan_match` the axis lock may only correct
//! by `scan_match_max_correction_deg`, widened by `scan_match_gate_growth_deg_per_m` per metre
//! of matched motion up to `scan_match_max_gate_growth_deg` and, as before, by
//! `gate_growth_deg_per_m` and `gate_growth_per_deg` for the odometry's motion since the last
//! correction (a curved wall or a wing off the axes must not pull a heading the scans hold,
//! however far the robot drove without seeing the building's axes); the drift is learnt from
//! the odometry's steps alone. Off in [`CompassConfig::default`] (the buildings' own configs
//! keep their measured behaviour), on in the settings `lplace extract` uses without `--config`
//! ([`super::ExtractConfig::travelling`]). Measured with the heading against the true poses
//! (within 10°, 2026-12-03, those settings; before the scan match → with it → with the
//! agreement and the bounded gate): Intel 98.5 → 99.8 → 99.8 %, Freiburg 101 90.4 → 91.8 →
//! 87.0 %, Seattle 100 %, CSAIL 5.2 → 80.8 → 94.6 %. Freiburg 101's hall has walls in two
//! directions 9–10° apart (its axis, −11°, and about −2°), and the lock follows either
//! (`docs/new-building.md`, section 5).
//!
//! # Orientation of a scan
//! Every pair of scan points `segment_deg` apart (the nearest whole number of beams, at least
//! one: 1 beam at 1° resolution, 2 at 0.5°, 4 at 0.25°, so that range quantisation tilts the
//! segments of a fine scanner no more than those of a coarse one), both valid and at most
//! `max_gap_m` apart,
//! is a short wall segment; its direction, folded modulo 90°, votes with its length into a
//! histogram of 1° bins (smoothed over ±`smooth_deg`). The peak, refined by the circular mean
//! of the votes within `smooth_deg` of it, is the scan's orientation; it counts only when at
//! least `min_peak_fraction` of the total vote lies within `smooth_deg` of the peak.
//!
//! # Free ranges
//! Positions are dead-reckoned from the odometry translations rotated by the tracked heading;
//! the points of the scans of the last `history_m` metres of travel are kept in that frame, so
//! the view covers 360° (the scanner itself sees only 180°). Memory is counted in metres, not
//! scans, so that a log at 11 scans per metre sees as far back as one at 2: a scan stays in the
//! view only if the robot moved `keyframe_m` or turned `keyframe_deg` since the last scan that
//! stayed (the current scan is always in it), at most `history_scans` of them, and only every
//! beam `beam_deg` apart is kept, so the density of points does not depend on the scanner. For each compass direction `d` (East = +x,
//! North = +y of the map frame; the four cardinal ones, or with `directions: 8` the diagonals
//! too), the free range along a ray is the `rank`-th nearest distance along it of the kept
//! points lying within `band_m` of the ray from the robot, capped at `cap_m` (no point on the
//! ray reads as the cap); with `fan_deg > 0` it is the longest such range over a fan of rays
//! `fan_step_deg` apart within `±fan_deg` of `d`, so that a doorway or a corridor end a few
//! degrees off the compass ray, or a heading a few degrees off the truth, still reads as open. The percept `free_range(d)` carries the natural
//! logarithm of that range in metres as its value (so one relative tolerance serves a
//! doorway at 1 m and a corridor end at 10 m) and degree 1.

use serde::{Deserialize, Serialize};

use super::config::{finite, non_negative, positive, ConfigError};
use super::scan::ScanView;
use super::scan_match::{Match, MatchParams, ScanMatcher};
use super::scan_rotation::{
    line_histogram_of, rotation_between, rotation_candidates, segments, BINS as LINE_BINS,
};
use crate::core::angle::wrap_pi;
use crate::core::Pose2;

/// Most starts of the scan match besides the odometry's (`scan_match_starts`).
const MAX_STARTS: usize = 8;

/// Parameters of the compass percepts. RON-loadable; every field has a default.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CompassConfig {
    /// Emit the compass percepts at all. Default false.
    pub enabled: bool,
    /// Direction of one of the building's wall axes in the map frame, degrees. Default 0.
    pub axis_deg: f64,
    /// The initial heading in the map frame, degrees; `None` takes the first frame's
    /// odometry heading. Only its quarter-turn matters: the first scan refines it. Default
    /// `None`.
    pub initial_heading_deg: Option<f64>,
    /// Angle between the two beams that end a wall segment, degrees: the segment joins beams
    /// `round(segment_deg / resolution)` apart (at least one), so a 0.5° scanner's segments are
    /// as long as a 1° scanner's. Default 1.
    pub segment_deg: f64,
    /// Longest wall segment, metres (longer ones jump between surfaces). Default 0.2.
    pub max_gap_m: f64,
    /// Half-width of the histogram smoothing and of the peak window, degrees. Default 3.
    pub smooth_deg: f64,
    /// Least share of the vote within the peak window for the scan to count. Default 0.4.
    pub min_peak_fraction: f64,
    /// Least share for a *weak* scan, which may correct the heading by at most
    /// `max_correction_deg` (the growing gate is for scans above `min_peak_fraction`).
    /// Default 0.15.
    pub weak_peak_fraction: f64,
    /// Largest heading correction a scan may make, degrees: a scan whose orientation is
    /// farther from the odometry's prediction is taken as cluttered and ignored. Default 15.
    pub max_correction_deg: f64,
    /// How much the gate widens per metre travelled without a correction, degrees (odometry
    /// heading drifts with the distance, not with the number of scans). Default 10; the gate
    /// never exceeds 40°.
    pub gate_growth_deg_per_m: f64,
    /// How much the gate widens per degree turned without a correction (odometry heading
    /// drifts when the robot turns on the spot too). Default 0.1.
    pub gate_growth_per_deg: f64,
    /// Gain of the odometry heading-drift estimate (see the module docs), in [0, 1]; 0 turns
    /// the estimate off. Default 0.
    pub drift_gain: f64,
    /// Least distance travelled since the previous accepted correction, metres, for a
    /// correction to update the drift estimate. Default 0.5.
    pub drift_min_distance_m: f64,
    /// Metres of travel whose scans make up the local view (the current scan is always in
    /// it). Default 10 (chosen on the Intel log: 6, 8, 10 and 12 m were tried, see
    /// `docs/intel.md`).
    pub history_m: f64,
    /// Most scans kept in the local view, whatever the distance (bounds the cost). Default 64.
    pub history_scans: usize,
    /// A scan enters the local view for good when the robot has moved this far since the last
    /// scan that did, metres (so 2 or 11 scans per metre keep alike views). Default 0.2.
    pub keyframe_m: f64,
    /// … or turned this much, degrees. Default 10.
    pub keyframe_deg: f64,
    /// Angular spacing of the beams kept in the local view, degrees: finer scans are thinned
    /// to it, so the density of points (and the `rank`-th nearest) does not depend on the
    /// scanner. Default 1.
    pub beam_deg: f64,
    /// Directions with a free range: 4 (East, North, West, South) or 8 (and NorthEast,
    /// NorthWest, SouthWest, SouthEast). Default 4.
    pub directions: usize,
    /// Half-width of the fan of rays per direction, degrees; 0 = the one compass ray.
    /// Default 0.
    pub fan_deg: f64,
    /// Angle between the fan's rays, degrees. Default 5.
    pub fan_step_deg: f64,
    /// Half-width of the band around a compass ray, metres. Default 0.3.
    pub band_m: f64,
    /// Which nearest point along the ray is the free range (1 = the nearest). Default 3.
    pub rank: usize,
    /// Free ranges are capped here, metres. Default 15.
    pub cap_m: f64,
    /// Ranges below this are self-hits, metres. Default 0.05.
    pub min_range_m: f64,
    /// Ranges at or above this are "no return", metres. Default 40.
    pub max_range_m: f64,
    /// Take the turn between two scans from the scans (see the module docs, "Turn between
    /// scans") instead of the odometry's. Default false.
    pub scan_rotation: bool,
    /// Half-width of the window around the odometry's turn in which the scans' turn is
    /// sought, degrees, below 90. Default 35.
    pub scan_rotation_window_deg: f64,
    /// Least rise of the scans' correlation over the window for their turn to count (in
    /// [0, 1]). Default 0.2.
    pub scan_rotation_min_contrast: f64,
    /// The scans' turn replaces the odometry's only when they differ by more than this,
    /// degrees (odometry that turns right between scans, only biased, keeps its turn and its
    /// learnt drift). Default 0.
    pub scan_rotation_min_disagreement_deg: f64,
    /// Take the motion between two scans from a point-to-line ICP of the current scan onto
    /// the previous one (see the module docs, "Motion between scans", and
    /// [`super::scan_match`]) when it is accepted, instead of the odometry's. Default false
    /// (the settings `lplace extract` uses without `--config` turn it on:
    /// [`super::ExtractConfig::travelling`]).
    pub scan_match: bool,
    /// Most Gauss–Newton iterations per start of the match. Default 20.
    pub scan_match_iterations: usize,
    /// Starts of the match besides the odometry's turn: the highest peaks of the scans'
    /// line-direction correlation within `±scan_rotation_window_deg`. Default 3.
    pub scan_match_starts: usize,
    /// Half-width of the window around the odometry's turn in which the match's starts are
    /// sought, degrees, below 90. Default 25 (the CSAIL log's odometry
    /// turns more than 25° wrong on 2 of its 405 steps, 20° on 6).
    pub scan_match_window_deg: f64,
    /// Pairing gate of the match's first iteration, metres, at most 8 × `scan_match_min_pair_m`.
    /// Default 1.
    pub scan_match_max_pair_m: f64,
    /// Pairing gate of its last iterations (and of the overlap), metres. Default 0.2.
    pub scan_match_min_pair_m: f64,
    /// Largest weighted RMS point-to-line residual of an accepted match, metres (also the
    /// scale of its robust weights). Default 0.05.
    pub scan_match_max_rms_m: f64,
    /// Least share of the current scan's points on a line of the previous scan for a match
    /// to be accepted, in [0, 1]. Default 0.3.
    pub scan_match_min_overlap: f64,
    /// Least smallest eigenvalue of the match's normal matrix per unit weight (0 when the
    /// walls leave a direction of the motion free, as a corridor's do), in [0, 1].
    /// Default 0.01.
    pub scan_match_min_constraint: f64,
    /// Also take the matched translation (not only the turn) for the dead-reckoned position;
    /// the match must then constrain every direction of the motion, not only the turn.
    /// Default true.
    pub scan_match_translation: bool,
    /// Largest heading correction a scan may make when the step's motion came from the scan
    /// match, degrees (the match's turn is the robot's to within a degree or two: a wall a few
    /// degrees off the axes must not pull it). Default 3.
    pub scan_match_max_correction_deg: f64,
    /// How much that gate widens per metre travelled on matched motion without a correction,
    /// degrees. Default 1.
    pub scan_match_gate_growth_deg_per_m: f64,
    /// Most that matched motion may widen the gate, degrees. Default 10 (a heading the scans
    /// hold does not drift by more over any distance, while walls 20–30° off the axes, a
    /// wing of the building, would capture a gate widened without bound).
    pub scan_match_max_gate_growth_deg: f64,
    /// A match refused only because the walls leave a direction of its motion free (it
    /// converged, its residual and overlap pass) still gives the step its turn, with the
    /// odometry's translation, when that turn agrees with the odometry's within this many
    /// degrees: two independent measurements of the turn agree. 0 turns it off. Default 3.
    pub scan_match_agreement_deg: f64,
}

impl Default for CompassConfig {
    fn default() -> Self {
        CompassConfig {
            enabled: false,
            axis_deg: 0.0,
            initial_heading_deg: None,
            segment_deg: 1.0,
            max_gap_m: 0.2,
            smooth_deg: 3.0,
            min_peak_fraction: 0.4,
            weak_peak_fraction: 0.15,
            max_correction_deg: 15.0,
            gate_growth_deg_per_m: 10.0,
            gate_growth_per_deg: 0.1,
            drift_gain: 0.0,
            drift_min_distance_m: 0.5,
            history_m: 10.0,
            history_scans: 64,
            keyframe_m: 0.2,
            keyframe_deg: 10.0,
            beam_deg: 1.0,
            directions: 4,
            fan_deg: 0.0,
            fan_step_deg: 5.0,
            band_m: 0.3,
            rank: 3,
            cap_m: 15.0,
            min_range_m: 0.05,
            max_range_m: 40.0,
            scan_rotation: false,
            scan_rotation_window_deg: 35.0,
            scan_rotation_min_contrast: 0.2,
            scan_rotation_min_disagreement_deg: 0.0,
            scan_match: false,
            scan_match_iterations: 20,
            scan_match_starts: 3,
            scan_match_window_deg: 25.0,
            scan_match_max_pair_m: 1.0,
            scan_match_min_pair_m: 0.2,
            scan_match_max_rms_m: 0.05,
            scan_match_min_overlap: 0.3,
            scan_match_min_constraint: 0.01,
            scan_match_translation: true,
            scan_match_max_correction_deg: 3.0,
            scan_match_gate_growth_deg_per_m: 1.0,
            scan_match_max_gate_growth_deg: 10.0,
            scan_match_agreement_deg: 3.0,
        }
    }
}

impl CompassConfig {
    /// Checks every parameter's range.
    ///
    /// # Errors
    /// [`ConfigError::Invalid`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        finite("compass.axis_deg", self.axis_deg)?;
        if let Some(h) = self.initial_heading_deg {
            finite("compass.initial_heading_deg", h)?;
        }
        for (field, v) in [
            ("compass.history_scans", self.history_scans),
            ("compass.rank", self.rank),
        ] {
            if v == 0 {
                return Err(ConfigError::invalid(field, 0.0, "must be ≥ 1"));
            }
        }
        positive("compass.max_gap_m", self.max_gap_m)?;
        positive("compass.smooth_deg", self.smooth_deg)?;
        non_negative("compass.min_peak_fraction", self.min_peak_fraction)?;
        non_negative("compass.weak_peak_fraction", self.weak_peak_fraction)?;
        positive("compass.max_correction_deg", self.max_correction_deg)?;
        non_negative("compass.gate_growth_deg_per_m", self.gate_growth_deg_per_m)?;
        non_negative("compass.gate_growth_per_deg", self.gate_growth_per_deg)?;
        positive("compass.segment_deg", self.segment_deg)?;
        non_negative("compass.history_m", self.history_m)?;
        non_negative("compass.keyframe_m", self.keyframe_m)?;
        non_negative("compass.keyframe_deg", self.keyframe_deg)?;
        positive("compass.beam_deg", self.beam_deg)?;
        if !(0.0..=1.0).contains(&self.drift_gain) {
            return Err(ConfigError::invalid(
                "compass.drift_gain",
                self.drift_gain,
                "must be in [0, 1]",
            ));
        }
        non_negative("compass.drift_min_distance_m", self.drift_min_distance_m)?;
        if self.directions != 4 && self.directions != 8 {
            return Err(ConfigError::invalid(
                "compass.directions",
                self.directions as f64,
                "must be 4 or 8",
            ));
        }
        non_negative("compass.fan_deg", self.fan_deg)?;
        if self.fan_deg > 45.0 {
            return Err(ConfigError::invalid(
                "compass.fan_deg",
                self.fan_deg,
                "must be at most 45 (a fan must stay within its direction's octant pair)",
            ));
        }
        positive("compass.fan_step_deg", self.fan_step_deg)?;
        positive("compass.band_m", self.band_m)?;
        positive("compass.cap_m", self.cap_m)?;
        non_negative("compass.min_range_m", self.min_range_m)?;
        positive("compass.max_range_m", self.max_range_m)?;
        for (field, v) in [
            (
                "compass.scan_rotation_min_contrast",
                self.scan_rotation_min_contrast,
            ),
            (
                "compass.scan_match_min_overlap",
                self.scan_match_min_overlap,
            ),
            (
                "compass.scan_match_min_constraint",
                self.scan_match_min_constraint,
            ),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(ConfigError::invalid(field, v, "must be in [0, 1]"));
            }
        }
        self.validate_scan_match()
    }

    /// The ranges of the parameters of the turn and the motion between scans.
    fn validate_scan_match(&self) -> Result<(), ConfigError> {
        let w = self.scan_rotation_window_deg;
        if !(1.0..90.0).contains(&w) {
            return Err(ConfigError::invalid(
                "compass.scan_rotation_window_deg",
                w,
                "must be in [1, 90) (lines fold modulo 180°, a room's modulo 90°)",
            ));
        }
        non_negative(
            "compass.scan_rotation_min_disagreement_deg",
            self.scan_rotation_min_disagreement_deg,
        )?;
        if self.scan_match_iterations == 0 {
            return Err(ConfigError::invalid(
                "compass.scan_match_iterations",
                0.0,
                "must be ≥ 1",
            ));
        }
        if self.scan_match_starts > MAX_STARTS {
            return Err(ConfigError::invalid(
                "compass.scan_match_starts",
                self.scan_match_starts as f64,
                "must be at most 8",
            ));
        }
        let w = self.scan_match_window_deg;
        if !(1.0..90.0).contains(&w) {
            return Err(ConfigError::invalid(
                "compass.scan_match_window_deg",
                w,
                "must be in [1, 90)",
            ));
        }
        positive("compass.scan_match_max_pair_m", self.scan_match_max_pair_m)?;
        positive("compass.scan_match_min_pair_m", self.scan_match_min_pair_m)?;
        if self.scan_match_min_pair_m > self.scan_match_max_pair_m {
            return Err(ConfigError::invalid(
                "compass.scan_match_min_pair_m",
                self.scan_match_min_pair_m,
                "must be at most scan_match_max_pair_m",
            ));
        }
        // The pairing grid's cells are `min_pair_m` wide and a query looks at most 8 cells
        // away: a wider first gate would silently miss pairs.
        if self.scan_match_max_pair_m > 8.0 * self.scan_match_min_pair_m {
            return Err(ConfigError::invalid(
                "compass.scan_match_max_pair_m",
                self.scan_match_max_pair_m,
                "must be at most 8 × scan_match_min_pair_m",
            ));
        }
        positive(
            "compass.scan_match_max_correction_deg",
            self.scan_match_max_correction_deg,
        )?;
        for (field, v) in [
            (
                "compass.scan_match_gate_growth_deg_per_m",
                self.scan_match_gate_growth_deg_per_m,
            ),
            (
                "compass.scan_match_max_gate_growth_deg",
                self.scan_match_max_gate_growth_deg,
            ),
            (
                "compass.scan_match_agreement_deg",
                self.scan_match_agreement_deg,
            ),
        ] {
            non_negative(field, v)?;
        }
        positive("compass.scan_match_max_rms_m", self.scan_match_max_rms_m)
    }

    /// The match's parameters.
    fn match_params(&self) -> MatchParams {
        MatchParams {
            iterations: self.scan_match_iterations,
            max_pair_m: self.scan_match_max_pair_m,
            min_pair_m: self.scan_match_min_pair_m,
            max_rms_m: self.scan_match_max_rms_m,
            min_overlap: self.scan_match_min_overlap,
            min_constraint: self.scan_match_min_constraint,
        }
    }
}

/// The compass directions, in the order of [`CompassTracker::step`]'s output (the one table in
/// [`crate::core::compass`]).
pub use crate::core::compass::DIRECTIONS;

/// One compass percept: `free_range(direction)` with its value (ln metres) and degree.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CompassRecord {
    /// Rule-file constant of the direction (`East`, `North`, …, see [`DIRECTIONS`]).
    pub direction: &'static str,
    /// Natural logarithm of the free range in metres.
    pub value: Option<f64>,
    /// Engine degree in `[0, 1]`.
    pub degree: f64,
}

/// The wall orientation of a scan, robot frame, radians in `[0, π/2)`, with the share of the
/// vote behind it; `None` when the scan has no wall segments.
///
/// # Complexity
/// `O(n)` in the number of beams plus 90 bins; no allocation.
pub fn orientation(scan: &ScanView<'_>, cfg: &CompassConfig) -> Option<(f64, f64)> {
    let mut local = Vec::with_capacity(scan.ranges.len());
    local_points(scan, cfg, &mut Vec::new(), &mut local);
    let mut found = Vec::new();
    let stride = beams_apart(cfg.segment_deg, scan.bearing_step);
    segments(&local, stride, cfg.max_gap_m, &mut found);
    orientation_of(&found, cfg)
}

/// How many beams of a scan with `step` radians between beams make up `angle_deg` degrees, at
/// least one (also for a step that is zero or not finite).
pub fn beams_apart(angle_deg: f64, step: f64) -> usize {
    let n = (angle_deg.to_radians() / step.abs()).round();
    if n.is_finite() && n >= 1.0 {
        n.min(1e6) as usize
    } else {
        1
    }
}

/// The scan's beams as points in the robot frame (`None` where a beam has no valid return),
/// into `out`. `dirs` caches each beam's `(cos, sin)` for the scan's geometry, recomputed
/// only when the beam count changes (the bearings of a scan are `first + i · step`, the same
/// for every scan of a log), so a scan costs no trigonometry.
fn local_points(
    scan: &ScanView<'_>,
    cfg: &CompassConfig,
    dirs: &mut Vec<(f64, f64, f64)>,
    out: &mut Vec<Option<(f64, f64)>>,
) {
    out.clear();
    if !(scan.bearing_step.is_finite() && scan.first_bearing.is_finite()) {
        return;
    }
    let n = scan.ranges.len();
    let stale = dirs.len() != n
        || dirs.first().is_some_and(|d| d.2 != scan.first_bearing)
        || dirs
            .get(1)
            .is_some_and(|d| d.2 != scan.first_bearing + scan.bearing_step);
    if stale {
        dirs.clear();
        dirs.extend((0..n).map(|i| {
            let b = scan.first_bearing + i as f64 * scan.bearing_step;
            (b.cos(), b.sin(), b)
        }));
    }
    out.extend(scan.ranges.iter().zip(dirs.iter()).map(|(&r, &(c, s, _))| {
        (r.is_finite() && r >= cfg.min_range_m && r < cfg.max_range_m)
            .then_some((scan.laser_offset_x + r * c, r * s))
    }));
}

/// [`orientation`] from the scan's [`segments`].
fn orientation_of(segments: &[(f64, f64)], cfg: &CompassConfig) -> Option<(f64, f64)> {
    let mut hist = [0.0f64; 90];
    let mut total = 0.0;
    for &(len, deg) in segments {
        let deg = deg.rem_euclid(90.0);
        let bin = (deg.floor() as usize).min(89);
        hist[bin] += len;
        total += len;
    }
    if total <= 0.0 {
        return None;
    }
    // Smoothed (circular, period 90) histogram; its peak.
    let w = cfg.smooth_deg.round().max(0.0) as i64;
    let window = |c: i64| -> f64 {
        (-w..=w)
            .map(|k| hist[(c + k).rem_euclid(90) as usize])
            .sum::<f64>()
    };
    let mut best = (0i64, f64::NEG_INFINITY);
    for c in 0..90 {
        let s = window(c);
        if s > best.1 {
            best = (c, s);
        }
    }
    // Circular mean of the votes near the peak, on the 4θ circle.
    let (mut sx, mut sy) = (0.0, 0.0);
    for k in -w..=w {
        let bin = (best.0 + k).rem_euclid(90) as usize;
        let ang = ((best.0 + k) as f64 + 0.5).to_radians() * 4.0;
        sx += hist[bin] * ang.cos();
        sy += hist[bin] * ang.sin();
    }
    let mean = (sy.atan2(sx) / 4.0).rem_euclid(std::f64::consts::FRAC_PI_2);
    Some((mean, best.1 / total))
}

/// Heading tracker and local 360° view; feed it every scan in order with
/// [`CompassTracker::step`].
#[derive(Debug, Clone)]
pub struct CompassTracker {
    cfg: CompassConfig,
    /// Tracked pose: dead-reckoned position, axis-locked heading.
    pose: Option<Pose2>,
    /// Points of recent scans in the tracked frame, oldest first; the last one is the current
    /// scan, kept for good only if it is a keyframe (see [`Slot`]).
    history: std::collections::VecDeque<Slot>,
    /// Buffers of slots that left the view, reused.
    spare: Vec<Vec<(f64, f64)>>,
    /// Distance travelled since the first scan, metres (the odometer).
    odometer: f64,
    /// Odometry turn since the first scan, radians (absolute values summed).
    turn: f64,
    /// Degrees turned on the odometry's motion since the last accepted correction.
    turned: f64,
    /// Distance travelled on matched motion since the last accepted correction, metres.
    matched_travel: f64,
    /// Whether the current step's motion came from an accepted scan match.
    matched_step: bool,
    /// Estimated odometry heading drift, radians per metre travelled.
    drift: f64,
    /// Distance travelled on the odometry's motion since the last accepted correction, metres.
    travelled: f64,
    /// The correction the last step's scan made to the predicted heading, radians, if it
    /// locked it.
    correction: Option<f64>,
    /// The rays of every direction's fan (see [`Rays`]).
    rays: Rays,
    /// Each beam's `(cos, sin, bearing)` for the scans' geometry (see [`local_points`]).
    dirs: Vec<(f64, f64, f64)>,
    /// The current scan's points in the robot frame.
    local: Vec<Option<(f64, f64)>>,
    /// The current scan's wall segments (see [`segments`]): the line histogram's and the
    /// orientation's votes.
    segments: Vec<(f64, f64)>,
    /// Per ray, the `rank` nearest distances found so far (ascending; `∞` = none yet).
    nearest: Vec<f64>,
    /// Per kept point, its arc of rays (see [`arc_of`]): scratch of `free_ranges`.
    arcs: Vec<(f32, f32)>,
    /// The last step's percepts, in [`DIRECTIONS`] order (the first `directions` are used).
    out: [CompassRecord; 8],
    /// Line-direction histograms of the previous and the current scan (`scan_rotation`), and
    /// whether the previous one has any segment.
    lines: Box<[[f64; LINE_BINS]; 2]>,
    lines_prev: bool,
    /// Steps whose turn came from the scans, and steps with a turn to take at all.
    scan_turns: (u64, u64),
    /// The scan matcher (`scan_match`), holding the previous scan.
    matcher: ScanMatcher,
    /// Steps whose motion came from an accepted match, and steps with a match to try.
    matches: (u64, u64),
    /// The turn of the last step's prediction, radians (the scans' or the odometry's).
    last_turn: Option<f64>,
}

impl CompassTracker {
    /// A tracker with parameters `cfg`.
    ///
    /// # Errors
    /// [`ConfigError`] when a parameter is out of range.
    pub fn new(cfg: CompassConfig) -> Result<Self, ConfigError> {
        cfg.validate()?;
        Ok(CompassTracker {
            cfg,
            pose: None,
            history: std::collections::VecDeque::new(),
            spare: Vec::new(),
            odometer: 0.0,
            turn: 0.0,
            turned: 0.0,
            matched_travel: 0.0,
            matched_step: false,
            drift: 0.0,
            travelled: 0.0,
            correction: None,
            rays: Rays::new(&cfg),
            dirs: Vec::new(),
            local: Vec::new(),
            segments: Vec::new(),
            nearest: Vec::new(),
            arcs: Vec::new(),
            out: [CompassRecord {
                direction: "East",
                value: None,
                degree: 0.0,
            }; 8],
            lines: Box::new([[0.0; LINE_BINS]; 2]),
            lines_prev: false,
            scan_turns: (0, 0),
            matcher: ScanMatcher::default(),
            matches: (0, 0),
            last_turn: None,
        })
    }

    /// The tracked pose (map frame, radians), once a scan has been seen.
    pub fn pose(&self) -> Option<Pose2> {
        self.pose
    }

    /// The parameters.
    pub fn config(&self) -> &CompassConfig {
        &self.cfg
    }

    /// The correction (radians) the last scan made to the heading predicted by the odometry
    /// and the learnt drift, if it locked the heading (its wall orientation was accepted; the
    /// first scan's initialisation is not a correction). Small corrections scan after scan
    /// mean a steady lock.
    pub fn correction(&self) -> Option<f64> {
        self.correction
    }

    /// Of the steps with an odometry increment so far, how many took their turn from the
    /// scans (`scan_rotation`), and how many there were.
    pub fn scan_turns(&self) -> (u64, u64) {
        self.scan_turns
    }

    /// Of the steps with an odometry increment and a previous scan, how many took their
    /// motion from an accepted scan match (`scan_match`), and how many there were.
    pub fn scan_matches(&self) -> (u64, u64) {
        self.matches
    }

    /// The turn (radians) the last step's prediction took: the scans' when they measured it,
    /// else the odometry's (with the learnt drift); `None` on the first scan.
    pub fn last_turn(&self) -> Option<f64> {
        self.last_turn
    }

    /// Scans in the local view after the last step (the current one included).
    pub fn view_scans(&self) -> usize {
        self.history.len()
    }

    /// Takes one scan: `increment` is the raw odometry since the previous scan (robot frame of
    /// the previous scan), `odom_heading` the odometry's own heading at this scan (used only to
    /// initialise, see the module docs). Returns the free-range percepts in [`DIRECTIONS`]
    /// order, `directions` of them.
    pub fn step(
        &mut self,
        scan: &ScanView<'_>,
        increment: Option<&Pose2>,
        odom_heading: f64,
    ) -> &[CompassRecord] {
        local_points(scan, &self.cfg, &mut self.dirs, &mut self.local);
        let stride = beams_apart(self.cfg.segment_deg, scan.bearing_step);
        segments(&self.local, stride, self.cfg.max_gap_m, &mut self.segments);
        let keep = beams_apart(self.cfg.beam_deg, scan.bearing_step);
        let measured = self.scan_motion(increment, stride, keep);
        let predicted = self.predict(increment, measured, odom_heading);
        let first = self.pose.is_none();
        let mut pose = predicted;
        pose.theta = predicted.theta + self.lock(predicted.theta, first);
        pose.theta = wrap_pi(pose.theta);
        self.pose = Some(pose);
        self.remember(&pose, keep);
        let n = self.cfg.directions.min(DIRECTIONS.len());
        self.free_ranges(&pose);
        for (k, &(name, _)) in DIRECTIONS.iter().enumerate().take(n) {
            let range = self
                .rays
                .of_direction(k)
                .map(|r| self.ray_range(r))
                .fold(0.0, f64::max);
            self.out[k] = CompassRecord {
                direction: name,
                value: Some(range.max(self.cfg.min_range_m.max(1e-3)).ln()),
                degree: 1.0,
            };
        }
        &self.out[..n]
    }

    /// The motion from the previous scan to the current one (`local`) measured on the scans,
    /// in the odometry increment's frame: an accepted scan match (`scan_match`; its turn, and
    /// its translation with `scan_match_translation`), else with `scan_rotation` the line
    /// correlation's turn with the odometry's translation; `None` keeps the odometry. Keeps
    /// the current scan's line histogram and points for the next step.
    fn scan_motion(
        &mut self,
        increment: Option<&Pose2>,
        stride: usize,
        keep: usize,
    ) -> Option<Pose2> {
        let c = self.cfg;
        self.matched_step = false;
        if !(c.scan_rotation || c.scan_match) {
            return None;
        }
        let [prev, cur] = &mut *self.lines;
        let has_lines = line_histogram_of(&self.segments, c.max_gap_m, c.smooth_deg, cur);
        let odometry = increment.filter(|d| d.x.is_finite() && d.y.is_finite());
        let odometry = odometry.filter(|d| d.theta.is_finite());
        let comparable = has_lines && self.lines_prev && self.pose.is_some();
        let mut measured = None;
        if c.scan_match {
            let mut starts = [0.0; MAX_STARTS];
            let n = match odometry {
                Some(d) if comparable => {
                    let out = &mut starts[..c.scan_match_starts];
                    rotation_candidates(prev, cur, d.theta, c.scan_match_window_deg, out)
                }
                _ => 0,
            };
            let params = c.match_params();
            let found =
                self.matcher
                    .step(&self.local, keep, stride, odometry, &starts[..n], &params);
            if let (Some(d), true) = (odometry, self.pose.is_some()) {
                let turn_of = |m: Match| Pose2 {
                    theta: m.motion.theta,
                    ..*d
                };
                let m = found.filter(|m| m.accepted(&params, !c.scan_match_translation));
                measured = m.map(|m| match c.scan_match_translation {
                    true => m.motion,
                    false => turn_of(m),
                });
                if measured.is_none() {
                    let agreed = found.filter(|m| {
                        m.fits(&params)
                            && wrap_pi(m.motion.theta - d.theta).abs()
                                <= c.scan_match_agreement_deg.to_radians()
                    });
                    measured = agreed.map(turn_of);
                }
                self.matched_step = measured.is_some();
                self.matches.0 += u64::from(measured.is_some());
                self.matches.1 += 1;
            }
        }
        if c.scan_rotation && measured.is_none() {
            let turn = match odometry {
                Some(d) if comparable => rotation_between(
                    prev,
                    cur,
                    d.theta,
                    c.scan_rotation_window_deg,
                    c.scan_rotation_min_contrast,
                    c.smooth_deg,
                )
                .filter(|t| {
                    (t - d.theta).abs() > c.scan_rotation_min_disagreement_deg.to_radians()
                }),
                _ => None,
            };
            if let (Some(_), true) = (odometry, self.pose.is_some()) {
                self.scan_turns.0 += u64::from(turn.is_some());
                self.scan_turns.1 += 1;
            }
            measured = turn.zip(odometry).map(|(t, d)| Pose2 { theta: t, ..*d });
        }
        self.lines.swap(0, 1);
        self.lines_prev = has_lines;
        measured
    }

    /// The pose predicted from the previous one by the odometry `increment` and the learnt
    /// drift, or by the `measured` motion (the scans'), or the initial pose; counts the
    /// distance and the turn.
    fn predict(
        &mut self,
        increment: Option<&Pose2>,
        measured: Option<Pose2>,
        odom_heading: f64,
    ) -> Pose2 {
        self.last_turn = None;
        match (self.pose, increment) {
            (Some(p), Some(odometry)) => {
                let d = measured.as_ref().unwrap_or(odometry);
                let (s, c) = p.theta.sin_cos();
                let dist = d.x.hypot(d.y);
                let dist = if dist.is_finite() { dist } else { 0.0 };
                let turn = if d.theta.is_finite() {
                    d.theta.abs()
                } else {
                    0.0
                };
                // The gate widens with the odometry's motion; matched motion has its own rate.
                if self.matched_step {
                    self.matched_travel += dist;
                } else {
                    self.travelled += dist;
                    self.turned += turn.to_degrees();
                }
                self.odometer += dist;
                self.turn += turn;
                // The scans' turn is the robot's: the odometry's drift has no part in it.
                let dtheta = match measured {
                    Some(m) => m.theta,
                    None => d.theta + self.drift * dist,
                };
                self.last_turn = Some(dtheta);
                Pose2 {
                    x: p.x + c * d.x - s * d.y,
                    y: p.y + s * d.x + c * d.y,
                    theta: p.theta + dtheta,
                }
            }
            (Some(p), None) => p,
            (None, _) => Pose2 {
                x: 0.0,
                y: 0.0,
                theta: self
                    .cfg
                    .initial_heading_deg
                    .map_or(odom_heading, f64::to_radians),
            },
        }
    }

    /// The heading correction (radians) the current scan (its `segments`) makes to the prediction
    /// `theta`, 0 when its orientation is missing, weak or outside the gate. The gate widens
    /// with the distance travelled and the angle turned since the last accepted correction.
    fn lock(&mut self, theta: f64, first: bool) -> f64 {
        let c = &self.cfg;
        let base = if c.scan_match {
            c.scan_match_max_correction_deg
        } else {
            c.max_correction_deg
        };
        let gate = (base
            + c.gate_growth_deg_per_m * self.travelled
            + c.gate_growth_per_deg * self.turned
            + (c.scan_match_gate_growth_deg_per_m * self.matched_travel)
                .min(c.scan_match_max_gate_growth_deg))
        .min(40.0);
        self.correction = None;
        let Some((alpha, share)) = orientation_of(&self.segments, &self.cfg) else {
            return 0.0;
        };
        let gate = if share >= self.cfg.min_peak_fraction {
            gate
        } else if share >= self.cfg.weak_peak_fraction {
            base
        } else {
            return 0.0;
        };
        let target = self.cfg.axis_deg.to_radians() - alpha;
        let q = std::f64::consts::FRAC_PI_2;
        let corr = (target - theta + q / 2.0).rem_euclid(q) - q / 2.0;
        if !(first || corr.abs() <= gate.to_radians()) {
            return 0.0;
        }
        if share >= self.cfg.min_peak_fraction {
            self.learn_drift(corr, first);
        }
        self.travelled = 0.0;
        self.turned = 0.0;
        self.matched_travel = 0.0;
        self.correction = (!first).then_some(corr);
        corr
    }

    /// A strong correction `corr` (radians) after `travelled` metres is the residual drift
    /// of the odometry heading over that distance; fold it into the estimate.
    fn learn_drift(&mut self, corr: f64, first: bool) {
        if !first && self.travelled >= self.cfg.drift_min_distance_m && self.travelled > 0.0 {
            let rate = corr / self.travelled;
            if rate.is_finite() {
                self.drift += self.cfg.drift_gain * rate;
            }
        }
    }

    /// Puts this scan's points (`local`, robot frame; every `keep`-th beam) into the view in
    /// the map frame at `pose`. The view's last slot is the current scan: it replaces the
    /// previous step's unless that one was a keyframe. Then slots farther back than
    /// `history_m` of travel, or beyond `history_scans`, leave the view (never the current one).
    fn remember(&mut self, pose: &Pose2, keep: usize) {
        let reuse = self.history.back().is_some_and(|s| !s.key);
        let mut slot = match reuse.then(|| self.history.pop_back()).flatten() {
            Some(slot) => slot,
            None => Slot {
                points: self.spare.pop().unwrap_or_default(),
                odometer: 0.0,
                turn: 0.0,
                key: false,
            },
        };
        slot.points.clear();
        slot.odometer = self.odometer;
        slot.turn = self.turn;
        slot.key = match self.history.back() {
            None => true,
            Some(last) => {
                self.odometer - last.odometer >= self.cfg.keyframe_m
                    || (self.turn - last.turn).to_degrees() >= self.cfg.keyframe_deg
            }
        };
        let (s, c) = pose.theta.sin_cos();
        for &(lx, ly) in self.local.iter().step_by(keep.max(1)).flatten() {
            slot.points
                .push((pose.x + c * lx - s * ly, pose.y + s * lx + c * ly));
        }
        self.history.push_back(slot);
        while self.history.len() > 1 {
            let Some(old) = self.history.front() else {
                break;
            };
            let too_far = self.odometer - old.odometer > self.cfg.history_m;
            if !(too_far || self.history.len() > self.cfg.history_scans) {
                break;
            }
            if let Some(old) = self.history.pop_front() {
                self.spare.push(old.points);
            }
        }
    }

    /// For every ray at once, the `rank` nearest distances along it of the kept points within
    /// `band_m` of it (into `nearest`). A point at distance `r` can be within the band only of
    /// rays within `asin(band/r)` of its own direction (within 90° when `r ≤ band`), so each
    /// point is tested against those rays alone, found by binary search in the sorted ray
    /// angles; the test itself is the plain one, so the result is that of testing every ray.
    fn free_ranges(&mut self, pose: &Pose2) {
        let k = self.cfg.rank;
        let (band, cap) = (self.cfg.band_m, self.cfg.cap_m);
        self.nearest.clear();
        self.nearest.resize(self.rays.len() * k, f64::INFINITY);
        let pi = std::f32::consts::PI;
        let (band32, band2) = (band as f32, (band * band) as f32);
        // A point farther than this cannot be within the band at less than the cap.
        let far2 = cap * cap + band * band;
        let Self {
            history,
            rays,
            nearest,
            arcs,
            ..
        } = self;
        // Each point's arc first, in a loop of its own: without branches it runs on vectors,
        // and the arcs' divisions overlap instead of each holding up its point's search.
        arcs.clear();
        for s in history.iter() {
            let arc = |p: &(f64, f64)| arc_of((p.0 - pose.x, p.1 - pose.y), far2, band32, band2);
            arcs.extend(s.points.iter().map(arc));
        }
        for (p, &(theta, w)) in history.iter().flat_map(|s| &s.points).zip(arcs.iter()) {
            if theta.is_nan() {
                continue;
            }
            let (vx, vy) = (p.0 - pose.x, p.1 - pose.y);
            let mut visit = |lo: f32, hi: f32| {
                for ray in rays.within(lo, hi) {
                    let (ux, uy) = rays.unit[ray];
                    let a = vx * ux + vy * uy;
                    let perp = (vy * ux - vx * uy).abs();
                    if a > 0.0 && perp <= band && a < cap {
                        insert_sorted(&mut nearest[ray * k..(ray + 1) * k], a);
                    }
                }
            };
            // The arc [θ − w, θ + w] as at most two intervals within [−π, π).
            let (lo, hi) = (theta - w, theta + w);
            if lo < -pi {
                visit(lo + 2.0 * pi, pi);
                visit(-pi, hi);
            } else if hi >= pi {
                visit(lo, pi);
                visit(-pi, hi - 2.0 * pi);
            } else {
                visit(lo, hi);
            }
        }
    }

    /// The `rank`-th nearest distance along ray `ray`, or the cap if there are fewer points.
    fn ray_range(&self, ray: usize) -> f64 {
        let k = self.cfg.rank;
        match self.nearest.get(ray * k + k - 1) {
            Some(&v) if v.is_finite() => v,
            _ => self.cfg.cap_m,
        }
    }
}

/// One scan's points in the local view.
#[derive(Debug, Clone, Default)]
struct Slot {
    /// The points, map frame.
    points: Vec<(f64, f64)>,
    /// The odometer (metres) and the summed turn (radians) when the scan was taken.
    odometer: f64,
    turn: f64,
    /// Whether the scan stays in the view when the next one comes (a keyframe).
    key: bool,
}

/// The rays of every direction's fan: per direction `d` of [`DIRECTIONS`], rays at `d`,
/// `d ± step`, `d ± 2·step`, … within `±fan_deg`, sorted by angle for [`Rays::within`].
#[derive(Debug, Clone)]
struct Rays {
    /// Angle of each ray in `[−π, π)`, ascending (f32: for pruning only).
    angle: Vec<f32>,
    /// Unit vector of each ray (from its angle as written, before wrapping).
    unit: Vec<(f64, f64)>,
    /// Direction of each ray (index into [`DIRECTIONS`]).
    direction: Vec<usize>,
    /// Per bin of [`BIN`] radians from −π, the number of rays below the bin's lower edge: where
    /// a search for an angle in that bin starts.
    first: Vec<usize>,
}

/// Bins of [`Rays::first`] over the circle, and their width in radians (half a degree).
const BINS: usize = 720;
const BIN: f32 = std::f32::consts::PI / 360.0;

impl Rays {
    fn new(cfg: &CompassConfig) -> Rays {
        let n = cfg.directions.min(DIRECTIONS.len());
        let (fan, step) = (cfg.fan_deg, cfg.fan_step_deg);
        let per_side = if fan > 0.0 && step > 0.0 {
            (fan / step).floor() as i32
        } else {
            0
        };
        let mut rays: Vec<(f64, (f64, f64), usize)> = Vec::new();
        for (k, &(_, deg)) in DIRECTIONS.iter().enumerate().take(n) {
            for j in -per_side..=per_side {
                let a = (deg + f64::from(j) * step).to_radians();
                let (uy, ux) = a.sin_cos();
                rays.push((wrap_pi(a), (ux, uy), k));
            }
        }
        rays.sort_by(|x, y| x.0.total_cmp(&y.0));
        let angle: Vec<f32> = rays.iter().map(|r| r.0 as f32).collect();
        let pi = std::f32::consts::PI;
        let first = (0..=BINS)
            .map(|b| angle.partition_point(|&a| a < -pi + b as f32 * BIN))
            .collect();
        Rays {
            angle,
            unit: rays.iter().map(|r| r.1).collect(),
            direction: rays.iter().map(|r| r.2).collect(),
            first,
        }
    }

    fn len(&self) -> usize {
        self.angle.len()
    }

    /// The rays whose angle lies in `[lo, hi]` (within `[−π, π)`): from the bin of `lo`, a
    /// short walk to the first ray at or above it, then on while at or below `hi`.
    fn within(&self, lo: f32, hi: f32) -> std::ops::Range<usize> {
        // Truncation is the floor here (the argument is ≥ 0); `as` saturates, NaN gives 0.
        let bin = (((lo + std::f32::consts::PI) * (1.0 / BIN)).max(0.0) as usize).min(BINS);
        let n = self.angle.len();
        let mut start = self.first.get(bin).copied().unwrap_or(n).min(n);
        while start < n && self.angle[start] < lo {
            start += 1;
        }
        let mut end = start;
        while end < n && self.angle[end] <= hi {
            end += 1;
        }
        start..end
    }

    /// The rays of direction `k`.
    fn of_direction(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        (0..self.len()).filter(move |&r| self.direction[r] == k)
    }
}

/// The arc `(θ, w)` of rays a point at `v` from the robot may be within `band` of (`band32`,
/// `band2 = band²` in f32): its direction `θ` and half-width `w`, or `θ` NaN for a point at
/// the robot, farther than `far2` (squared) or not finite. Worked out in f32 (it only prunes;
/// [`ATAN_MARGIN`] covers the approximations, rounding included; the ray test itself is in
/// f64 as written), and without branches (see [`CompassTracker::free_ranges`]).
#[inline(always)]
fn arc_of(v: (f64, f64), far2: f64, band32: f32, band2: f32) -> (f32, f32) {
    let pi = std::f32::consts::PI;
    let r2 = v.0 * v.0 + v.1 * v.1;
    let theta = approx_atan2(v.1 as f32, v.0 as f32);
    let r2f = r2 as f32;
    // tan(asin(x)) = x/√(1 − x²) ≥ asin(x): the window is never too narrow.
    let narrow = (band32 / (r2f - band2).sqrt()).min(0.5 * pi);
    let w = ATAN_MARGIN + if r2f > band2 { narrow } else { 0.5 * pi };
    let kept = r2 > 0.0 && r2 <= far2;
    (if kept { theta } else { f32::NAN }, w)
}

/// What [`approx_atan2`] may be off by, radians, rounding included, with room to spare: the
/// formula is off by at most 1.51e-3 on [0, 1] (`the_fast_atan2_is_within_its_margin` checks
/// it under 1.7e-3 in f32, over every direction).
const ATAN_MARGIN: f32 = 3e-3;

/// `atan2(y, x)` to within [`ATAN_MARGIN`], from `atan(z) ≈ π/4·z − z(z − 1)(0.2447 + 0.0663 z)`
/// on [0, 1] (Rajan et al., 2006: 1.5e-3 rad), a fraction of the library's cost; for pruning
/// only (see [`CompassTracker::free_ranges`]: a window widened by the margin misses no ray).
#[inline(always)]
fn approx_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay > ax;
    let (num, den) = if swap { (ax, ay) } else { (ay, ax) };
    // Selects, not an early return, so that a loop of these runs on vectors: 0 at the origin.
    let defined = den > 0.0;
    let z = if defined { num / den } else { 0.0 };
    let pi = std::f32::consts::PI;
    let t = 0.25 * pi * z - z * (z - 1.0) * (0.2447 + 0.0663 * z);
    let t = if swap { 0.5 * pi - t } else { t };
    let t = if x < 0.0 { pi - t } else { t };
    let t = if y < 0.0 { -t } else { t };
    if defined {
        t
    } else {
        0.0
    }
}

/// Inserts `v` into the ascending `best`, dropping its largest entry.
fn insert_sorted(best: &mut [f64], v: f64) {
    let Some(last) = best.last_mut() else {
        return;
    };
    if v >= *last {
        return;
    }
    *last = v;
    let mut i = best.len() - 1;
    while i > 0 && best[i - 1] > best[i] {
        best.swap(i - 1, i);
        i -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn the_fast_atan2_is_within_its_margin() {
        // Every direction at 2e-5 rad steps (the axes and diagonals included), at three
        // ranges, against the library's atan2 in f64; the difference is wrapped, so that −π
        // and π agree.
        let mut worst = 0.0f64;
        let steps = 314_160;
        for k in 0..=steps {
            let a = -PI + 2.0 * PI * k as f64 / steps as f64;
            for r in [1e-3, 1.0, 1e3] {
                let (y, x) = ((r * a.sin()) as f32, (r * a.cos()) as f32);
                let want = f64::from(y).atan2(f64::from(x));
                let got = f64::from(approx_atan2(y, x));
                worst = worst.max(wrap_pi(got - want).abs());
            }
        }
        assert!(worst < 1.7e-3, "{worst}");
        assert!(worst < f64::from(ATAN_MARGIN) / 1.5);
        assert_eq!(approx_atan2(0.0, 0.0), 0.0);
    }

    /// A 180° scan inside a 4 m × 4 m square room centred on the robot, turned by `yaw`.
    fn room(yaw: f64) -> Vec<f64> {
        (0..180)
            .map(|i| {
                let b = -FRAC_PI_2 + i as f64 * PI / 180.0 + yaw;
                let (s, c) = b.sin_cos();
                (2.0 / c.abs().max(1e-9)).min(2.0 / s.abs().max(1e-9))
            })
            .collect()
    }

    fn view(r: &[f64]) -> ScanView<'_> {
        ScanView {
            pose: Pose2::default(),
            ranges: r,
            first_bearing: -FRAC_PI_2,
            bearing_step: PI / 180.0,
            laser_offset_x: 0.0,
        }
    }

    #[test]
    fn orientation_is_the_wall_direction_mod_90() {
        let cfg = CompassConfig::default();
        for yaw_deg in [0.0f64, 17.0, 44.0, 63.0] {
            let r = room(yaw_deg.to_radians());
            let (a, share) = orientation(&view(&r), &cfg).unwrap();
            let expect = (-yaw_deg).rem_euclid(90.0);
            let err = (a.to_degrees() - expect + 45.0).rem_euclid(90.0) - 45.0;
            assert!(
                err.abs() < 1.0,
                "yaw {yaw_deg}: {} vs {expect}",
                a.to_degrees()
            );
            assert!(share > 0.8);
        }
    }

    /// The heading error after each step of a robot spinning on the spot by 30° a step in the
    /// square room, its odometry saying it does not turn at all.
    fn spin_with_still_odometry(scan_rotation: bool) -> Vec<f64> {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(0.0),
            scan_rotation,
            scan_match: false,
            ..CompassConfig::default()
        };
        let mut t = CompassTracker::new(cfg).unwrap();
        let still = Pose2::default();
        (0..8)
            .map(|k| {
                let truth = 30.0 * f64::from(k);
                let r = room(truth.to_radians());
                t.step(&view(&r), (k > 0).then_some(&still), 0.0);
                let est = t.pose().unwrap().theta.to_degrees();
                (est - truth + 180.0).rem_euclid(360.0) - 180.0
            })
            .collect()
    }

    #[test]
    fn the_scans_turn_holds_the_heading_when_the_odometry_turns_wrong() {
        // Without it each scan's wall direction is 30° from the prediction, beyond the 15°
        // gate (nothing travelled or turned by the odometry's account): the heading stays put
        // and is a multiple of 30° off. With it, each step's turn is the scans' 30° (within
        // ±35° of the odometry's 0°; the room's next match, −60°, is outside).
        let off = spin_with_still_odometry(false);
        assert!(off[1..].iter().all(|e| e.abs() > 25.0), "{off:?}");
        let on = spin_with_still_odometry(true);
        assert!(on.iter().all(|e| e.abs() < 1.0), "{on:?}");
    }

    #[test]
    fn heading_survives_odometry_drift_and_free_ranges_are_compass_bound() {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(10.0),
            ..CompassConfig::default()
        };
        let mut t = CompassTracker::new(cfg).unwrap();
        // The robot spins on the spot by 30° a step; odometry says 40°.
        let mut truth = 0.0f64;
        for k in 0..12 {
            let r = room(truth.to_radians());
            let inc = Pose2 {
                x: 0.0,
                y: 0.0,
                theta: 40f64.to_radians(),
            };
            let out = t.step(&view(&r), (k > 0).then_some(&inc), 0.0).to_vec();
            let est = t.pose().unwrap().theta.to_degrees();
            let err = (est - truth + 180.0).rem_euclid(360.0) - 180.0;
            assert!(err.abs() < 1.0, "step {k}: {est} vs {truth}");
            // Once the robot has turned through 180°, the kept scans cover all four sides.
            for rec in out.iter().filter(|_| k >= 6) {
                assert!((rec.value.unwrap().exp() - 2.0).abs() < 0.1, "{rec:?}");
            }
            truth = (truth + 30.0).rem_euclid(360.0);
        }
    }

    /// A robot driving straight along +x in 1 m steps in a square room whose scans are too
    /// weak to correct the heading after the first few frames; its odometry turns by −4° per
    /// metre that the robot did not turn (a wheel-diameter mismatch, as in the Intel log).
    fn drive_with_biased_odometry(gain: f64) -> f64 {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(0.0),
            drift_gain: gain,
            // The drift is the odometry's: matched steps take the scans' turn instead.
            scan_match: false,
            ..CompassConfig::default()
        };
        let mut t = CompassTracker::new(cfg).unwrap();
        let inc = Pose2 {
            x: 1.0,
            y: 0.0,
            theta: (-4f64).to_radians(),
        };
        let clear = room(0.0);
        let blind: Vec<f64> = vec![f64::NAN; 180];
        // Ten frames with walls in view (the drift can be learnt), then thirty blind ones.
        for k in 0..40 {
            let r = if k < 10 { &clear } else { &blind };
            t.step(&view(r), (k > 0).then_some(&inc), 0.0);
        }
        t.pose().unwrap().theta.to_degrees()
    }

    #[test]
    fn the_odometry_heading_drift_is_learnt_and_removed() {
        // Without the estimate, 30 blind metres at −4°/m leave the heading 120° off.
        let off = drive_with_biased_odometry(0.0);
        assert!((off + 120.0).abs() < 1.0, "{off}");
        // With it, nine corrections of the residual (gain 0.5) leave a drift of
        // 4·0.5⁹ ≈ 0.008°/m: under 1° after 30 m.
        let on = drive_with_biased_odometry(0.5);
        assert!(on.abs() < 1.0, "{on}");
    }

    /// The free range of one ray the plain way: every kept point tested against the ray.
    fn brute_free_range(t: &CompassTracker, pose: &Pose2, ux: f64, uy: f64) -> f64 {
        let cfg = &t.cfg;
        let mut along: Vec<f64> = t
            .history
            .iter()
            .flat_map(|s| &s.points)
            .filter_map(|p| {
                let (vx, vy) = (p.0 - pose.x, p.1 - pose.y);
                let a = vx * ux + vy * uy;
                let perp = (vy * ux - vx * uy).abs();
                (a > 0.0 && perp <= cfg.band_m && a < cfg.cap_m).then_some(a)
            })
            .collect();
        along.sort_by(f64::total_cmp);
        along.get(cfg.rank - 1).copied().unwrap_or(cfg.cap_m)
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// Pruning the rays by angle changes nothing: every ray's range is the plain test's.
        #[test]
        fn pruned_rays_give_the_plain_free_ranges(
            points in proptest::collection::vec((-12.0..12.0f64, -12.0..12.0f64), 0..400),
            near in proptest::collection::vec((-0.5..0.5f64, -0.5..0.5f64), 0..20),
            (px, py) in (-2.0..2.0f64, -2.0..2.0f64),
            band in 0.05..1.0f64,
            rank in 1usize..5,
            fan in proptest::prop_oneof![proptest::prelude::Just(0.0), 1.0..45.0f64],
            step in 1.0..20.0f64,
            eight in proptest::prelude::any::<bool>(),
        ) {
            let cfg = CompassConfig {
                band_m: band,
                rank,
                fan_deg: fan,
                fan_step_deg: step,
                directions: if eight { 8 } else { 4 },
                ..CompassConfig::default()
            };
            let mut t = CompassTracker::new(cfg).unwrap();
            // Points scattered around, some right next to the robot (inside the band).
            let near = near.iter().map(|(x, y)| (px + x, py + y));
            t.history = std::collections::VecDeque::from([Slot {
                points: points.iter().copied().chain(near).collect(),
                ..Slot::default()
            }]);
            let pose = Pose2 { x: px, y: py, theta: 0.0 };
            t.free_ranges(&pose);
            for ray in 0..t.rays.len() {
                let (ux, uy) = t.rays.unit[ray];
                let want = brute_free_range(&t, &pose, ux, uy);
                proptest::prop_assert_eq!(t.ray_range(ray), want, "ray {} at {}", ray, t.rays.angle[ray]);
            }
        }
    }

    /// Range from `(px, py)` along bearing `b` (map frame) to the walls of the box
    /// `[x0, x1] × [y0, y1]` around it, rounded to the centimetre as CARMEN logs are.
    fn box_range(px: f64, py: f64, b: f64, [x0, y0, x1, y1]: [f64; 4]) -> f64 {
        let (s, c) = b.sin_cos();
        let tx = if c > 1e-12 {
            (x1 - px) / c
        } else if c < -1e-12 {
            (x0 - px) / c
        } else {
            f64::INFINITY
        };
        let ty = if s > 1e-12 {
            (y1 - py) / s
        } else if s < -1e-12 {
            (y0 - py) / s
        } else {
            f64::INFINITY
        };
        (tx.min(ty) * 100.0).round() / 100.0
    }

    /// A scan of `beams` beams over `fov` radians (centred on the heading) in a box, from the
    /// pose `(px, py, yaw)`.
    fn box_scan(px: f64, py: f64, yaw: f64, fov: f64, beams: usize, walls: [f64; 4]) -> Vec<f64> {
        let step = fov / beams as f64;
        (0..beams)
            .map(|i| box_range(px, py, yaw - fov / 2.0 + i as f64 * step, walls))
            .collect()
    }

    #[test]
    fn orientation_holds_at_every_resolution_and_field_of_view() {
        let cfg = CompassConfig::default();
        let walls = [-3.0, -2.0, 5.0, 4.0];
        for fov_deg in [180.0f64, 360.0] {
            for res in [0.25f64, 0.5, 1.0] {
                let beams = (fov_deg / res) as usize;
                for yaw_deg in [0.0f64, 17.0, 44.0, 63.0] {
                    let yaw = yaw_deg.to_radians();
                    let r = box_scan(0.3, 0.2, yaw, fov_deg.to_radians(), beams, walls);
                    let v = ScanView {
                        pose: Pose2::default(),
                        ranges: &r,
                        first_bearing: -fov_deg.to_radians() / 2.0,
                        bearing_step: res.to_radians(),
                        laser_offset_x: 0.0,
                    };
                    let (a, _) = orientation(&v, &cfg).unwrap();
                    let expect = (-yaw_deg).rem_euclid(90.0);
                    let err = (a.to_degrees() - expect + 45.0).rem_euclid(90.0) - 45.0;
                    assert!(
                        err.abs() < 1.0,
                        "{fov_deg}° at {res}°, yaw {yaw_deg}: {err}"
                    );
                }
            }
        }
        assert_eq!(beams_apart(1.0, 0.5f64.to_radians()), 2);
        assert_eq!(beams_apart(1.0, 0.25f64.to_radians()), 4);
        assert_eq!(beams_apart(1.0, f64::NAN), 1);
        assert_eq!(beams_apart(1.0, 0.0), 1);
    }

    /// The free range West of a robot that looked at a corridor's west end wall (turning on
    /// the spot from West to East at x = 0), then drove `metres` East at `per_metre` scans per
    /// metre with exact odometry.
    fn west_range_after(metres: f64, per_metre: usize) -> f64 {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(180.0),
            ..CompassConfig::default()
        };
        let walls = [-1.0, -1.0, 40.0, 1.0];
        let mut t = CompassTracker::new(cfg).unwrap();
        let mut yaw = 180f64;
        let mut first = true;
        let turn = Pose2 {
            x: 0.0,
            y: 0.0,
            theta: (-30f64).to_radians(),
        };
        while yaw >= 0.0 {
            let r = box_scan(0.0, 0.0, yaw.to_radians(), PI, 180, walls);
            t.step(&view(&r), (!first).then_some(&turn), 0.0);
            first = false;
            yaw -= 30.0;
        }
        let step = 1.0 / per_metre as f64;
        let inc = Pose2 {
            x: step,
            y: 0.0,
            theta: 0.0,
        };
        let n = (metres * per_metre as f64).round() as usize;
        let mut west = 0.0;
        for k in 1..=n {
            let r = box_scan(k as f64 * step, 0.0, 0.0, PI, 180, walls);
            west = t.step(&view(&r), Some(&inc), 0.0)[2].value.unwrap().exp();
        }
        west
    }

    #[test]
    fn memory_is_metres_of_travel_whatever_the_scan_rate() {
        for per_metre in [2, 11] {
            // 5 m on, the west wall is still in the view (history_m = 10): 6 m away.
            let near = west_range_after(5.0, per_metre);
            assert!((near - 6.0).abs() < 0.1, "{per_metre}/m: {near}");
            // 12 m on, it has left the view: nothing West but the cap.
            let far = west_range_after(12.0, per_metre);
            assert!((far - 15.0).abs() < 1e-9, "{per_metre}/m: {far}");
        }
    }

    /// The heading error after each step of a robot turning 20° a step while driving 0.3 m
    /// a step through an off-centre box, its odometry saying it drives straight.
    fn turn_in_a_box_with_straight_odometry(scan_match: bool) -> (Vec<f64>, (u64, u64)) {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(0.0),
            scan_match,
            ..CompassConfig::default()
        };
        let walls = [-3.0, -2.0, 5.0, 4.0];
        let mut t = CompassTracker::new(cfg).unwrap();
        let inc = Pose2 {
            x: 0.3,
            y: 0.0,
            theta: 0.0,
        };
        let (mut x, mut y, mut yaw) = (0.0f64, 0.0f64, 0.0f64);
        let errors = (0..8)
            .map(|k| {
                let r = box_scan(x, y, yaw.to_radians(), PI, 360, walls);
                let v = ScanView {
                    bearing_step: PI / 360.0,
                    ..view(&r)
                };
                t.step(&v, (k > 0).then_some(&inc), 0.0);
                let est = t.pose().unwrap().theta.to_degrees();
                let err = (est - yaw + 180.0).rem_euclid(360.0) - 180.0;
                let (s, c) = yaw.to_radians().sin_cos();
                x += 0.3 * c;
                y += 0.3 * s;
                yaw += 20.0;
                err
            })
            .collect();
        (errors, t.scan_matches())
    }

    #[test]
    fn the_matched_turn_holds_the_heading_when_the_odometry_turns_wrong() {
        // Without the match, each step's wall direction is 20° from the prediction, beyond the
        // gate of 15° + 10°/m · 0.3 m + 0.1 · 0°: the heading falls 20° more behind each step.
        let (off, _) = turn_in_a_box_with_straight_odometry(false);
        assert!(off[1..].iter().all(|e| e.abs() > 15.0), "{off:?}");
        // With it, every step's turn is the scans' (the odometry's 0° is within the 25°
        // window of the correlation's candidates around it).
        let (on, matches) = turn_in_a_box_with_straight_odometry(true);
        assert!(on.iter().all(|e| e.abs() < 1.0), "{on:?}");
        assert_eq!(matches, (7, 7));
    }

    /// Per step of a robot weaving (±5° a step) down a 2 m corridor whose ends are out of
    /// range, its odometry turning `odometry_error_deg` more than it does: the turn the
    /// prediction took, the true turn and the odometry's (degrees); and the matches taken.
    fn weave_down_a_corridor(
        agreement_deg: f64,
        odometry_error_deg: f64,
    ) -> (Vec<[f64; 3]>, (u64, u64)) {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(0.0),
            scan_match: true,
            scan_match_agreement_deg: agreement_deg,
            ..CompassConfig::default()
        };
        let walls = [-100.0, -1.0, 100.0, 1.0];
        let mut t = CompassTracker::new(cfg).unwrap();
        let (mut x, mut yaw) = (0.0f64, 0.0f64);
        let mut turns = Vec::new();
        for k in 0..10 {
            let r = box_scan(x, 0.0, yaw.to_radians(), PI, 360, walls);
            let v = ScanView {
                bearing_step: PI / 360.0,
                ..view(&r)
            };
            let turn = if k % 2 == 1 { 5.0 } else { -5.0 };
            let inc = Pose2 {
                x: 0.5 * (-yaw).to_radians().cos(),
                y: 0.5 * (-yaw).to_radians().sin(),
                theta: (turn + odometry_error_deg).to_radians(),
            };
            t.step(&v, (k > 0).then_some(&inc), 0.0);
            if k > 0 {
                let took = t.last_turn().unwrap().to_degrees();
                turns.push([took, turn, turn + odometry_error_deg]);
            }
            x += 0.5;
            yaw += if k % 2 == 0 { 5.0 } else { -5.0 };
        }
        (turns, t.scan_matches())
    }

    #[test]
    fn a_corridor_match_gives_its_turn_when_the_odometry_agrees() {
        // The corridor's walls leave the motion along it free: every match is refused as a
        // whole (no step matched without the agreement).
        let (off, matched) = weave_down_a_corridor(0.0, 2.0);
        assert_eq!(matched, (0, 9));
        assert!(
            off.iter().all(|[took, _, odo]| (took - odo).abs() < 1e-9),
            "{off:?}"
        );
        // Its turn agrees with the odometry's within 3°: the step takes the measured turn.
        let (on, matched) = weave_down_a_corridor(3.0, 2.0);
        assert_eq!(matched, (9, 9));
        assert!(
            on.iter().all(|[took, truth, _]| (took - truth).abs() < 0.5),
            "{on:?}"
        );
        // Odometry 6° off disagrees: it is kept.
        let (far, matched) = weave_down_a_corridor(3.0, 6.0);
        assert_eq!(matched, (0, 9));
        assert!(
            far.iter().all(|[took, _, odo]| (took - odo).abs() < 1e-9),
            "{far:?}"
        );
    }

    /// The heading error after a robot facing 20° in the map, in a 12 m × 6 m room whose
    /// walls run at 20° (a wing off the building's axis, 0°), drove 30 m to and fro along it
    /// on exact odometry. The first scan is empty, so that the heading starts right.
    fn error_after_a_wing(max_growth_deg: f64) -> f64 {
        let cfg = CompassConfig {
            enabled: true,
            initial_heading_deg: Some(20.0),
            scan_match: true,
            scan_match_max_gate_growth_deg: max_growth_deg,
            ..CompassConfig::default()
        };
        let walls = [-2.0, -3.0, 10.0, 3.0];
        let mut t = CompassTracker::new(cfg).unwrap();
        t.step(&view(&[]), None, 0.0);
        let mut x = 0.0f64;
        let mut dir = 0.5;
        for _ in 0..60 {
            if !(0.0..=7.0).contains(&(x + dir)) {
                dir = -dir;
            }
            x += dir;
            let r = box_scan(x, 0.0, 0.0, PI, 180, walls);
            let inc = Pose2 {
                x: dir,
                y: 0.0,
                theta: 0.0,
            };
            t.step(&view(&r), Some(&inc), 0.0);
        }
        (t.pose().unwrap().theta.to_degrees() - 20.0 + 180.0).rem_euclid(360.0) - 180.0
    }

    #[test]
    fn walls_off_the_axis_do_not_capture_a_matched_heading() {
        // Their direction is 20° from the prediction. Widened by 1°/m of matched travel
        // without bound, the gate (3° + 0.5 m of unmatched first step at 10°/m) passes 20°
        // after 12 m: the heading snaps onto the wing's walls. Capped at 10°, it never does.
        let unbounded = error_after_a_wing(40.0);
        assert!((unbounded + 20.0).abs() < 1.0, "{unbounded}");
        let capped = error_after_a_wing(10.0);
        assert!(capped.abs() < 1.0, "{capped}");
    }

    #[test]
    fn empty_scans_keep_the_prediction() {
        let mut t = CompassTracker::new(CompassConfig::default()).unwrap();
        let out = t.step(&view(&[]), None, 0.5).to_vec();
        assert!((t.pose().unwrap().theta - 0.5).abs() < 1e-12);
        assert!(out.iter().all(|r| r.value == Some(15f64.ln())));
        assert!(CompassConfig {
            rank: 0,
            ..CompassConfig::default()
        }
        .validate()
        .is_err());
        let wide = |max: f64| CompassConfig {
            scan_match_max_pair_m: max,
            ..CompassConfig::default()
        };
        assert!(wide(1.6).validate().is_ok());
        assert!(wide(1.7).validate().is_err());
    }
}
