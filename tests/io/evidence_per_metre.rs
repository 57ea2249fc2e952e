//! The thinning check of DESIGN §12 ("evidence per metre, not per frame") on real data: the
//! Intel Research Lab log extracted once, then evaluated with the metric grid tracker of
//! `config/intel-tracker.ron` whole, **thinned** to every k-th frame (the odometry of the
//! dropped frames composed into the kept ones: the same run logged k times more sparsely) and
//! **densified** k-fold (each frame repeated k times, its odometry split into k equal steps:
//! the same run logged k times more densely, with the near-identical neighbouring scans of a
//! fast scanner), k = 2 … 6.
//!
//! Tolerance: at the frames the two runs share, the decisions may differ between a place and
//! *disoriented* (a log sparser than one frame per `evidence_length_m` takes less evidence per
//! metre, so it decides less often), but they name **different places** on at most 1 % of the
//! thinned frames and 3 % of the densified ones. Taking evidence per frame instead
//! (`evidence_length_m: 0`) fails the densified check: the same scan repeated is taken as new
//! evidence each time, and the tracker becomes sure of wrong places (measured 2026-12-02: 6 to
//! 20 % for k = 3 … 6). Skips with a message when the data is absent (`$LPLACE_DATA`, else
//! `../shared/data` next to the crate).

use std::path::Path;

use crate::support::carmen::{self, repo};
use crate::support::data_dir;
use lplace::engine::tracker::TrackerConfig;
use lplace::engine::{CompileOptions, Engine};
use lplace::io::record::{FrameRecord, Odometry};
use lplace::logic::Decision;
use lplace::map::Map;
use lplace::report::run::StreamRun;
use lplace::survey::{decide_all, thin};
use lplace::syntax::diagnostic::SourceFile;

fn extract(log: &Path, map: &Map) -> Vec<FrameRecord> {
    carmen::extract(log, "config/intel.ron", map)
}

fn decisions(frames: &[FrameRecord], cfg: TrackerConfig) -> Vec<Decision> {
    let map = SourceFile::new("maps/intel.map", repo("maps/intel.map"));
    let rules = SourceFile::new("rules/intel.lpl", repo("rules/intel.lpl"));
    let engine = Engine::load_with(&map, &rules, &CompileOptions::default()).expect("loads");
    decide_all(&mut StreamRun::new(engine, Some(cfg)), frames)
}

/// Both decided, and on different places.
fn contradict(a: &Decision, b: &Decision) -> bool {
    match (a, b) {
        (Decision::Place { place: p, .. }, Decision::Place { place: q, .. }) => p != q,
        _ => false,
    }
}

/// Each frame `k` times, its odometry split into `k` equal steps (the turn on the last one).
fn densify(frames: &[FrameRecord], k: usize) -> Vec<FrameRecord> {
    let mut out = Vec::with_capacity(frames.len() * k);
    for f in frames {
        for j in 0..k {
            let mut g = f.clone();
            g.odometry = f.odometry.map(|o| Odometry {
                dx: o.dx / k as f64,
                dy: o.dy / k as f64,
                dtheta: if j + 1 == k { o.dtheta } else { 0.0 },
            });
            out.push(g);
        }
    }
    out
}

/// Per k = 2 … 6, the share of shared frames on which the thinned and the densified runs name
/// another place than the whole log.
fn contradictions(frames: &[FrameRecord], cfg: TrackerConfig) -> Vec<(f64, f64)> {
    let whole = decisions(frames, cfg);
    (2..=6)
        .map(|k| {
            let thinned = decisions(&thin(frames, k), cfg);
            let bad = thinned
                .iter()
                .enumerate()
                .filter(|(i, d)| whole.get(i * k).is_some_and(|w| contradict(w, d)))
                .count();
            let thin_rate = bad as f64 / thinned.len().max(1) as f64;
            let dense = decisions(&densify(frames, k), cfg);
            let bad = whole
                .iter()
                .enumerate()
                .filter(|(i, w)| dense.get(i * k + k - 1).is_some_and(|d| contradict(w, d)))
                .count();
            (thin_rate, bad as f64 / whole.len().max(1) as f64)
        })
        .collect()
}

#[test]
fn thinned_and_densified_logs_decide_as_the_whole_log() {
    let log = data_dir().join("carmen-corrected-logs/intel-corrected.log");
    if !log.is_file() {
        eprintln!(
            "SKIP: {} not found (set LPLACE_DATA or provide ../shared/data)",
            log.display()
        );
        return;
    }
    let map = carmen::load_map("maps/intel.map");
    let frames = extract(&log, &map);
    let cfg = TrackerConfig::from_ron(&repo("config/intel-tracker.ron")).expect("tracker");
    let per_metre = contradictions(&frames, cfg);
    let mut per_frame_cfg = cfg;
    if let Some(g) = per_frame_cfg.grid.as_mut() {
        g.evidence_length_m = 0.0;
    }
    let per_frame = contradictions(&frames, per_frame_cfg);
    for (k, (a, b)) in per_metre.iter().zip(&per_frame).enumerate() {
        eprintln!(
            "k = {}: another place named on {:.1} % thinned, {:.1} % densified \
             (evidence per frame: {:.1} %, {:.1} %)",
            k + 2,
            100.0 * a.0,
            100.0 * a.1,
            100.0 * b.0,
            100.0 * b.1
        );
    }
    for (k, (thinned, densified)) in per_metre.iter().enumerate() {
        assert!(*thinned <= 0.01, "k = {}: thinned {thinned}", k + 2);
        assert!(*densified <= 0.03, "k = {}: densified {densified}", k + 2);
    }
    // The check can fail: evidence per frame is over-confident on the densified logs.
    assert!(per_frame.iter().any(|(_, d)| *d > 0.05), "{per_frame:?}");
}
