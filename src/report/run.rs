//! One evaluated stream, frame by frame: the engine's step, then (unless tracking is off) the
//! graph tracker fed the frame's odometry and heading, then the [`Tally`] that becomes the
//! [`Summary`]. This is the loop behind `lplace eval` and the Python binding's `evaluate`, kept
//! in one place so that both give the same decisions and the same summary.
//!
//! Reading the stream and writing decisions stay with the caller (the command line writes text,
//! the binding fills columns); this module only turns records into decisions and counts.
//!
//! Depends on `engine` (the engine and the tracker), `io::stream` (frame meta data, rejections)
//! and `report::summary`.

use crate::engine::grid_tracker::GridTracker;
use crate::engine::tracker::{PlaceTracker, TrackerConfig};
use crate::engine::{Engine, Frame};
use crate::io::stream::{FrameMeta, Rejection, Schema};
use crate::logic::{Decision, DecisionParams, PlaceDistribution, PlaceSet};
use crate::report::summary::{Summary, Tally};

/// An engine, its optional tracker and the running tally of one stream.
#[derive(Debug, Clone)]
pub struct StreamRun {
    engine: Engine,
    tracker: Option<PlaceTracker>,
    tally: Tally,
    places: Vec<String>,
    /// The names a record's `region` field may take, and their sets (same order), each resolved
    /// when a record first names it: every place is such a name, and a set per place up front
    /// would cost places² bytes (100 MB at 10,000 places).
    region_names: Vec<String>,
    regions: Vec<Option<PlaceSet>>,
}

impl StreamRun {
    /// A run over `engine`; `tracker` is the graph tracker's configuration, `None` for
    /// frame-by-frame decisions (`lplace eval --no-track`).
    pub fn new(engine: Engine, tracker: Option<TrackerConfig>) -> StreamRun {
        let places = Schema::new(engine.percepts(), engine.map())
            .places()
            .to_vec();
        let logic = engine.rules().logic;
        let tracker = tracker.map(|cfg| {
            PlaceTracker::new(
                engine.map(),
                DecisionParams {
                    threshold: logic.threshold,
                    margin: logic.margin,
                },
                cfg,
            )
        });
        let tally = Tally::new(places.clone(), tracker.is_some());
        let region_names = crate::engine::query::set_names(engine.map(), engine.rules());
        let regions = vec![None; region_names.len()];
        StreamRun {
            engine,
            tracker,
            tally,
            places,
            region_names,
            regions,
        }
    }

    /// The schema a stream reader needs for this run's engine.
    pub fn schema(&self) -> Schema {
        Schema::new(self.engine.percepts(), self.engine.map())
            .with_regions(self.region_names.clone())
    }

    /// Place names, in the order decisions index them.
    pub fn places(&self) -> &[String] {
        &self.places
    }

    /// The engine.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    /// Whether the tracker is on.
    pub fn tracking(&self) -> bool {
        self.tracker.is_some()
    }

    /// The metric grid tracker, when the tracker configuration chose one (its belief plane is
    /// what `lplace report` draws).
    pub fn grid_tracker(&self) -> Option<&GridTracker> {
        match &self.tracker {
            Some(PlaceTracker::Grid(g)) => Some(g),
            _ => None,
        }
    }

    /// Steps one accepted frame and counts its decision. A record's `region` field conditions
    /// the engine on that set (a region known from outside).
    pub fn step(&mut self, frame: &Frame, meta: &FrameMeta) -> Decision {
        let known = match meta.region.map(|r| r as usize) {
            Some(r) if r < self.regions.len() && r < self.region_names.len() => {
                if self.regions[r].is_none() {
                    self.regions[r] = self.engine.query_set(&self.region_names[r]).ok();
                }
                self.regions[r].as_ref()
            }
            _ => None,
        };
        self.engine.step_within(frame, known);
        let d = match &mut self.tracker {
            Some(t) => t.step(
                self.engine.distribution(),
                meta.odometry.to_si(),
                meta.heading,
            ),
            None => self.engine.decision(),
        };
        self.tally.record(d, meta);
        d
    }

    /// Counts a rejected record.
    pub fn reject(&mut self, why: &Rejection) {
        self.tally.reject(why);
    }

    /// The distribution the last decision was drawn from (the tracker's when tracking).
    pub fn distribution(&self) -> &PlaceDistribution {
        match &self.tracker {
            Some(t) => t.distribution(),
            None => self.engine.distribution(),
        }
    }

    /// The summary of everything stepped and rejected so far.
    pub fn summary(&self) -> Summary {
        self.tally.finish()
    }
}
