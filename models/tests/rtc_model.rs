//! The RTC adapter model: the exhaustive check CI runs, with its unique-state count pinned, and
//! the sensitivity tests (every injected adapter fault is caught by its property, with a
//! shortest counterexample that replays from its JSON and passes against the shipped adapter).
//!
//! The pinned counts are the model's, not targets: if one moves, find out why before changing
//! it (see docs/verification.md).

use cooperation_models::check::pins;
use cooperation_models::check::run::{check, shortest, Report, Settings, Strategy};
use cooperation_models::model::rtc::AVOIDANCE;
use cooperation_models::{RtcBounds, RtcFault, RtcModel, Trace};
use stateright::Expectation;

use crate::exhaustive::unsatisfied;

fn run(bounds: RtcBounds, threads: usize, strategy: Strategy, symmetry: bool) -> Report {
    let model = RtcModel::new(bounds).expect("valid bounds");
    let settings = Settings {
        threads,
        strategy,
        symmetry,
    };
    let report = check(&model, settings, &mut std::io::sink());
    assert!(report.complete, "the search did not complete");
    report
}

/// The `always` properties a report found broken.
fn broken(report: &Report) -> Vec<&'static str> {
    report
        .outcomes
        .iter()
        .filter(|o| !o.holds && !matches!(o.expectation, Expectation::Sometimes))
        .map(|o| o.name)
        .collect()
}

/// The CI configuration: 2 interfaces (the two lane changes, which share one core module) and
/// 3 scene identifiers (at most 2 live), every call, to completion, depth first with symmetry
/// reduction; every property satisfied, and the same count with 1 and 2 threads.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_interfaces_three_scenes() {
    let bounds = RtcBounds::new(2, 3);
    let one = run(bounds, 1, Strategy::Dfs, true);
    assert_eq!(unsatisfied(&one), Vec::<&str>::new());
    let two = run(bounds, 2, Strategy::Dfs, true);
    assert_eq!(unsatisfied(&two), Vec::<&str>::new());
    assert_eq!(one.unique, pins::RTC_2X3.unique);
    assert_eq!(two.unique, one.unique);
    eprintln!(
        "rtc 2x3: {} unique, {} generated; 1 thread {:.1} s, 2 threads {:.1} s",
        one.unique,
        one.generated,
        one.elapsed.as_secs_f64(),
        two.elapsed.as_secs_f64()
    );
}

/// With a quota of 2 live scenes per interface (`[COOP-DEV-QUOTA.1]`), the two lane changes and
/// 3 identifiers, 2 live: an interface holding 2 refuses a third, and the scene limit is still
/// met with one scene on each interface. Every property satisfied, the quota's refusal reached.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_interfaces_three_scenes_with_a_quota() {
    let bounds = RtcBounds {
        live: 2,
        quota: Some(2),
        ..RtcBounds::new(2, 3)
    };
    let report = run(bounds, 2, Strategy::Dfs, true);
    assert_eq!(unsatisfied(&report), Vec::<&str>::new());
    assert_eq!(report.unique, pins::RTC_QUOTA.unique);
}

/// A quota of one live scene per interface, two interfaces and two identifiers: each holds at
/// most one, and every safety property holds; two scenes on one interface, and the scene limit,
/// are out of reach.
#[test]
fn a_quota_of_one_scene_per_interface() {
    let bounds = RtcBounds {
        live: 2,
        quota: Some(1),
        ..RtcBounds::new(2, 2)
    };
    let report = run(bounds, 2, Strategy::Dfs, true);
    assert_eq!(
        unsatisfied(&report),
        [
            "COOP-REG-FULL.1: an update beyond the scene limit is refused",
            "COOP-OWN-REMOVE.1: a clear retires two scenes",
        ]
    );
}

/// Three interfaces (the intersection is a module of its own, velocity scenes) and two
/// identifiers: an auto-mode switch must not reach another module, and a velocity scene
/// reports one distance twice. Every safety property holds; a scene limit of one leaves two
/// witnesses unreachable.
#[test]
fn three_interfaces_two_scenes() {
    let report = run(RtcBounds::new(3, 2), 2, Strategy::Dfs, true);
    assert_eq!(
        unsatisfied(&report),
        [
            "COOP-OWN-REMOVE.1: a clear retires two scenes",
            "witness: two interfaces have live scenes at once",
        ]
    );
}

/// Without symmetry, depth first and breadth first agree, and the reduction is a reduction.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_interfaces_two_scenes_without_symmetry() {
    let bounds = RtcBounds {
        live: 2,
        ..RtcBounds::new(2, 2)
    };
    let dfs = run(bounds, 1, Strategy::Dfs, false);
    let bfs = run(bounds, 1, Strategy::Bfs, false);
    assert_eq!(dfs.unique, bfs.unique);
    // Two identifiers may both be live here, so the scene limit is never met.
    assert_eq!(
        unsatisfied(&bfs),
        ["COOP-REG-FULL.1: an update beyond the scene limit is refused"]
    );
    let reduced = run(bounds, 1, Strategy::Dfs, true);
    assert!(reduced.unique < dfs.unique);
}

/// A retired set smaller than the identifiers: the core forgets the oldest retirements, and an
/// identifier another interface registered may register again; the routes follow, and stay
/// within their bound with four identifiers to outgrow it (no symmetry, since the retirement
/// order matters).
#[test]
fn forgetting_retired_identifiers() {
    let bounds = RtcBounds {
        live: 1,
        retired: 1,
        ..RtcBounds::new(2, 4)
    };
    let report = run(bounds, 2, Strategy::Bfs, false);
    assert_eq!(broken(&report), Vec::<&str>::new());
}

/// One avoidance interface, bound to `avoidance/change` and `avoidance/return`, and two
/// identifiers both live at once: the owner states each scene's sequence (or, wrongly, none, or
/// one the interface is not bound to), the AD API sets either sequence's policy, so a change
/// and a return live side by side under different policies, and every status, query and
/// auto-mode switch must follow each scene's own module. Everything is reachable but what
/// needs a second interface or a scene limit below the identifiers.
#[test]
fn avoidance_change_and_return() {
    let bounds = RtcBounds {
        live: 2,
        ..RtcBounds::new(1, 2).from_interface(AVOIDANCE)
    };
    let report = run(bounds, 2, Strategy::Dfs, true);
    assert_eq!(
        unsatisfied(&report),
        [
            "COOP-DEV-ID-REUSE.1: an update of another interface's scene is refused",
            "COOP-REG-FULL.1: an update beyond the scene limit is refused",
            "COOP-DEV-ID-REUSE.1: a removal of another interface's scene is refused",
            "COOP-DEV-ID-REUSE.1: an interface's command for another interface's scene is refused",
            "witness: two interfaces have live scenes at once",
        ]
    );
    assert_eq!(report.unique, pins::RTC_AVOIDANCE.unique);
}

/// Both avoidance interfaces, which share their two modules, so only the routes keep their
/// scenes apart, whatever sequence a report states; one scene live at a time.
#[test]
fn two_avoidance_interfaces() {
    let bounds = RtcBounds::new(2, 2).from_interface(AVOIDANCE);
    let report = run(bounds, 2, Strategy::Dfs, true);
    assert_eq!(
        unsatisfied(&report),
        [
            "COOP-OWN-REMOVE.1: a clear retires two scenes",
            "witness: two interfaces have live scenes at once",
            "witness: one interface has live scenes of two modules under different policies",
        ]
    );
    assert_eq!(report.unique, pins::RTC_TWO_AVOIDANCES.unique);
}

/// The property each fault must break.
fn expected(fault: RtcFault) -> &'static str {
    match fault {
        RtcFault::AutoModeClobbers => {
            "COOP-DEV-POLICY-CLOBBER.1: an auto-mode switch keeps every scene and operator decision"
        }
        RtcFault::CommandCrossesInterface | RtcFault::RemoveCrossesInterface => {
            "COOP-DEV-ID-REUSE.1: an interface's calls change only scenes registered through it"
        }
        RtcFault::StoredCommandReapplies => {
            "COOP-DEV-STORED-COMMANDS.1, COOP-DEV-NONE.1: a new scene starts with no operator decision"
        }
        RtcFault::RejectionDropped | RtcFault::SequenceIgnored => {
            "COOP-DEV-SILENT-DROP.1, COOP-DEV-REGISTER-PHASE.1, COOP-DEV-SEQUENCE.1: an accepted status update or removal leaves the scene as reported, in the module its sequence names"
        }
        RtcFault::RefusalHalfApplies => {
            "COOP-DEV-SILENT-DROP.1: a refused call changes nothing (the state after it equals the state before)"
        }
        RtcFault::AutoModeOneSequence => {
            "COOP-DEV-AUTO-MODE-KEY.1, COOP-DEV-ROUTING.1: an auto-mode switch reaches every interface of its modules and no other"
        }
        RtcFault::RemoveInFirstSequence => {
            "COOP-DEV-SEQUENCE.1, COOP-OWN-MODULE.1: an update is refused for its sequence exactly when it is unbound, unstated for a new scene of several, or not its live scene's; no other call meets the module rule"
        }
    }
}

/// The bounds the faults are checked at: the two lane changes, or, for a fault that only an
/// interface bound to several sequences can show, the avoidance with two scenes live.
fn small(fault: Option<RtcFault>) -> RtcBounds {
    if fault.is_some_and(RtcFault::needs_sequences) {
        RtcBounds {
            live: 2,
            ..RtcBounds::new(1, 2).from_interface(AVOIDANCE)
        }
    } else {
        RtcBounds::new(2, 2)
    }
}

/// The counterexample replays to the violation from its JSON, and the same calls pass on the
/// shipped adapter.
fn replays(fault: RtcFault, trace: &Trace) {
    assert!(!trace.is_empty());
    let json = serde_json::to_string(trace).expect("serializes");
    let replayed: Trace = serde_json::from_str(&json).expect("reads back");
    assert_eq!(&replayed, trace);
    assert!(
        !replayed.holds_at_end().expect("replays"),
        "{fault:?}: the replay holds"
    );
    assert!(
        replayed.without_fault().holds_at_end().expect("replays"),
        "{fault:?}: the shipped adapter fails"
    );
    let text = trace.render().expect("renders");
    assert!(text.contains("  1. "), "{text}");
    let diagram = trace.sequence_diagram().expect("draws");
    assert!(diagram.contains("->>Adapter"), "{diagram}");
}

#[test]
fn every_fault_is_caught_with_a_replayable_counterexample() {
    for fault in RtcFault::ALL {
        let property = expected(fault);
        let model = RtcModel::new(small(Some(fault)))
            .expect("valid")
            .with_fault(fault);
        let trace = shortest(&model, property)
            .unwrap_or_else(|| panic!("{fault:?} went unnoticed by {property:?}"));
        replays(fault, &trace);
        eprintln!("{fault:?}:\n{}", trace.render().expect("renders"));
    }
}

/// The fault bounds break no safety property without a fault: the faults, not the bounds, fail.
/// (The avoidance's bounds are checked whole by `avoidance_change_and_return`.)
#[test]
fn the_fault_bounds_pass_without_a_fault() {
    let report = run(small(None), 2, Strategy::Dfs, true);
    assert_eq!(broken(&report), Vec::<&str>::new());
}

/// Property names are unique (the checker keys discoveries by name), each names a spec tag or
/// is a witness, and each makes a file name.
#[test]
fn property_names_are_unique_and_tagged() {
    let names: Vec<&str> = cooperation_models::model::rtc::properties()
        .iter()
        .map(|p| p.name)
        .collect();
    let unique: std::collections::BTreeSet<&str> = names.iter().copied().collect();
    assert_eq!(unique.len(), names.len());
    for name in names {
        assert!(
            name.starts_with("COOP-") || name.starts_with("witness: "),
            "{name}"
        );
        // A counterexample is saved under the property's name, with `.json`; a file name has
        // at most 255 bytes.
        assert!(name.len() <= 240, "{name} is too long for a file name");
    }
}
