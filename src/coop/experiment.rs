//! Paper 002's experiment on MRCLAM: one robot is the object, the others see it (the robots
//! wear barcodes), and the fused estimate is scored next to each observer's own and next to
//! plain and reliability-weighted averages (paper 002 §4.4 tables).
//!
//! Protocol:
//! 1. Every robot runs its own Fuzzy Position Grid over its own frames, stepped by the one
//!    driver [`Drive`], all robots interleaved in one global time order (ties by robot number).
//! 2. A *sighting* is a reading, in some robot's frame, of a robot chosen as object. Right after
//!    the observer's frame has been stepped, its self grid and reliability at that moment give
//!    its object grid ([`object_grid`]); the grid is kept as it would be sent, one byte per cell,
//!    run-length encoded ([`ObjectGrid::to_rle`]). The observer's own object estimate is the
//!    centre of gravity of its (unquantised) object grid.
//! 3. An *event* groups the sightings of one object that fall within
//!    [`CoopConfig::window`] of the first sighting not yet used; for each observer the last of
//!    its sightings counts. Events with fewer than [`CoopConfig::min_observers`] distinct
//!    observers are dropped. The event's time is its last sighting's; the object's truth is its
//!    Vicon pose interpolated there.
//! 4. The received codes are decoded and fused ([`fuse`]); the errors against the truth are
//!    `Δ_self` (each observer's self-localization error at its sighting), `Δ_object` (each
//!    observer's own object estimate), `Δ_best` (the best of those, an oracle), `Δ_avg`,
//!    `Δ_wavg` (weights: self-localization reliability) and `Δ_fuzzy`. An event is *scored* only
//!    when every one of those estimates exists (a flat object grid — an observer in total
//!    ignorance — has none); the others are counted as unscored.
//!
//! # Complexity
//!
//! The robots' grid runs (O(frames · cells)), plus O(cells + k · m) per sighting (see
//! [`crate::coop::object`]) and O(observers · cells) per event; memory O(cells · robots +
//! sightings · code size).
//!
//! # Example
//!
//! ```
//! use lplace::coop::experiment::{run, RobotTrack, Options};
//! use lplace::coop::CoopConfig;
//! use lplace::grid::{GridConfig, Landmark, LandmarkTable};
//! let table = LandmarkTable::new(vec![Landmark { id: 6, x: 0.0, y: 0.0 }]).unwrap();
//! let logs: Vec<RobotTrack> = Vec::new();
//! let r = run(&table, &GridConfig::default(), &CoopConfig::default(), &logs, &Options::default()).unwrap();
//! assert_eq!(r.overall.events, 0);
//! ```

use super::fuse::{average, fuse, weighted_average};
use super::{object_grid, CoopConfig, CoopError, ObjectGrid, ObjectReading};
use crate::grid::{GridConfig, LandmarkTable};
use crate::localize::grid::GridLocalizer;
use crate::localize::{interpolate_truth, Drive, FrameEstimate, MetricFrame, RunOptions, TruthRow};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One robot's recording as the experiment reads it (a dataset reader, such as
/// `io::mrclam_dir`, owns the data).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotTrack<'a> {
    /// Robot (subject) number; other robots' readings name it.
    pub robot: u32,
    /// Its frames, with readings of landmarks and of robots.
    pub frames: &'a [MetricFrame],
    /// Its ground-truth track, time-ordered.
    pub truth: &'a [TruthRow],
}

/// What to run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Options {
    /// Robots taken as objects; empty means every robot.
    pub objects: Vec<u32>,
    /// Stop this many seconds after the first frame; `None` runs everything.
    pub until: Option<f64>,
}

/// Mean and median of a set of errors (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Stat {
    /// Mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// Values counted.
    pub count: usize,
}

impl Stat {
    /// Statistics of the finite values; `None` when there is none.
    pub fn of(values: impl IntoIterator<Item = f64>) -> Option<Stat> {
        let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Some(Stat {
            mean: v.iter().sum::<f64>() / n as f64,
            median,
            count: n,
        })
    }
}

/// One observer's part in an event.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sighting {
    /// Time of the reading (s).
    pub t: f64,
    /// Observing robot.
    pub observer: u32,
    /// Observed robot.
    pub object: u32,
    /// The reading.
    pub reading: ObjectReading,
    /// Observer's self-localization error at `t` (m), when its truth is known.
    pub self_error: Option<f64>,
    /// Observer's self-localization reliability at `t`.
    pub self_reliability: f32,
    /// Observer's own object estimate (centre of gravity of its object grid).
    pub object_estimate: Option<(f32, f32)>,
    /// Floor (bias) of its object grid.
    pub floor: f32,
    /// Its object grid as sent: one byte per cell, run-length encoded.
    pub code: Vec<u8>,
}

/// One scored event.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EventScore {
    /// Event time (s).
    pub t: f64,
    /// The object robot.
    pub object: u32,
    /// Observers, in robot order.
    pub observers: Vec<u32>,
    /// `Δ_self` per observer (m; NaN where its truth is unknown).
    pub self_errors: Vec<f64>,
    /// `Δ_object` per observer (m).
    pub object_errors: Vec<f64>,
    /// Self-localization reliability per observer.
    pub reliabilities: Vec<f32>,
    /// Size of each observer's code (bytes).
    pub code_bytes: Vec<usize>,
    /// `Δ_avg` (m).
    pub avg: f64,
    /// `Δ_wavg` (m).
    pub wavg: f64,
    /// `Δ_fuzzy` (m).
    pub fuzzy: f64,
    /// Conflict of the fusion, `1 − height` of the product.
    pub conflict: f32,
}

/// The errors of one object robot's events (or of all of them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The object robot, `None` for all together.
    pub object: Option<u32>,
    /// Sightings of the object.
    pub sightings: usize,
    /// Scored events.
    pub events: usize,
    /// Events dropped because some estimate did not exist.
    pub unscored: usize,
    /// `Δ_self` over all observers of all events.
    pub self_error: Option<Stat>,
    /// `Δ_object` over all observers of all events.
    pub object_error: Option<Stat>,
    /// Best observer's `Δ_object` per event.
    pub best: Option<Stat>,
    /// `Δ_avg`.
    pub avg: Option<Stat>,
    /// `Δ_wavg`.
    pub wavg: Option<Stat>,
    /// `Δ_fuzzy`.
    pub fuzzy: Option<Stat>,
    /// Events where `Δ_fuzzy < Δ_avg`.
    pub fuzzy_beats_avg: usize,
    /// Events where `Δ_fuzzy < Δ_wavg`.
    pub fuzzy_beats_wavg: usize,
    /// Mean size of a sent object grid (bytes).
    pub mean_code_bytes: Option<f64>,
    /// `Δ_self` and `Δ_object` per observer robot.
    pub per_observer: BTreeMap<u32, (Option<Stat>, Option<Stat>)>,
}

/// Everything the experiment measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// Per object robot, in robot order.
    pub per_object: Vec<Summary>,
    /// All objects together.
    pub overall: Summary,
    /// The events where some observer's self error exceeds [`CoopConfig::lost_self_error`].
    pub with_lost_observer: Summary,
    /// Every scored event, in time order per object.
    pub events: Vec<EventScore>,
    /// Cells of one grid (the uncompressed size in bytes of one object grid).
    pub cells: usize,
    /// Readings of objects that gave no object grid (non-finite values).
    pub rejected_sightings: usize,
}

/// Runs the experiment (see the module docs).
///
/// # Errors
/// [`CoopError::Grid`] when a self grid cannot be built from `grid_cfg`, [`CoopError::BadConfig`]
/// for an invalid `cfg`.
pub fn run(
    table: &LandmarkTable,
    grid_cfg: &GridConfig,
    cfg: &CoopConfig,
    logs: &[RobotTrack<'_>],
    opts: &Options,
) -> Result<Report, CoopError> {
    cfg.validate()?;
    let objects: Vec<u32> = if opts.objects.is_empty() {
        logs.iter().map(|l| l.robot).collect()
    } else {
        opts.objects.clone()
    };
    let mut locs = Vec::with_capacity(logs.len());
    for _ in logs {
        locs.push(GridLocalizer::new(table, grid_cfg)?);
    }
    let seen = collect_sightings(table, cfg, logs, &objects, opts.until, &mut locs);
    let geometry = locs.first().map(|l| super::GridGeometry::of(l.grid()));
    Ok(score_all(logs, &objects, &seen, geometry, cfg))
}

/// What the robots' runs produced: the sightings, the cells of one object grid, and the
/// readings that gave no object grid.
struct Seen {
    sightings: Vec<Sighting>,
    cells: usize,
    rejected: usize,
}

/// Steps every robot's grid over its frames in one global time order (ties by robot, then
/// frame) until `until` seconds after the first frame, and turns each reading of an object robot
/// into a [`Sighting`] right after its observer's frame.
fn collect_sightings(
    table: &LandmarkTable,
    cfg: &CoopConfig,
    logs: &[RobotTrack<'_>],
    objects: &[u32],
    until: Option<f64>,
    locs: &mut [GridLocalizer],
) -> Seen {
    let mut drives: Vec<Drive> = logs
        .iter()
        .map(|_| Drive::new(table, RunOptions::default()))
        .collect();
    let mut order: Vec<(f64, usize, usize)> = logs
        .iter()
        .enumerate()
        .flat_map(|(r, l)| l.frames.iter().enumerate().map(move |(k, f)| (f.t, r, k)))
        .filter(|x| x.0.is_finite())
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let t_end = match (until, order.first()) {
        (Some(u), Some(first)) => first.0 + u,
        _ => f64::INFINITY,
    };
    let mut seen = Seen {
        sightings: Vec::new(),
        cells: 0,
        rejected: 0,
    };
    for &(t, r, k) in &order {
        if t > t_end {
            break;
        }
        let f = &logs[r].frames[k];
        let est = drives[r].step(&mut locs[r], f);
        let me = logs[r].robot;
        for reading in &f.observations {
            if reading.subject == me || !objects.contains(&reading.subject) {
                continue;
            }
            let obs = ObjectReading {
                range: reading.range as f32,
                bearing: reading.bearing as f32,
            };
            sight(
                &mut seen,
                &mut locs[r],
                &est,
                (t, me, reading.subject),
                obs,
                cfg,
            );
        }
    }
    seen
}

/// Records one sighting of `object` by `observer` at `t`, or counts it rejected.
fn sight(
    seen: &mut Seen,
    loc: &mut GridLocalizer,
    est: &FrameEstimate,
    (t, observer, object): (f64, u32, u32),
    obs: ObjectReading,
    cfg: &CoopConfig,
) {
    let rel = est.reliability.clamp(0.0, 1.0);
    match object_grid(loc.grid_now(), rel, obs, cfg) {
        Ok(g) => {
            seen.cells = g.values().len();
            seen.sightings.push(Sighting {
                t,
                observer,
                object,
                reading: obs,
                self_error: est.error,
                self_reliability: rel,
                object_estimate: g.centre_of_gravity(cfg.cog_cut),
                floor: g.floor(),
                code: g.to_rle(),
            });
        }
        Err(_) => seen.rejected += 1,
    }
}

/// Groups and scores the sightings per object (in robot order) and over all objects.
fn score_all(
    logs: &[RobotTrack<'_>],
    objects: &[u32],
    seen: &Seen,
    geometry: Option<super::GridGeometry>,
    cfg: &CoopConfig,
) -> Report {
    let mut per_object = Vec::new();
    let mut all_events = Vec::new();
    let mut all_unscored = 0;
    let mut sorted_objects = objects.to_vec();
    sorted_objects.sort_unstable();
    sorted_objects.dedup();
    for &object in &sorted_objects {
        let mine: Vec<&Sighting> = seen
            .sightings
            .iter()
            .filter(|s| s.object == object)
            .collect();
        let truth = logs.iter().find(|l| l.robot == object).map(|l| l.truth);
        let (events, unscored) = match (geometry, truth) {
            (Some(geo), Some(truth)) => score_object(&mine, truth, geo, cfg),
            _ => (Vec::new(), 0),
        };
        per_object.push(summarise(Some(object), mine.len(), &events, unscored));
        all_unscored += unscored;
        all_events.extend(events);
    }
    let overall = summarise(None, seen.sightings.len(), &all_events, all_unscored);
    let lost: Vec<EventScore> = all_events
        .iter()
        .filter(|e| e.self_errors.iter().any(|&x| x > cfg.lost_self_error))
        .cloned()
        .collect();
    let with_lost_observer = summarise(None, 0, &lost, 0);
    Report {
        per_object,
        overall,
        with_lost_observer,
        events: all_events,
        cells: seen.cells,
        rejected_sightings: seen.rejected,
    }
}

/// Groups one object's sightings (time-ordered) into events and scores them; returns the
/// scored events and the number of unscored ones.
fn score_object(
    seen: &[&Sighting],
    truth: &[TruthRow],
    geo: super::GridGeometry,
    cfg: &CoopConfig,
) -> (Vec<EventScore>, usize) {
    let mut out = Vec::new();
    let mut unscored = 0;
    let mut i = 0;
    while i < seen.len() {
        let t0 = seen[i].t;
        let mut j = i;
        // Last sighting of each observer within the window.
        let mut last: BTreeMap<u32, &Sighting> = BTreeMap::new();
        while j < seen.len() && seen[j].t <= t0 + cfg.window {
            last.insert(seen[j].observer, seen[j]);
            j += 1;
        }
        i = j;
        if last.len() < cfg.min_observers {
            continue;
        }
        let t = last.values().map(|s| s.t).fold(f64::NEG_INFINITY, f64::max);
        match score_event(&last, t, truth, geo, cfg) {
            Some(e) => out.push(e),
            None => unscored += 1,
        }
    }
    (out, unscored)
}

fn score_event(
    last: &BTreeMap<u32, &Sighting>,
    t: f64,
    truth: &[TruthRow],
    geo: super::GridGeometry,
    cfg: &CoopConfig,
) -> Option<EventScore> {
    let tr = interpolate_truth(truth, t, 1.0)?;
    let err = |p: (f32, f32)| (p.0 as f64 - tr.x).hypot(p.1 as f64 - tr.y);
    let ss: Vec<&Sighting> = last.values().copied().collect();
    let points: Vec<(f32, f32)> = ss
        .iter()
        .map(|s| s.object_estimate)
        .collect::<Option<_>>()?;
    let weights: Vec<f32> = ss.iter().map(|s| s.self_reliability).collect();
    let grids: Vec<ObjectGrid> = ss
        .iter()
        .map(|s| ObjectGrid::from_rle(geo, &s.code).ok())
        .collect::<Option<_>>()?;
    let fused = fuse(&grids).ok()?;
    let f = fused.grid.centre_of_gravity(cfg.cog_cut)?;
    Some(EventScore {
        t,
        object: ss[0].object,
        observers: ss.iter().map(|s| s.observer).collect(),
        self_errors: ss
            .iter()
            .map(|s| s.self_error.unwrap_or(f64::NAN))
            .collect(),
        object_errors: points.iter().map(|&p| err(p)).collect(),
        reliabilities: weights.clone(),
        code_bytes: ss.iter().map(|s| s.code.len()).collect(),
        avg: err(average(&points)?),
        wavg: err(weighted_average(&points, &weights)?),
        fuzzy: err(f),
        conflict: fused.conflict,
    })
}

fn summarise(object: Option<u32>, sightings: usize, ev: &[EventScore], unscored: usize) -> Summary {
    let mut per_observer: BTreeMap<u32, (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    for e in ev {
        for (k, &o) in e.observers.iter().enumerate() {
            let slot = per_observer.entry(o).or_default();
            slot.0.push(e.self_errors[k]);
            slot.1.push(e.object_errors[k]);
        }
    }
    let bytes: Vec<f64> = ev
        .iter()
        .flat_map(|e| e.code_bytes.iter().map(|&b| b as f64))
        .collect();
    Summary {
        object,
        sightings,
        events: ev.len(),
        unscored,
        self_error: Stat::of(ev.iter().flat_map(|e| e.self_errors.iter().copied())),
        object_error: Stat::of(ev.iter().flat_map(|e| e.object_errors.iter().copied())),
        best: Stat::of(ev.iter().map(|e| {
            e.object_errors
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
        })),
        avg: Stat::of(ev.iter().map(|e| e.avg)),
        wavg: Stat::of(ev.iter().map(|e| e.wavg)),
        fuzzy: Stat::of(ev.iter().map(|e| e.fuzzy)),
        fuzzy_beats_avg: ev.iter().filter(|e| e.fuzzy < e.avg).count(),
        fuzzy_beats_wavg: ev.iter().filter(|e| e.fuzzy < e.wavg).count(),
        mean_code_bytes: (!bytes.is_empty())
            .then(|| bytes.iter().sum::<f64>() / bytes.len() as f64),
        per_observer: per_observer
            .into_iter()
            .map(|(o, (s, b))| (o, (Stat::of(s), Stat::of(b))))
            .collect(),
    }
}
