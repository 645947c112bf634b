//! The exhaustive checks, to completion, with their state counts pinned
//! (`cooperation_models::check::pins`): a change in the reachable state space shows up there as
//! a one-line diff to review.
//!
//! The small ones run under the test command; the long ones are ignored there and run by
//! `cargo test --release -p cooperation-models -- --ignored`, a step of CI of its own
//! (docs/verification.md, *Which command runs what*).
//!
//! The pinned counts are the model's, not targets: if one moves, find out why before changing
//! it (see docs/verification.md).

use cooperation_models::check::pins::{self, Pin};
use cooperation_models::check::run::{
    check, check_for, Checkable, Report, Settings, Stop, Strategy,
};
use cooperation_models::{Bounds, NetBounds, NetworkModel, SequentialModel, Views};

fn run(bounds: Bounds, threads: usize, strategy: Strategy, symmetry: bool) -> Report {
    let model = SequentialModel::new(bounds).expect("valid bounds");
    passes(
        &model,
        Settings {
            threads,
            strategy,
            symmetry,
        },
    )
}

/// Checks to completion and requires every property satisfied.
pub(crate) fn passes<M: Checkable>(model: &M, settings: Settings) -> Report
where
    M::State: core::hash::Hash
        + core::fmt::Debug
        + Clone
        + PartialEq
        + Send
        + Sync
        + stateright::Representative,
    M::Action: core::fmt::Debug + Clone + PartialEq + Send + Sync,
{
    let report = check(model, settings, &mut std::io::sink());
    assert!(report.complete, "the search did not complete");
    assert_eq!(unsatisfied(&report), Vec::<&str>::new());
    report
}

/// The report reached exactly the pinned counts (`cooperation_models::check::pins`, rendered as
/// docs/counts.md): the unique states, and the generated ones where they are pinned.
pub(crate) fn assert_pinned(report: &Report, pin: Pin) {
    assert_eq!(report.unique, pin.unique, "unique states of {}", pin.test);
    if let Some(generated) = pin.generated {
        assert_eq!(
            report.generated, generated,
            "generated states of {}",
            pin.test
        );
    }
}

/// The properties a report found unsatisfied.
pub(crate) fn unsatisfied(report: &Report) -> Vec<&'static str> {
    report
        .outcomes
        .iter()
        .filter(|o| !o.holds)
        .map(|o| o.name)
        .collect()
}

/// The CI configuration: 2 modules, 3 scene identifiers (at most 2 live), every input, to
/// completion, depth first with symmetry reduction; the same count with 1 and 2 threads.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_modules_three_scenes() {
    let bounds = Bounds::new(2, 3);
    let one = run(bounds, 1, Strategy::Dfs, true);
    let two = run(bounds, 2, Strategy::Dfs, true);
    assert_pinned(&one, pins::SEQUENTIAL_2X3);
    assert_eq!(two.unique, one.unique);
    eprintln!(
        "2x3: {} unique, {} generated; 1 thread {:.1} s, 2 threads {:.1} s",
        one.unique,
        one.generated,
        one.elapsed.as_secs_f64(),
        two.elapsed.as_secs_f64()
    );
}

/// Three modules × 3 scene identifiers (at most 2 live), to completion, depth first with
/// symmetry reduction on 2 threads: about 6.5 minutes in the release profile (as CI runs it),
/// longer in the test profile (debug assertions on).
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn three_modules_three_scenes() {
    let report = run(Bounds::new(3, 3), 2, Strategy::Dfs, true);
    assert_pinned(&report, pins::SEQUENTIAL_3X3);
    eprintln!(
        "3x3: {} unique, {} generated, {:.1} s on 2 threads",
        report.unique,
        report.generated,
        report.elapsed.as_secs_f64()
    );
}

/// The CI configuration with every state's scenes in the shipped hash index from the first
/// scene, under a hash that makes identifiers collide (`check --table hashed`): probing,
/// wrap-around deletion and index rebuilds all run under every property. The layout is invisible
/// to `Eq` and `Hash`, so the count is the default layout's.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_modules_three_scenes_hashed_table() {
    let model = SequentialModel::new(Bounds::new(2, 3))
        .expect("valid bounds")
        .with_table(cooperation::TableLayout::Colliding);
    let settings = Settings {
        threads: 2,
        strategy: Strategy::Dfs,
        symmetry: true,
    };
    let report = passes(&model, settings);
    assert_pinned(&report, pins::SEQUENTIAL_2X3_HASHED);
}

/// The hashed table again, without symmetry reduction. With it, the checker expands one state
/// of each class of states equal up to renaming, so a layout fault that shows only in some
/// members of a class (scenes kept in the order they registered, say) can go unseen: such a
/// fault passes the run above and fails this one at depth 4. The count is the default
/// layout's.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn one_module_three_scenes_hashed_table_without_symmetry() {
    let model = SequentialModel::new(Bounds::new(1, 3))
        .expect("valid bounds")
        .with_table(cooperation::TableLayout::Colliding);
    let settings = Settings {
        threads: 2,
        strategy: Strategy::Bfs,
        symmetry: false,
    };
    let report = passes(&model, settings);
    assert_pinned(&report, pins::SEQUENTIAL_1X3_HASHED);
}

/// The hashed table with three scenes live at once out of four identifiers, registered in
/// every order, without symmetry, to six steps (the whole space is far larger): a fault that
/// shows only with a third entry in the index or the identifier order (an order rebuilt from
/// insertion positions, an index too small for its entries, a deletion that stops shifting
/// entries at the index's end) fails here within four or five steps. Four identifiers are
/// needed for the last: with three, the colliding hash never puts three entries in one probe
/// run across the end. One thread: with more, which states a depth bound cuts off can vary
/// between runs.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn one_module_three_live_scenes_hashed_table_to_six_steps() {
    let bounds = Bounds {
        live: 3,
        ..Bounds::new(1, 4)
    };
    let model = SequentialModel::new(bounds)
        .expect("valid bounds")
        .with_table(cooperation::TableLayout::Colliding);
    let settings = Settings {
        threads: 1,
        strategy: Strategy::Bfs,
        symmetry: false,
    };
    let stop = Stop {
        depth: Some(6),
        ..Stop::every_violation()
    };
    let report = check_for(&model, settings, stop, &mut std::io::sink());
    assert!(report.complete, "the search did not complete to its depth");
    assert_eq!(report.depth_bound, Some(6));
    assert_eq!(unsatisfied(&report), Vec::<&str>::new());
    assert_pinned(&report, pins::SEQUENTIAL_1X4_HASHED_6_STEPS);
}

/// Without symmetry, depth first and breadth first agree: the reduction above loses nothing
/// the smaller space can show. The counts are the 2 × 2 rows of docs/counts.md.
#[test]
fn two_modules_two_scenes_without_symmetry() {
    let bounds = Bounds::new(2, 2);
    let dfs = run(bounds, 1, Strategy::Dfs, false);
    let bfs = run(bounds, 1, Strategy::Bfs, false);
    assert_pinned(&bfs, pins::SEQUENTIAL_2X2);
    assert_eq!(dfs.unique, bfs.unique);
    let reduced = run(bounds, 1, Strategy::Dfs, true);
    assert_pinned(&reduced, pins::SEQUENTIAL_2X2_SYMMETRY);
}

/// The 1 × 2 rows of docs/counts.md: one module, 2 identifiers (at most
/// 1 live), with and without symmetry.
#[test]
fn one_module_two_scenes() {
    let bounds = Bounds::new(1, 2);
    let reduced = run(bounds, 1, Strategy::Dfs, true);
    assert_pinned(&reduced, pins::SEQUENTIAL_1X2_SYMMETRY);
    let bfs = run(bounds, 1, Strategy::Bfs, false);
    assert_pinned(&bfs, pins::SEQUENTIAL_1X2);
}

/// A retired set smaller than the identifiers: the oldest retirements are forgotten, so the
/// retirement order matters (no symmetry); the properties still hold.
#[test]
fn forgetting_retired_identifiers() {
    let bounds = Bounds {
        modules: 2,
        scenes: 3,
        live: 1,
        retired: 1,
    };
    let report = run(bounds, 2, Strategy::Bfs, false);
    assert_pinned(&report, pins::SEQUENTIAL_FORGETTING);
}

/// The network model: the planner and two operators, 2 scene identifiers, messages delayed,
/// reordered, duplicated and lost; breadth first (no symmetry), the same with 1 and 2 threads.
#[test]
fn network_two_operators_two_scenes() {
    let model = NetworkModel::new(NetBounds { scenes: 2 }).expect("valid bounds");
    let one = passes(
        &model,
        Settings {
            threads: 1,
            strategy: Strategy::Bfs,
            symmetry: false,
        },
    );
    let two = passes(
        &model,
        Settings {
            threads: 2,
            strategy: Strategy::Bfs,
            symmetry: false,
        },
    );
    assert_pinned(&one, pins::NETWORK);
    assert_eq!(two.unique, one.unique);
}

/// The network model with operator views carrying the library's whole statuses, decisions
/// included, and owners that can abort: one operator, 2 scene identifiers; breadth first, the
/// same with 1 and 2 threads. (Two operators with status views outgrow memory:
/// docs/models.md, *The network model*.)
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn network_one_operator_two_scenes_status_views() {
    let model = NetworkModel::new(NetBounds { scenes: 2 })
        .and_then(|model| model.with_operators(1))
        .expect("valid bounds")
        .with_views(Views::Statuses);
    let settings = |threads| Settings {
        threads,
        strategy: Strategy::Bfs,
        symmetry: false,
    };
    let one = passes(&model, settings(1));
    let two = passes(&model, settings(2));
    assert_pinned(&one, pins::NETWORK_STATUS_VIEWS);
    assert_eq!(two.unique, one.unique);
    eprintln!(
        "network 1 operator x 2 ids, status views: {} unique, {} generated; 1 thread {:.1} s, \
         2 threads {:.1} s",
        one.unique,
        one.generated,
        one.elapsed.as_secs_f64(),
        two.elapsed.as_secs_f64()
    );
}
