//! The library's own pieces, tested through its public interface: the spec's tables as the
//! models read them, the sequential model's alphabet and properties, and the check's budget.
//! (They are here rather than in the library so that the test command does not build the
//! library a second time for them.)

use std::collections::BTreeSet;

use cooperation::{Decision, Input, OperatorDecision, Phase, Policy, Rule};
use cooperation_models::check::budget::{status_bytes, Budget, Exceeded, Halt};
use cooperation_models::model::sequential::{properties, rule_property, INVARIANTS};
use cooperation_models::model::spec::{LifecycleTable, MergeTable, SPEC};
use cooperation_models::{Bounds, SequentialModel};

#[test]
fn reads_the_specs_table() {
    let table = MergeTable::from_spec(SPEC).expect("the spec's table reads");
    assert_eq!(
        table.merged(
            OperatorDecision::Undecided,
            Policy::Required,
            Decision::Activate
        ),
        Some(Decision::Deactivate)
    );
    assert!(MergeTable::from_spec("no table here").is_err());
}

#[test]
fn reads_the_specs_lifecycle() {
    let table = LifecycleTable::from_spec(SPEC).expect("the spec's lifecycle reads");
    assert!(table.allows(Phase::Running, Phase::Succeeded));
    assert!(!table.allows(Phase::Aborting, Phase::Running));
    assert!(!table.allows(Phase::Failed, Phase::Failed));
    let edited = SPEC.replace(
        "| aborting | ✗ | ✗ | ✓ | ✗ | ✓ |",
        "| aborting | ✗ | ? | ✓ | ✗ | ✓ |",
    );
    assert!(LifecycleTable::from_spec(&edited).is_err());
    assert!(LifecycleTable::from_spec("no table here").is_err());
}

#[test]
fn the_alphabet_is_deterministic_and_covers_every_kind_of_input() {
    let model = SequentialModel::new(Bounds::new(2, 3)).expect("valid");
    let again = SequentialModel::new(Bounds::new(2, 3)).expect("valid");
    assert_eq!(model.alphabet(), again.alphabet());
    let has = |f: fn(&Input) -> bool| model.alphabet().iter().any(f);
    assert!(has(|i| matches!(i, Input::Register { .. })));
    assert!(has(|i| matches!(i, Input::Update { .. })));
    assert!(has(|i| matches!(i, Input::Remove { .. })));
    assert!(has(|i| matches!(i, Input::SetCommands { .. })));
    assert!(has(|i| matches!(i, Input::SetPolicies { .. })));
    assert!(has(|i| matches!(i, Input::Tick { .. })));
}

#[test]
fn there_is_a_property_per_rule_and_per_invariant() {
    let names: Vec<&str> = properties().iter().map(|p| p.name).collect();
    for rule in Rule::ALL {
        assert!(
            names
                .iter()
                .any(|n| n.starts_with(rule.tag()) && n.ends_with("is reachable")),
            "{rule}"
        );
        assert!(names.contains(&rule_property(rule).as_str()), "{rule}");
    }
    assert!(names.contains(&INVARIANTS));
    let unique: BTreeSet<&str> = names.iter().copied().collect();
    assert_eq!(unique.len(), names.len(), "property names are unique");
}

#[test]
fn a_budget_names_the_limit_reached_first() {
    let budget = Budget {
        memory_bytes: 10,
        states: 5,
    };
    assert_eq!(budget.exceeded(Some(9), 4), None);
    assert_eq!(budget.exceeded(None, 4), None);
    assert_eq!(budget.exceeded(Some(10), 4), Some(Exceeded::Memory(10)));
    assert_eq!(budget.exceeded(Some(9), 5), Some(Exceeded::States(5)));
    assert_eq!(budget.exceeded(None, 6), Some(Exceeded::States(6)));
}

#[test]
fn a_halt_is_shared_by_clones_only() {
    let halt = Halt::new();
    let clone = halt.clone();
    let other = Halt::new();
    halt.set();
    assert!(clone.is_set());
    assert!(!other.is_set());
    clone.release();
    assert!(!halt.is_set());
}

#[test]
fn this_process_has_a_resident_size() {
    let resident = status_bytes("VmRSS:").expect("Linux has /proc/self/status");
    assert!(resident > 0);
    assert!(status_bytes("NoSuchField:").is_none());
}
