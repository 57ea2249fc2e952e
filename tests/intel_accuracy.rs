//! Regression over the real Intel Research Lab log: extract the percept stream from the raw
//! CARMEN log (`config/intel.ron`), evaluate it with `maps/intel.map` + `rules/intel.lpl`, per
//! frame and with the tracker, against the truth the map's extents give, and lock in the
//! figures reached (asserted slightly below what was measured). Also draws the trajectory SVG
//! into the test's temporary directory. Skips with a message when the data is absent
//! (`$LPLACE_DATA`, else `../shared/data` next to the crate).

use std::collections::BTreeMap;
use std::path::PathBuf;

use lplace::engine::tracker::{Tracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::io::record::FrameRecord;
use lplace::logic::{Decision, DecisionParams};
use lplace::percept::ExtractConfig;
use lplace::report::trajectory::{svg, TrajectoryPoint, Verdict};
use lplace::syntax::diagnostic::SourceFile;

fn data_dir() -> PathBuf {
    std::env::var_os("LPLACE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data"))
}

fn crate_file(rel: &str) -> SourceFile {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(rel);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{rel}: {e}"));
    SourceFile::new(rel, text)
}

#[derive(Default, Debug)]
struct Score {
    right: usize,
    wrong: usize,
    disoriented: usize,
    confidently_wrong: usize,
    /// (truth, decided) → frames; `-` = no place / disoriented.
    confusion: BTreeMap<(String, String), usize>,
}

impl Score {
    fn add(&mut self, d: Decision, names: &[String], truth: &str) -> Verdict {
        let (v, dec) = match d {
            Decision::Place { place, necessity } => {
                let name = names.get(place).cloned().unwrap_or_default();
                if name == truth {
                    self.right += 1;
                    (Verdict::Right, name)
                } else {
                    self.wrong += 1;
                    if necessity >= 0.9 {
                        self.confidently_wrong += 1;
                    }
                    (Verdict::Wrong, name)
                }
            }
            Decision::Disoriented(_) => {
                self.disoriented += 1;
                (Verdict::Disoriented, "-".to_owned())
            }
        };
        *self.confusion.entry((truth.to_owned(), dec)).or_default() += 1;
        v
    }
    fn frames(&self) -> usize {
        self.right + self.wrong + self.disoriented
    }
    fn decided(&self) -> f64 {
        (self.right + self.wrong) as f64 / self.frames().max(1) as f64
    }
    fn precision(&self) -> f64 {
        self.right as f64 / (self.right + self.wrong).max(1) as f64
    }
    fn confidently_wrong_rate(&self) -> f64 {
        self.confidently_wrong as f64 / self.frames().max(1) as f64
    }
    fn report(&self, label: &str) {
        eprintln!(
            "{label}: {} frames: {} right, {} wrong, {} disoriented; decided {:.1} %, right of decided {:.1} %, confidently wrong {:.2} %",
            self.frames(),
            self.right,
            self.wrong,
            self.disoriented,
            100.0 * self.decided(),
            100.0 * self.precision(),
            100.0 * self.confidently_wrong_rate()
        );
        // Per true place: frames, right, the place most often chosen instead.
        let mut by_truth: BTreeMap<&str, Vec<(&str, usize)>> = BTreeMap::new();
        for ((t, d), n) in &self.confusion {
            by_truth.entry(t).or_default().push((d, *n));
        }
        for (t, row) in by_truth {
            let total: usize = row.iter().map(|x| x.1).sum();
            let right = row.iter().find(|x| x.0 == t && t != "-").map_or(0, |x| x.1);
            let lost = row.iter().find(|x| x.0 == "-").map_or(0, |x| x.1);
            let worst = row
                .iter()
                .filter(|x| x.0 != t && x.0 != "-")
                .max_by_key(|x| x.1)
                .map_or(String::new(), |x| {
                    format!(", most confused with {} ({})", x.0, x.1)
                });
            eprintln!("  {t:5} {total:4} frames, {right:3} right, {lost:3} disoriented{worst}");
        }
    }
}

#[test]
fn intel_lab_accuracy_is_locked_in() {
    let log = data_dir().join("carmen-corrected-logs/intel-corrected.log");
    let Ok(bytes) = std::fs::read(&log) else {
        eprintln!(
            "SKIP: {} not found (set LPLACE_DATA or provide ../shared/data)",
            log.display()
        );
        return;
    };
    let mut engine = Engine::load(
        &crate_file("maps/intel.map"),
        &crate_file("rules/intel.lpl"),
    )
    .expect("the Intel map and rules load");
    let cfg = ExtractConfig::from_ron(&crate_file("config/intel.ron").text)
        .expect("config/intel.ron is valid");
    let map = engine.map().clone();
    assert!(map.places().len() >= 15, "issue 4: at least 15 places");
    let names: Vec<String> = map.places().iter().map(|p| p.name.clone()).collect();
    let logic = engine.rules().logic;
    let mut tracker = Tracker::new(
        &map,
        DecisionParams {
            threshold: logic.threshold,
            margin: logic.margin,
        },
        TrackerConfig::default(),
    );

    let mut framer = CarmenFramer::new(cfg, Some(map.places())).expect("framer");
    let mut frames: Vec<FrameRecord> = Vec::new();
    let mut malformed = 0usize;
    convert(
        bytes.as_slice(),
        &mut framer,
        |f| {
            frames.push(f);
            Ok::<(), ()>(())
        },
        |_| malformed += 1,
    )
    .expect("collecting frames cannot fail");
    assert_eq!(malformed, 0);
    assert_eq!(frames.len(), 910, "one frame per FLASER scan");

    let (mut single, mut tracked) = (Score::default(), Score::default());
    let mut frame = engine.new_frame();
    let mut points = Vec::new();
    let mut at_a_place = 0usize;
    for f in &frames {
        let mut rejected = Vec::new();
        f.fill(engine.percepts(), &mut frame, &mut rejected);
        assert!(rejected.is_empty(), "{rejected:?}");
        let truth = f
            .truth
            .as_ref()
            .and_then(|t| t.place.as_deref())
            .unwrap_or("-");
        at_a_place += usize::from(truth != "-");
        let d = engine.step(&frame);
        single.add(d, &names, truth);
        let dt = tracker.step(engine.distribution(), f.odometry.unwrap_or_default());
        let v = tracked.add(dt, &names, truth);
        if let Some(p) = f.truth.as_ref().and_then(|t| t.pose) {
            points.push(TrajectoryPoint {
                x: p[0],
                y: p[1],
                verdict: v,
            });
        }
    }
    single.report("per frame");
    tracked.report("with tracking");

    let picture = svg(
        &map,
        &points,
        20.0,
        "Intel Research Lab: tracked decisions per scan",
    );
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("intel-trajectory.svg");
    if std::fs::write(&out, picture).is_ok() {
        eprintln!("trajectory picture: {}", out.display());
    }

    // Locked in (measured: 830/910 frames inside a place; with the drift-corrected compass
    // and its free ranges, per frame 37.8 % decided, 51.7 % of them right, 0 % confidently
    // wrong; tracked 28.5 % decided, 54.1 % right, 0.99 % confidently wrong). Below the
    // issue's goal: see docs/intel.md.
    assert!(at_a_place >= 820, "truth coverage {at_a_place}");
    assert!(single.decided() >= 0.36, "{single:?}");
    assert!(single.precision() >= 0.50, "{single:?}");
    assert!(single.confidently_wrong_rate() <= 0.01, "{single:?}");
    assert!(tracked.decided() >= 0.27, "{tracked:?}");
    assert!(tracked.precision() >= 0.52, "{tracked:?}");
    assert!(tracked.confidently_wrong_rate() <= 0.01, "{tracked:?}");
}
