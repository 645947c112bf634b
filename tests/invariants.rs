//! One test per invariant of spec §8, named after its tag: a state that breaks the invariant
//! (built through the serialized form, the only way past `apply`) is refused by
//! `check_invariants` with that invariant, and a reachable state near the bound passes.

mod common;

use common::*;
use cooperation::*;
use serde_json::{json, Value};

/// A reachable state: one scene live per module, one retired.
fn reachable() -> State {
    let mut state = with_scenes();
    fires(
        &mut state,
        register(id(3), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        Input::Remove {
            id: id(3),
            module: LANE_CHANGE,
        },
        Rule::OwnerRemove,
    );
    fires(
        &mut state,
        Input::Tick { elapsed_ms: TTL_MS },
        Rule::TimeAge,
    );
    state
}

/// Serializes the reachable state, lets `corrupt` edit it, and returns the deserialization
/// error (which runs `check_invariants`).
fn refused(corrupt: impl FnOnce(&mut Value)) -> String {
    let state = reachable();
    let mut value = serde_json::to_value(&state).expect("serializes");
    let back: State = serde_json::from_value(value.clone()).expect("the untouched state loads");
    assert_eq!(back, state);
    corrupt(&mut value);
    serde_json::from_value::<State>(value)
        .expect_err("the corrupted state is refused")
        .to_string()
}

fn first_scene(value: &mut Value) -> &mut Value {
    &mut value["scenes"][0][1]
}

#[test]
fn coop_inv_disjoint_1() {
    let error = refused(|v| {
        let live = v["scenes"][0][0].clone();
        v["retired"].as_array_mut().expect("list").push(json!([live, {"module": {"behavior": "LaneChange", "sequence": "Empty"}, "reason": "Removed"}]));
        v["retired_order"].as_array_mut().expect("list").push(live);
    });
    assert!(error.contains("COOP-INV-DISJOINT.1"), "{error}");
}

#[test]
fn coop_inv_retired_order_1() {
    let error = refused(|v| v["retired_order"] = json!([]));
    assert!(error.contains("COOP-INV-RETIRED-ORDER.1"), "{error}");
    let error = refused(|v| {
        let first = v["retired_order"][0].clone();
        v["retired_order"].as_array_mut().expect("list").push(first);
    });
    assert!(error.contains("COOP-INV-RETIRED-ORDER.1"), "{error}");
}

#[test]
fn coop_inv_retired_bound_1() {
    let error = refused(|v| v["limits"]["retired_capacity"] = json!(0));
    assert!(error.contains("COOP-INV-RETIRED-BOUND.1"), "{error}");
}

#[test]
fn coop_inv_live_bound_1() {
    let error = refused(|v| v["limits"]["max_scenes"] = json!(1));
    assert!(error.contains("COOP-INV-LIVE-BOUND.1"), "{error}");
}

#[test]
fn coop_inv_live_phase_1() {
    let error = refused(|v| first_scene(v)["phase"] = json!("Succeeded"));
    assert!(error.contains("COOP-INV-LIVE-PHASE.1"), "{error}");
}

#[test]
fn coop_inv_age_1() {
    let error = refused(|v| first_scene(v)["age_ms"] = json!(TTL_MS + 1));
    assert!(error.contains("COOP-INV-AGE.1"), "{error}");
}

#[test]
fn coop_inv_module_1() {
    let error = refused(|v| v["policies"] = json!([]));
    assert!(error.contains("COOP-INV-MODULE.1"), "{error}");
}

/// `[COOP-INV-RETIRED-ORDER.1]` past 32 retired identifiers, where the check counts distinct
/// entries instead of comparing pairs: an exact order passes, a repeated entry is refused.
#[test]
fn coop_inv_retired_order_1_large() {
    let mut state = State::new(Config {
        limits: Limits {
            retired_capacity: 100,
            ..config().limits
        },
        ..config()
    })
    .expect("valid");
    churn(&mut state, 1..=40);
    assert_eq!(state.check_invariants(), Ok(()));
    let mut value = serde_json::to_value(&state).expect("serializes");
    let order = value["retired_order"].as_array_mut().expect("list");
    let first = order[0].clone();
    order[1] = first;
    let error = serde_json::from_value::<State>(value)
        .expect_err("refused")
        .to_string();
    assert!(error.contains("COOP-INV-RETIRED-ORDER.1"), "{error}");
}
