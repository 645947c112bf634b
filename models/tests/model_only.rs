//! The model check alone, at bounds that run in seconds: the only test `tools/mutants` gives
//! `cargo mutants`, so that a mutant of the shipped transition code counts as caught only when a
//! model property fails (`docs/mutation.md`). No count is pinned here: a moved count is not a
//! caught fault.

use cooperation::TableLayout;
use cooperation_models::check::run::{check_for, Checkable, Report, Settings, Stop, Strategy};
use cooperation_models::{Bounds, NetBounds, NetworkModel, RtcBounds, RtcModel, SequentialModel};
use stateright::Expectation;

const SETTINGS: Settings = Settings {
    threads: 1,
    strategy: Strategy::Dfs,
    symmetry: true,
};

/// Checks to completion (to `stop`'s depth bound, where it sets one); every property satisfied
/// but the `sometimes` properties named in `unreachable`, which these bounds are too small for.
/// Every caller stops at the first violated `always` property, as `check` does by default: a
/// wrong transition that also grows the state space is then reported by the property it
/// breaks, not by a run that outlasts its time.
fn satisfied<M: Checkable>(model: &M, settings: Settings, stop: Stop, unreachable: &[&str])
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
    let report: Report = check_for(model, settings, stop, &mut std::io::sink());
    let failed: Vec<&str> = report
        .outcomes
        .iter()
        .filter(|o| !o.holds)
        .filter(|o| {
            !(matches!(o.expectation, Expectation::Sometimes) && unreachable.contains(&o.name))
        })
        .map(|o| o.name)
        .collect();
    assert!(failed.is_empty(), "properties not satisfied: {failed:#?}");
    assert!(
        report.complete,
        "the search did not complete: {:?}",
        report.ended
    );
}

/// The sequential model with two live scenes (so expiry, the scene limit and commands over two
/// scenes happen), in both table layouts, and with two and three modules.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn sequential() {
    for table in [TableLayout::Adaptive, TableLayout::Colliding] {
        let model = SequentialModel::new(Bounds::new(1, 3))
            .expect("valid")
            .with_table(table);
        satisfied(&model, SETTINGS, Stop::first_violation(), &[]);
    }
    // Symmetry reduction expands one state of each class equal up to renaming; a table that
    // kept scenes in the order they registered shows only in some members, so the hashed
    // table is also checked without it, with every identifier live at once, two and three.
    let both_live = Bounds {
        live: 2,
        ..Bounds::new(1, 2)
    };
    let model = SequentialModel::new(both_live)
        .expect("valid")
        .with_table(TableLayout::Colliding);
    let bfs = Settings {
        strategy: Strategy::Bfs,
        symmetry: false,
        ..SETTINGS
    };
    satisfied(
        &model,
        bfs,
        Stop::first_violation(),
        &["COOP-REG-FULL.1 is reachable"],
    );
    // Three live scenes out of four identifiers, registered in any order, to five steps: an
    // index or an identifier order that goes wrong only with a third entry shows here, and
    // four identifiers give the home buckets a deletion must shift entries across.
    let three_live = Bounds {
        live: 3,
        ..Bounds::new(1, 4)
    };
    let model = SequentialModel::new(three_live)
        .expect("valid")
        .with_table(TableLayout::Colliding);
    let to_five_steps = Stop {
        depth: Some(5),
        ..Stop::first_violation()
    };
    satisfied(&model, bfs, to_five_steps, &[]);
    let model = SequentialModel::new(Bounds::new(2, 2)).expect("valid");
    satisfied(&model, SETTINGS, Stop::first_violation(), &[]);
    // Three modules, so that a built-in module with a sequence (`avoidance/change`) is among
    // them: a module's index or policy slot that ignored its sequence shows only there. One
    // identifier: the scene limit (one live scene) is not reachable.
    let model = SequentialModel::new(Bounds::new(3, 1)).expect("valid");
    satisfied(
        &model,
        SETTINGS,
        Stop::first_violation(),
        &["COOP-REG-FULL.1 is reachable"],
    );
    let forgetting = Bounds {
        modules: 1,
        scenes: 3,
        live: 1,
        retired: 1,
    };
    let model = SequentialModel::new(forgetting).expect("valid");
    satisfied(&model, bfs, Stop::first_violation(), &[]);
}

/// The RTC adapter model, two interfaces, two identifiers both live at once; and with four
/// identifiers, one live and a retired set of one, so that the core forgets and the adapter
/// must prune its routes to stay within its bound (breadth first, without symmetry: the
/// retirement order matters); with a quota of one live scene per interface; and the avoidance,
/// bound to two sequences, with two identifiers live at once.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn rtc() {
    let bounds = RtcBounds {
        live: 2,
        ..RtcBounds::new(2, 2)
    };
    let model = RtcModel::new(bounds).expect("valid");
    satisfied(
        &model,
        SETTINGS,
        Stop::first_violation(),
        &["COOP-REG-FULL.1: an update beyond the scene limit is refused"],
    );
    let forgetting = RtcBounds {
        live: 1,
        retired: 1,
        ..RtcBounds::new(2, 4)
    };
    let model = RtcModel::new(forgetting).expect("valid");
    let bfs = Settings {
        strategy: Strategy::Bfs,
        symmetry: false,
        threads: 1,
    };
    satisfied(
        &model,
        bfs,
        Stop::first_violation(),
        &[
            "COOP-OWN-REMOVE.1: a clear retires two scenes",
            "witness: two interfaces have live scenes at once",
        ],
    );
    let quota = RtcBounds {
        live: 2,
        quota: Some(1),
        ..RtcBounds::new(2, 2)
    };
    let model = RtcModel::new(quota).expect("valid");
    satisfied(
        &model,
        SETTINGS,
        Stop::first_violation(),
        &[
            "COOP-REG-FULL.1: an update beyond the scene limit is refused",
            "COOP-OWN-REMOVE.1: a clear retires two scenes",
        ],
    );
    let avoidance = RtcBounds {
        live: 2,
        ..RtcBounds::new(1, 2).from_interface(cooperation_models::model::rtc::AVOIDANCE)
    };
    let model = RtcModel::new(avoidance).expect("valid");
    satisfied(
        &model,
        SETTINGS,
        Stop::first_violation(),
        &[
            "COOP-DEV-ID-REUSE.1: an update of another interface's scene is refused",
            "COOP-REG-FULL.1: an update beyond the scene limit is refused",
            "COOP-DEV-ID-REUSE.1: a removal of another interface's scene is refused",
            "COOP-DEV-ID-REUSE.1: an interface's command for another interface's scene is refused",
            "witness: two interfaces have live scenes at once",
        ],
    );
}

/// The network model at its CI bounds.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn network() {
    let model = NetworkModel::new(NetBounds { scenes: 2 }).expect("valid");
    let bfs = Settings {
        strategy: Strategy::Bfs,
        symmetry: false,
        threads: 2,
    };
    satisfied(&model, bfs, Stop::first_violation(), &[]);
}
