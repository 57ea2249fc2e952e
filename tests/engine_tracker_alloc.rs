//! `Tracker::step` allocates nothing (its module docs promise it, and `eval` calls it once per
//! frame): a counting global allocator watches a thousand steps, with evidence of the right and
//! the wrong length, odometry that is large, zero or not finite, after the tracker is built.

use lplace::engine::tracker::{Tracker, TrackerConfig};
use lplace::engine::Engine;
use lplace::io::record::Odometry;
use lplace::logic::{DecisionParams, PlaceDistribution};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn step_allocates_nothing() {
    let engine = Engine::office().expect("office loads");
    let n = engine.map().places().len();
    let params = DecisionParams {
        threshold: 0.5,
        margin: 0.1,
    };
    let mut tracker = Tracker::new(engine.map(), params, TrackerConfig::default());
    let evidence: Vec<PlaceDistribution> = (0..n + 2)
        .map(|k| {
            // The last two have the wrong length: missing places read as "no evidence".
            let mut d = PlaceDistribution::new(if k < n { n } else { n / 2 });
            if k < n {
                d.support[k] = 0.9;
                d.possibility.fill(0.3);
                d.possibility[k] = 1.0;
            }
            d
        })
        .collect();
    let steps = [0.3, 0.0, 25.0, f64::NAN, f64::INFINITY, 0.05];
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    let mut chosen = 0usize;
    for k in 0..1000 {
        let odometry = Odometry {
            dx: steps[k % steps.len()],
            dy: 0.1,
            dtheta: 0.0,
        };
        if tracker
            .step(&evidence[(k / 7) % evidence.len()], odometry)
            .place()
            .is_some()
        {
            chosen += 1;
        }
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert_eq!(after - before, 0, "step allocated {} times", after - before);
    // Some frames decide and some do not: the loop did real work.
    assert!(chosen > 0 && chosen < 1000, "{chosen} decided");
}
