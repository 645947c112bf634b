//! The checks can fail: every deliberately wrong behaviour is found by the checker, with a
//! (shortest) counterexample that replays to the violation from its JSON and passes against
//! the shipped code.

use cooperation::{OperatorDecision, SceneId};
use cooperation_models::check::run::{check, shortest, Settings, Strategy};
use cooperation_models::model::network::{reported, NetAction};
use cooperation_models::{Bounds, Fault, NetBounds, NetworkModel, SequentialModel, Trace, Views};

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

/// Breadth first over canonical states (`SequentialModel::with_canonical_states`), every fault
/// is caught too, and its shortest counterexample, found among renamed states, is translated
/// into inputs that replay to the violation on the model without renaming.
#[test]
fn every_fault_is_caught_through_canonical_states() {
    for fault in Fault::ALL {
        let (property, bounds) = expected(fault);
        let model = SequentialModel::new(bounds)
            .expect("valid")
            .with_fault(fault)
            .with_canonical_states(true);
        let trace = shortest(&model, property)
            .unwrap_or_else(|| panic!("{fault:?} went unnoticed by {property:?}"));
        replays(fault, &trace);
    }
}

/// The same bounds break no safety property without a fault: the faults, not the bounds, fail.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
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

/// One operator told the library's whole statuses: the faults that get decisions wrong are
/// caught by the network model's properties about decisions.
fn with_statuses(fault: Fault) -> NetworkModel {
    NetworkModel::new(NetBounds { scenes: 2 })
        .and_then(|model| model.with_operators(1))
        .expect("valid")
        .with_views(Views::Statuses)
        .with_fault(fault)
}

const NOT_CANCELLABLE: &str = "COOP-CMD-NOT-CANCELLABLE.1, COOP-CANCELLABLE.1 (network): a delivered command never changes the operator decision of a scene that is not cancellable";
const AT_ONCE: &str = "COOP-CMD-APPLY.1, COOP-DEV-STORED-COMMANDS.1 (network): a delivered command takes effect at once, and one for an identifier that is not live changes nothing, then or later";

/// A planner that applies commands to aborting scenes, one whose repeated command flips the
/// decision, and one whose owner updates clear it (as a stored command re-applied at an unlock
/// would change it) are each caught with status views.
#[test]
fn network_decision_faults_are_caught() {
    let cases = [
        (Fault::CommandIgnoresCancellable, NOT_CANCELLABLE),
        (Fault::CommandToggles, AT_ONCE),
        (Fault::OwnerClearsOperator, AT_ONCE),
    ];
    for (fault, property) in cases {
        let trace = shortest(&with_statuses(fault), property)
            .unwrap_or_else(|| panic!("{fault:?} went unnoticed by {property:?}"));
        replays(fault, &trace);
        let json = serde_json::to_string(&trace).expect("serializes");
        assert!(json.contains("\"views\":\"statuses\""), "{json}");
    }
}

/// The status property compares what a message carries with the library's statuses of the
/// state it was sent from: a message that is stale for that state, or whose decision was
/// altered, or that lacks its decisions, or a scene, fails it.
#[test]
fn coop_out_status_1_a_misreported_status_is_caught() {
    let model = NetworkModel::new(NetBounds { scenes: 2 })
        .and_then(|model| model.with_operators(1))
        .expect("valid")
        .with_views(Views::Statuses);
    let id = SceneId::from_u128(1);
    let actions = [
        NetAction::Owner(0),
        NetAction::Publish(0),
        NetAction::Receive(0, 0),
        NetAction::Send(0, id, OperatorDecision::Activate),
        NetAction::Deliver(0, 0),
    ];
    let steps = model.replay(&actions).expect("replays");
    assert_eq!(steps.len(), actions.len() + 1, "every action is enabled");
    let (registered, published, delivered) = (&steps[1], &steps[2], &steps[5]);
    let sent = &published.statuses[0][0].seen;
    assert!(reported(&registered.core, sent, Views::Statuses));
    // The same message judged against the state after the command: stale there.
    assert!(!reported(&delivered.core, sent, Views::Statuses));
    // A message whose operator decision was altered on the way.
    let mut altered = sent.clone();
    let status = altered[0].status.as_mut().expect("a status");
    status.operator_decision = OperatorDecision::Deactivate;
    assert!(!reported(&registered.core, &altered, Views::Statuses));
    // A message without decisions, or without the scene.
    let mut bare = sent.clone();
    bare[0].status = None;
    assert!(!reported(&registered.core, &bare, Views::Statuses));
    assert!(reported(&registered.core, &bare, Views::Identifiers));
    assert!(!reported(&registered.core, &[], Views::Statuses));
}
