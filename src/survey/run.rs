//! One survey from texts and records to results: [`Survey::new`] parses the map and the rules
//! and checks the configuration, [`Survey::run`] labels the frames, fits, writes the map text
//! by spans and, for first-visit fits, scores the later visits. Also the two readers the
//! callers share: the run's records ([`read_records`], from any reader, no file of its own) and
//! a labels CSV ([`parse_labels`], from its text). Printing, file names on the command line and
//! Python values are the callers' business (`cli::survey`, the `lplace-python` crate).

use std::collections::BTreeMap;
use std::io::BufRead;

use super::{
    decide_all, fit, later_within, links_from_rules, visits, write_params, ParamLink, PlaceFit,
    Protocol, Score, SurveyConfig, SurveyError,
};
use crate::engine::query::set_names;
use crate::engine::tracker::TrackerConfig;
use crate::engine::{
    CompileOptions, Engine, FileRole, Frame, LoadError, PerceptSlot, PerceptTable,
};
use crate::io::record::{FrameRecord, PerceptRecord};
use crate::io::stream::{FrameMeta, LineError, ReadOutcome, Schema, StreamFormat, StreamReader};
use crate::map::Map;
use crate::report::run::StreamRun;
use crate::rules::check_declarations;
use crate::syntax::ast::MapFile;
use crate::syntax::diagnostic::SourceFile;
use crate::syntax::{parse_map, parse_rules};

/// The warning a place fitted from fewer than `min_scans` frames carries.
const FEW_SCANS: &str = "few scans, the fit is unreliable";

/// The warning a first-visit fit carries when most of the later visits' readings lie outside it.
const LATER_OUTSIDE: &str = "most readings of the later visits lie outside the fitted ranges";

/// Records read from a stream: the accepted ones, and each line that was rejected.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Records {
    /// The accepted records, in stream order.
    pub frames: Vec<FrameRecord>,
    /// Every rejected record with its 1-based line, as [`StreamReader`] words it.
    pub rejected: Vec<LineError>,
}

/// The record the reader accepted into `frame`/`meta`, with names again: the fit groups values
/// by percept name and the held-out score steps whole records, as the stream gave them.
fn record_of(
    frame: &Frame,
    meta: &FrameMeta,
    order: &[PerceptSlot],
    schema: &Schema,
) -> FrameRecord {
    let percepts = order
        .iter()
        .filter_map(|&slot| {
            let inst = schema.instance(slot)?;
            let k = slot.0 as usize;
            let value = frame.value.get(k).copied().filter(|v| !v.is_nan());
            Some(PerceptRecord {
                name: inst.name.clone(),
                args: inst.args.clone(),
                value,
                degree: frame.degree.get(k).copied().unwrap_or(0.0),
            })
        })
        .collect();
    let truth = meta.truth_known.then(|| crate::io::record::Truth {
        place: meta
            .truth_place
            .and_then(|p| schema.places().get(p).cloned()),
        pose: meta.truth_pose,
    });
    FrameRecord {
        version: None,
        t: meta.t,
        odometry: Some(meta.odometry),
        heading: meta.heading,
        percepts,
        truth,
        region: meta
            .region
            .and_then(|r| schema.region_name(r).map(str::to_owned)),
    }
}

/// One row of ground truth: from time `t` on, the robot is at `place` (`None`: between places).
#[derive(Debug, Clone, PartialEq)]
pub struct LabelRow {
    /// Time, seconds, on the stream's clock.
    pub t: f64,
    /// The place, `None` between places.
    pub place: Option<String>,
}

/// The rows of a labels CSV `t,place`: a header and blank or `#` lines are skipped, an empty
/// place is "between places". Sorted by time.
///
/// # Errors
/// [`SurveyError::LabelRow`] for a row after the first whose time is not a finite number.
pub fn parse_labels(text: &str) -> Result<Vec<LabelRow>, SurveyError> {
    let mut rows = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (t, place) = line.split_once(',').unwrap_or((line, ""));
        match t.trim().parse::<f64>() {
            Ok(t) if t.is_finite() => {
                let p = place.trim();
                rows.push(LabelRow {
                    t,
                    place: (!p.is_empty()).then(|| p.to_owned()),
                });
            }
            _ if n == 0 => {} // a header
            _ => return Err(SurveyError::LabelRow { line: n + 1 }),
        }
    }
    rows.sort_by(|a, b| a.t.total_cmp(&b.t));
    Ok(rows)
}

/// Each frame's label: the row nearest its time, if within 0.5 s. Rows need not be sorted;
/// rows with a non-finite time are ignored.
pub fn label_frames(frames: &[FrameRecord], rows: &[LabelRow]) -> Vec<Option<String>> {
    let mut rows: Vec<LabelRow> = rows.iter().filter(|r| r.t.is_finite()).cloned().collect();
    rows.sort_by(|a, b| a.t.total_cmp(&b.t));
    frames
        .iter()
        .map(|f| {
            let k = nearest_label(&rows, f.t?)?;
            rows[k].place.clone()
        })
        .collect()
}

/// The index of the row of `rows` (sorted by time, as [`parse_labels`] returns them) nearest
/// `t`, if it lies within 0.5 s of it: a frame's label (halfway between two rows, the
/// earlier).
///
/// # Complexity
/// `O(log n)`.
pub fn nearest_label(rows: &[LabelRow], t: f64) -> Option<usize> {
    let i = rows.partition_point(|r| r.t < t);
    let k = [i.checked_sub(1), Some(i)]
        .into_iter()
        .flatten()
        .filter(|&k| k < rows.len())
        .min_by(|&a, &b| (rows[a].t - t).abs().total_cmp(&(rows[b].t - t).abs()))?;
    ((rows[k].t - t).abs() <= 0.5).then_some(k)
}

/// Where each frame's true place comes from.
#[derive(Debug, Clone, Copy)]
pub enum Truth<'a> {
    /// The records' own `truth.place`.
    Records,
    /// The label nearest in time ([`label_frames`]).
    Labels(&'a [LabelRow]),
}

/// What the survey says about one fitted place.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaceReport {
    /// The place.
    pub place: String,
    /// Frames its fit used.
    pub scans: usize,
    /// [`PlaceFit::spread`]: the median width of its fitted ranges.
    pub spread: f64,
    /// Fitted from fewer than the configuration's `min_scans` frames.
    pub few_scans: bool,
    /// With [`Protocol::FirstVisits`], the readings of the later visits within the fitted
    /// ranges and all of them ([`later_within`]); `None` otherwise, or if the place was not
    /// visited again.
    pub later: Option<(usize, usize)>,
}

impl PlaceReport {
    /// The warning about this place's fit, if any: too few scans, else (first-visit fits) most
    /// of the later visits' readings outside the fitted ranges — the fit does not describe the
    /// place as the robot meets it again.
    pub fn warning(&self) -> Option<&'static str> {
        if self.few_scans {
            return Some(FEW_SCANS);
        }
        let outside = self.later.is_some_and(|(within, n)| 2 * within < n);
        outside.then_some(LATER_OUTSIDE)
    }
}

impl std::fmt::Display for PlaceReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {} scan(s), median spread {:.2}",
            self.place, self.scans, self.spread
        )?;
        match self.warning() {
            Some(w) => write!(f, "  WARNING: {w}"),
            None => Ok(()),
        }
    }
}

/// Everything a survey produces.
#[derive(Debug, Clone, PartialEq)]
pub struct SurveyOutcome {
    /// The map text with the fitted parameters written in (every other byte as it was).
    pub map_text: String,
    /// The fits, places in name order.
    pub fits: Vec<PlaceFit>,
    /// One row per fitted place, in the order of `fits`.
    pub report: Vec<PlaceReport>,
    /// With [`Protocol::FirstVisits`]: how the written map does on the later visits.
    pub held_out: Option<Score>,
}

/// A map and rules ready to be surveyed with a configuration.
#[derive(Debug, Clone)]
pub struct Survey {
    map: SourceFile,
    map_ast: MapFile,
    rules: SourceFile,
    links: Vec<ParamLink>,
    cfg: SurveyConfig,
    /// The names a stream may use: the rules' percepts over the map as given (their parameters
    /// play no part), the map's places and regions — what `lplace eval` reads with.
    schema: Schema,
}

impl Survey {
    /// Parses the map and the rules, checks the quantiles, and builds the stream's schema from
    /// the rules' declarations over the map as given: which percepts, places and regions a
    /// record may name depends on those, not on the place parameters the survey is about to
    /// write (and which the map may not have yet, so the rules are not checked against it).
    ///
    /// # Errors
    /// [`SurveyError::Load`] with the diagnostics of the first file that does not parse, of a
    /// map that does not build, or of declarations that do not check;
    /// [`SurveyError::Quantiles`] unless `0 ≤ lo ≤ hi ≤ 1`.
    pub fn new(
        map: SourceFile,
        rules: SourceFile,
        cfg: SurveyConfig,
    ) -> Result<Survey, SurveyError> {
        let fail = |role, file: &SourceFile, diagnostics| LoadError {
            role,
            file: file.clone(),
            diagnostics,
        };
        let map_ast = parse_map(&map.text).map_err(|d| fail(FileRole::Map, &map, d))?;
        let rules_ast = parse_rules(&rules.text).map_err(|d| fail(FileRole::Rules, &rules, d))?;
        if !((0.0..=1.0).contains(&cfg.lo) && (cfg.lo..=1.0).contains(&cfg.hi)) {
            return Err(SurveyError::Quantiles {
                lo: cfg.lo,
                hi: cfg.hi,
            });
        }
        let model = Map::from_ast(&map_ast).map_err(|d| fail(FileRole::Map, &map, d))?;
        let declared =
            check_declarations(&rules_ast, &model).map_err(|d| fail(FileRole::Rules, &rules, d))?;
        let schema = Schema::new(&PerceptTable::new(&declared), &model)
            .with_regions(set_names(&model, &declared));
        Ok(Survey {
            links: links_from_rules(&rules_ast),
            map,
            map_ast,
            rules,
            cfg,
            schema,
        })
    }

    /// Every record of a percept stream in `format`, read by [`StreamReader`] as every command
    /// reads one (the same validation, rejections and line numbers). Blank lines are skipped;
    /// rejected records are collected, not fitted.
    ///
    /// # Errors
    /// The reader's own error (unreadable).
    pub fn read_records(
        &self,
        input: impl BufRead,
        format: StreamFormat,
    ) -> std::io::Result<Records> {
        let mut reader = StreamReader::new(input, self.schema.clone(), format);
        let mut frame = Frame::new(self.schema.slots());
        let mut meta = FrameMeta::default();
        let mut out = Records::default();
        loop {
            match reader.next_frame(&mut frame, &mut meta)? {
                ReadOutcome::End => return Ok(out),
                ReadOutcome::Rejected(e) => out.rejected.push(e),
                ReadOutcome::Frame => out.frames.push(record_of(
                    &frame,
                    &meta,
                    reader.percept_order(),
                    &self.schema,
                )),
            }
        }
    }

    /// The configuration.
    pub fn config(&self) -> &SurveyConfig {
        &self.cfg
    }

    /// Fits the places of `frames` under `protocol` and writes them into the map text; with
    /// [`Protocol::FirstVisits`], also runs the engine and `tracker` (without one, the rule
    /// file's `tracker { … }` block or the defaults) over every frame with the written map and
    /// scores the later visits (the tracker sees the whole run, as it would live).
    ///
    /// # Errors
    /// [`SurveyError::NothingToFit`] when no rule links a percept with a place parameter;
    /// [`SurveyError::UnknownPlace`] / [`SurveyError::SpanMismatch`] when the map cannot be
    /// written; [`SurveyError::Load`] when the written map does not load with the rules.
    pub fn run(
        &self,
        frames: &[FrameRecord],
        truth: Truth<'_>,
        protocol: Protocol,
        tracker: Option<&TrackerConfig>,
    ) -> Result<SurveyOutcome, SurveyError> {
        let labels = match truth {
            Truth::Records => frames
                .iter()
                .map(|f| f.truth.as_ref().and_then(|t| t.place.clone()))
                .collect(),
            Truth::Labels(rows) => label_frames(frames, rows),
        };
        if self.links.is_empty() {
            return Err(SurveyError::NothingToFit {
                rules: self.rules.name.clone(),
            });
        }
        let fits = fit(frames, &labels, &self.links, protocol, &self.cfg);
        let later = match protocol {
            Protocol::All => vec![None; fits.len()],
            Protocol::FirstVisits => {
                later_within(frames, &labels, &self.links, &fits, self.cfg.visit_gap_m)
            }
        };
        let report = fits
            .iter()
            .zip(later)
            .map(|(f, later)| PlaceReport {
                place: f.place.clone(),
                scans: f.scans,
                spread: f.spread(),
                few_scans: f.scans < self.cfg.min_scans,
                later,
            })
            .collect();
        let map_text = write_params(&self.map.text, &self.map_ast, &fits)?;
        let held_out = match protocol {
            Protocol::All => None,
            Protocol::FirstVisits => {
                let written = SourceFile::new(self.map.name.clone(), map_text.clone());
                Some(self.held_out(&written, tracker, frames, &labels)?)
            }
        };
        Ok(SurveyOutcome {
            map_text,
            fits,
            report,
            held_out,
        })
    }

    /// The score of the written map on the frames of later visits.
    fn held_out(
        &self,
        map: &SourceFile,
        tracker: Option<&TrackerConfig>,
        frames: &[FrameRecord],
        labels: &[Option<String>],
    ) -> Result<Score, SurveyError> {
        let engine = Engine::load_with(map, &self.rules, &CompileOptions::default())?;
        let names: BTreeMap<String, usize> = engine
            .map()
            .places()
            .iter()
            .enumerate()
            .map(|(k, p)| (p.name.clone(), k))
            .collect();
        // Without a tracker file, the rule file's `tracker { … }` block (or the defaults).
        let tracker = tracker.copied().unwrap_or_else(|| engine.tracker_config());
        let mut run = StreamRun::new(engine, Some(tracker));
        let visit = visits(frames, labels, self.cfg.visit_gap_m);
        let decisions = decide_all(&mut run, frames);
        let truth: Vec<Option<usize>> = labels
            .iter()
            .map(|l| l.as_ref().and_then(|l| names.get(l)).copied())
            .collect();
        Ok(Score::of(&decisions, &truth, |k| {
            visit.get(k).copied().flatten().is_some_and(|v| v > 0)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64) -> FrameRecord {
        FrameRecord {
            version: None,
            t: Some(t),
            odometry: None,
            heading: None,
            region: None,
            percepts: Vec::new(),
            truth: None,
        }
    }

    fn row(t: f64, place: Option<&str>) -> LabelRow {
        LabelRow {
            t,
            place: place.map(str::to_owned),
        }
    }

    #[test]
    fn frames_take_the_label_nearest_in_time_within_half_a_second() {
        let frames = [at(0.0), at(1.0), at(2.0), at(2.3)];
        // Unsorted on purpose: label_frames sorts.
        let rows = [row(2.35, None), row(0.1, Some("A")), row(1.9, Some("B"))];
        let got = label_frames(&frames, &rows);
        // 1.0 is 0.9 s from both rows: no label; 2.3 is nearest the "between places" row.
        assert_eq!(
            got,
            vec![Some("A".to_owned()), None, Some("B".to_owned()), None]
        );
    }

    #[test]
    fn labels_csv_skips_a_header_and_rejects_a_bad_row_by_line() {
        let rows = parse_labels("t,place\n\n2.0,B\n# note\n1.0, A \n3.0,\n").expect("parsed");
        assert_eq!(
            rows,
            vec![row(1.0, Some("A")), row(2.0, Some("B")), row(3.0, None)]
        );
        assert_eq!(
            parse_labels("t,place\n1.0,A\nnan,B\n"),
            Err(SurveyError::LabelRow { line: 3 })
        );
    }

    #[test]
    fn records_count_blank_lines_and_collect_the_rejected() {
        let map = SourceFile::new("m.map", crate::engine::OFFICE_MAP);
        let rules = SourceFile::new("r.lpl", crate::engine::OFFICE_RULES);
        let s = Survey::new(map, rules, SurveyConfig::default()).expect("loads");
        // Line 3 is not JSON, 4 has another version, 6 a degree above 1, 8 goes back in time.
        let text = "{\"t\":1.0,\"percepts\":[]}\n\n{oops\n{\"version\":99,\"percepts\":[]}\n\
                    {\"t\":2.0,\"odometry\":{\"dx\":0.5},\"percepts\":[{\"name\":\"beacon_angle\",\
                    \"value\":30,\"degree\":0.5}],\"truth\":{\"place\":\"P1\"}}\n\
                    {\"t\":2.5,\"percepts\":[{\"name\":\"beacon_angle\",\"value\":1,\"degree\":1.5}]}\n\
                    {\"t\":3.0,\"percepts\":[]}\n{\"t\":0.5,\"percepts\":[]}\n{\"t\":4.0,\"percepts\":[]}\n";
        let got = s
            .read_records(text.as_bytes(), StreamFormat::JsonLines)
            .expect("read");
        let lines: Vec<u64> = got.rejected.iter().map(|r| r.line).collect();
        assert_eq!(lines, vec![3, 4, 6, 8]);
        let t: Vec<Option<f64>> = got.frames.iter().map(|f| f.t).collect();
        assert_eq!(t, vec![Some(1.0), Some(2.0), Some(3.0), Some(4.0)]);
        // The accepted record comes back with its names, values and truth.
        let f = &got.frames[1];
        assert_eq!(f.odometry.map(|o| o.dx), Some(0.5));
        assert_eq!(f.percepts.len(), 1);
        assert_eq!(
            (
                f.percepts[0].name.as_str(),
                f.percepts[0].value,
                f.percepts[0].degree
            ),
            ("beacon_angle", Some(30.0), 0.5)
        );
        let place = f.truth.as_ref().and_then(|t| t.place.as_deref());
        assert_eq!(place, Some("P1"));
    }

    #[test]
    fn a_map_without_the_parameters_still_reads_its_stream() {
        // Before a survey the places need not carry what the rules compare with.
        let bare: String = crate::engine::OFFICE_MAP
            .lines()
            .map(|l| match l.find("param ") {
                Some(i) => &l[..i],
                None => l,
            })
            .collect::<Vec<_>>()
            .join("\n");
        assert!(!bare.contains("param "));
        let map = SourceFile::new("m.map", bare);
        let rules = SourceFile::new("r.lpl", crate::engine::OFFICE_RULES);
        // The rules do not check against this map …
        assert!(Engine::load_with(&map, &rules, &CompileOptions::default()).is_err());
        // … but their declarations do, and give the stream its percepts and places.
        let s = Survey::new(map, rules, SurveyConfig::default()).expect("declarations check");
        let text = "{\"t\":1.0,\"percepts\":[{\"name\":\"beacon_angle\",\"value\":30,\"degree\":1}],\
                    \"truth\":{\"place\":\"P0\"}}\n{\"t\":2.0,\"percepts\":[{\"name\":\"nope\",\"degree\":1}]}\n";
        let got = s
            .read_records(text.as_bytes(), StreamFormat::JsonLines)
            .expect("read");
        assert_eq!(got.frames.len(), 1);
        assert_eq!(
            got.rejected.iter().map(|r| r.line).collect::<Vec<_>>(),
            vec![2]
        );
    }

    #[test]
    fn bad_quantiles_and_rules_without_links_are_errors_not_panics() {
        let map = SourceFile::new("m.map", crate::engine::OFFICE_MAP);
        let rules = SourceFile::new("r.lpl", "percept w(value, time);\n");
        let cfg = SurveyConfig {
            lo: 0.9,
            hi: 0.1,
            ..SurveyConfig::default()
        };
        assert!(matches!(
            Survey::new(map.clone(), rules.clone(), cfg),
            Err(SurveyError::Quantiles { .. })
        ));
        let cfg = SurveyConfig {
            lo: f64::NAN,
            ..SurveyConfig::default()
        };
        assert!(Survey::new(map.clone(), rules.clone(), cfg).is_err());
        let s = Survey::new(map, rules, SurveyConfig::default()).expect("parses");
        let got = s.run(
            &[at(0.0)],
            Truth::Records,
            Protocol::All,
            Some(&TrackerConfig::default()),
        );
        assert_eq!(
            got,
            Err(SurveyError::NothingToFit {
                rules: "r.lpl".to_owned()
            })
        );
    }

    #[test]
    fn a_map_that_does_not_parse_is_a_load_error_on_the_map() {
        let map = SourceFile::new("m.map", "map m;\nplace P at (0, ;\n");
        let rules = SourceFile::new("r.lpl", "percept w(value, time);\n");
        match Survey::new(map, rules, SurveyConfig::default()) {
            Err(SurveyError::Load(e)) => {
                assert_eq!(e.role, FileRole::Map);
                assert!(!e.diagnostics.is_empty());
            }
            other => panic!("expected a load error, got {other:?}"),
        }
    }
}
