//! `Engine::step` and the trackers allocate nothing after loading: a counting global allocator,
//! per thread, so that the harness and the other tests of this binary do not count. A binary of
//! its own, since a process has one global allocator.

#[path = "../support/counting_alloc.rs"]
mod counting_alloc;

pub(crate) use counting_alloc::allocations;

#[global_allocator]
static GLOBAL: counting_alloc::Counting = counting_alloc::Counting;

mod engine_alloc;
mod engine_tracker_alloc;
