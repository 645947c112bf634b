//! The checks can fail: every deliberately wrong behaviour is caught by the exhaustive check
//! with a counterexample, and the counterexample replays to the violation from its JSON.

use cooperation_models::run::{check, Settings, Strategy};
use cooperation_models::{Bounds, Fault, SequentialModel, Trace};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The property each fault must break (others may break too).
fn expected(fault: Fault) -> &'static str {
    match fault {
        Fault::RequiredAsOptional => {
            "COOP-MERGE.1: required with no operator decision never activates"
        }
        Fault::OperatorDeactivateIgnored => "COOP-MERGE.1: an explicit operator decision wins",
        Fault::CommandReachesRetired => {
            "COOP-CMD-RETIRED.1: commands naming retired identifiers change nothing"
        }
        Fault::PolicyClobbersOperator => {
            "COOP-CMD-APPLY.1: only commands change operator decisions"
        }
        Fault::TerminalLeaves => {
            "COOP-REG-RETIRED.1: a remembered retired identifier never becomes live again"
        }
        Fault::RetiredIdReused => {
            "COOP-REG-RETIRED.1: a remembered retired identifier never becomes live again"
        }
        Fault::RejectionHalfApplies => "spec §4: a rejected input changes nothing",
        Fault::BatchNotAtomic => "spec §4: a rejected input changes nothing",
        Fault::IdMovesModule => {
            "COOP-OWN-MODULE.1: an identifier keeps its module while remembered"
        }
        Fault::OwnerClearsOperator => "COOP-CMD-APPLY.1: only commands change operator decisions",
        Fault::ForgetsEarly => {
            "COOP-RETIRE.1: the retired set forgets only when full, oldest first"
        }
    }
}

#[test]
fn every_fault_is_caught_with_a_replayable_counterexample() {
    let settings = Settings {
        threads: 2,
        strategy: Strategy::Dfs,
        symmetry: true,
    };
    let clean = SequentialModel::new(Bounds::new(2, 2)).expect("valid");
    assert!(
        check(&clean, settings, &mut std::io::sink()).passed(),
        "the shipped code passes"
    );
    for fault in Fault::ALL {
        // Forgetting early needs a retired set that holds several with room to spare.
        let bounds = match fault {
            Fault::ForgetsEarly => Bounds {
                modules: 1,
                scenes: 3,
                live: 1,
                retired: 3,
            },
            _ => Bounds::new(2, 2),
        };
        let model = SequentialModel::new(bounds)
            .expect("valid")
            .with_fault(fault);
        let report = check(&model, settings, &mut std::io::sink());
        assert!(!report.passed(), "{fault:?} went unnoticed");
        let outcome = report
            .outcomes
            .iter()
            .find(|o| o.name == expected(fault))
            .unwrap_or_else(|| panic!("no property {:?}", expected(fault)));
        assert!(!outcome.holds, "{fault:?} did not break {:?}", outcome.name);
        let trace = outcome.counterexample.clone().expect("a counterexample");
        assert!(!trace.inputs.is_empty());
        let json = serde_json::to_string(&trace).expect("serializes");
        let replayed: Trace = serde_json::from_str(&json).expect("reads back");
        assert_eq!(replayed, trace);
        assert!(
            !replayed.holds_at_end().expect("replays"),
            "{fault:?}: replay"
        );
        let mut without_fault = replayed.clone();
        without_fault.fault = None;
        assert!(
            without_fault.holds_at_end().expect("replays"),
            "{fault:?}: the shipped code"
        );
        assert!(trace.render().expect("renders").contains("1. "));
    }
}
