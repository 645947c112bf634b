//! A steady-state planning cycle allocates nothing: every owner updates its existing scene, the
//! planner reads every merged decision, and the statuses and factor lists are written into
//! caller-owned buffers that already have room.
//!
//! The cycle is the one `benches/runtime.rs` times. The counting allocator is process-wide,
//! so this file holds a single test: no other test thread can allocate while it counts.

use std::alloc::System;

use cooperation::State;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};

#[path = "../benches/workload/mod.rs"]
mod workload;

use workload::{Outputs, Planner};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

#[test]
fn steady_state_cycles_do_not_allocate() {
    // The counter counts: a region around one allocation sees it.
    let region = Region::new(GLOBAL);
    let boxed = std::hint::black_box(Box::new(7_u64));
    assert_eq!(region.change().allocations, 1);
    drop(boxed);

    // The scene table in both its forms: a sorted vector (1 and 10 scenes, at most 16) and
    // hash-indexed (100 and 1 000). Test builds keep debug assertions, so the invariant check
    // after every input is counted too.
    for scenes in [1, 10, 100, 1_000] {
        let mut planner = Planner::<State>::new(scenes);
        let mut out = Outputs::default();
        // The first cycle grows the output buffers; from then on they have room.
        let first = planner.cycle(&mut out);
        assert_eq!(first.accepted, scenes, "every update is accepted");
        assert_eq!(first.statuses, scenes);
        assert_eq!(first.factors, scenes);

        let region = Region::new(GLOBAL);
        let mut activated = 0;
        for _ in 0..20 {
            let summary = planner.cycle(&mut out);
            assert_eq!(summary.accepted, scenes);
            assert_eq!(summary.statuses, scenes);
            assert_eq!(summary.factors, scenes);
            activated += summary.activated;
        }
        let change = region.change();
        assert_eq!(
            (
                change.allocations,
                change.reallocations,
                change.bytes_allocated
            ),
            (0, 0, 0),
            "20 steady-state cycles with {scenes} scenes allocated"
        );
        // The cycles did real work: some merged decisions were `Activate`.
        assert!(activated > 0, "{scenes} scenes: nothing activated");
    }
}
