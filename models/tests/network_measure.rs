//! How far the network model with status views gets with two operators: not a pass or fail
//! test, a measurement (`cargo test --release -p cooperation-models --test network_measure --
//! --ignored --nocapture`). Two operators told whole statuses outgrow a 24 GiB machine, so the
//! default tests check one operator with status views and two with identifier views
//! (`tests/exhaustive.rs`); this run says how many states the search reached by its cap.
//!
//! Measured before the network model dropped its freshness flags (which made 2 operators with
//! identifier views 2.4 times larger, and 1 operator with status views 5 % larger), on 2 threads
//! on a loaded 2-core machine: at the 10 million state cap, depth 17 of a
//! space whose one-operator version is 42 deep, 94.9 million generated, 142.5 s, 8.52 GiB
//! resident, no property violated. Uncapped, `check --model network --operators 2 --views
//! statuses --memory-gib 12` stopped at 12 GiB with 15,805,905 states, depth 18, in 191 s.

use std::time::Duration;

use cooperation_models::budget::{Budget, GIB};
use cooperation_models::run::{check_for, Settings, Stop, Strategy};
use cooperation_models::{NetBounds, NetworkModel, Views};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The state cap: a run stops there, incomplete, and reports what it found.
const CAP: usize = 10_000_000;

#[test]
#[ignore = "a measurement of minutes and gigabytes, not a check"]
fn two_operators_two_scenes_status_views() {
    let model = NetworkModel::new(NetBounds { scenes: 2 })
        .expect("valid bounds")
        .with_views(Views::Statuses);
    let settings = Settings {
        threads: 2,
        strategy: Strategy::Bfs,
        symmetry: false,
    };
    let stop = Stop {
        keep_going: true,
        budget: Budget {
            memory_bytes: 12 * GIB,
            states: CAP,
        },
        timeout: Some(Duration::from_secs(600)),
        depth: None,
    };
    let report = check_for(&model, settings, stop, &mut std::io::stderr());
    eprintln!(
        "network 2 operators x 2 ids, status views: {} unique, {} generated, depth {}, {:.1} s, \
         peak {:.2} GiB, {:?}",
        report.unique,
        report.generated,
        report.depth,
        report.elapsed.as_secs_f64(),
        report.peak_bytes.unwrap_or(0) as f64 / GIB as f64,
        report.ended
    );
    let violated: Vec<&str> = report
        .outcomes
        .iter()
        .filter(|o| !o.holds && !matches!(o.expectation, stateright::Expectation::Sometimes))
        .map(|o| o.name)
        .collect();
    assert!(violated.is_empty(), "violated: {violated:#?}");
}
