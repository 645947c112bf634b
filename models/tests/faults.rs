//! The checks can fail: every deliberately wrong behaviour is found by the checker, with a
//! (shortest) counterexample that replays to the violation from its JSON and passes against
//! the shipped code.

use cooperation_models::run::{check, shortest, Settings, Strategy};
use cooperation_models::{Bounds, Fault, NetBounds, NetworkModel, SequentialModel, Trace};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The sequential model's property each fault must break, and the bounds that can show it.
fn expected(fault: Fault) -> (&'static str, Bounds) {
    let small = Bounds::new(2, 2);
    let two_live = Bounds {
        modules: 1,
        scenes: 2,
        live: 2,
        retired: 2,
    };
    let roomy = Bounds {
        modules: 1,
        scenes: 3,
        live: 1,
        retired: 3,
    };
    match fault {
        Fault::RequiredAsOptional => (
            "COOP-MERGE.1, COOP-REQUESTED.1: required or requested with no operator decision never activates",
            small,
        ),
        Fault::OperatorDeactivateIgnored => {
            ("COOP-MERGE.1: an explicit operator decision wins", small)
        }
        Fault::CommandReachesRetired => (
            "COOP-CMD-RETIRED.1: commands naming retired identifiers change nothing",
            two_live,
        ),
        Fault::PolicyClobbersOperator => (
            "COOP-CMD-APPLY.1: only commands change operator decisions",
            small,
        ),
        Fault::TerminalLeaves | Fault::RetiredIdReused => (
            "COOP-REG-RETIRED.1: a remembered retired identifier never becomes live again",
            small,
        ),
        Fault::RejectionHalfApplies | Fault::BatchNotAtomic => {
            ("spec §4: a rejected input changes nothing", two_live)
        }
        Fault::IdMovesModule => (
            "COOP-OWN-MODULE.1: an identifier keeps its module while remembered",
            small,
        ),
        Fault::OwnerClearsOperator => (
            "COOP-CMD-APPLY.1: only commands change operator decisions",
            small,
        ),
        Fault::ForgetsEarly => (
            "COOP-RETIRE.1: the retired set forgets only when full, oldest first",
            roomy,
        ),
        Fault::CommandToggles => ("COOP-CMD-APPLY.1: an applied command takes effect", small),
        Fault::CommandBroadcast => (
            "COOP-CMD-APPLY.1: a command changes only the operator decision it names",
            two_live,
        ),
        Fault::CommandIgnoresCancellable => (
            "COOP-CMD-NOT-CANCELLABLE.1: when the spec's condition holds, this rule fires with the spec's outcome",
            small,
        ),
    }
}

/// The checked trace replays to the violation, and the same inputs pass on the shipped code.
fn replays(fault: Fault, trace: &Trace) {
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
        "{fault:?}: shipped code fails"
    );
    assert!(trace.render().expect("renders").contains("  1. "));
}

#[test]
fn every_fault_is_caught_with_a_replayable_counterexample() {
    for fault in Fault::ALL {
        let (property, bounds) = expected(fault);
        let model = SequentialModel::new(bounds)
            .expect("valid")
            .with_fault(fault);
        let trace = shortest(&model, property)
            .unwrap_or_else(|| panic!("{fault:?} went unnoticed by {property:?}"));
        replays(fault, &trace);
    }
}

/// The same bounds break no safety property without a fault: the faults, not the bounds, fail.
#[test]
fn the_fault_bounds_pass_without_a_fault() {
    let settings = Settings {
        threads: 2,
        strategy: Strategy::Dfs,
        symmetry: true,
    };
    for bounds in Fault::ALL.map(|fault| expected(fault).1) {
        let model = SequentialModel::new(bounds).expect("valid");
        let report = check(&model, settings, &mut std::io::sink());
        assert!(report.complete);
        let broken: Vec<&str> = report
            .outcomes
            .iter()
            .filter(|o| !o.holds && !matches!(o.expectation, stateright::Expectation::Sometimes))
            .map(|o| o.name)
            .collect();
        assert!(broken.is_empty(), "{bounds:?}: {broken:?}");
    }
}

/// The network model's step properties can fail too.
#[test]
fn network_faults_are_caught() {
    let cases = [
        (
            Fault::RetiredIdReused,
            "COOP-REG-RETIRED.1 (network): a command built from a stale status never touches a newer scene",
        ),
        (Fault::CommandToggles, "COOP-CMD-APPLY.1 (network): a duplicated command has no second effect"),
        (Fault::CommandBroadcast, "COOP-CMD-APPLY.1 (network): a command affects only the scene it names"),
    ];
    for (fault, property) in cases {
        let model = NetworkModel::new(NetBounds { scenes: 2 })
            .expect("valid")
            .with_fault(fault);
        let trace = shortest(&model, property)
            .unwrap_or_else(|| panic!("{fault:?} went unnoticed by {property:?}"));
        replays(fault, &trace);
    }
}
