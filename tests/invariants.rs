//! One test per invariant of spec §8, named after its tag: a state that breaks the invariant
//! (built through the serialized form, the only way past `apply`) is refused by
//! `check_invariants` with that invariant, and a reachable state near the bound passes.

use crate::common::*;
use cooperation::*;
use serde_json::{json, Value};

/// A reachable state: one scene live per module (1 and 2), two retired (3, then 4), every
/// age at the TTL.
fn reachable() -> State {
    let mut state = with_scenes();
    churn(&mut state, 3..=4);
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

/// As [`refused`], for a corruption that keeps the length of every list in the state (the
/// scenes, the retired identifiers, their order, the policies): the check must read the
/// contents, not only count them.
fn refused_keeping_lengths(corrupt: impl FnOnce(&mut Value)) -> String {
    let lengths = |v: &Value| {
        ["scenes", "retired", "retired_order", "policies"]
            .map(|list| v[list].as_array().map(Vec::len))
    };
    refused(|v| {
        let before = lengths(v);
        corrupt(v);
        assert_eq!(lengths(v), before, "the corruption keeps every length");
    })
}

fn first_scene(value: &mut Value) -> &mut Value {
    &mut value["scenes"][0][1]
}

#[test]
fn coop_inv_disjoint_1() {
    let error = refused(|v| {
        let live = v["scenes"][0][0].clone();
        v["retired"].as_array_mut().expect("list").push(json!([live, {"module": {"behavior": "lane-change", "sequence": ""}, "reason": "removed"}]));
        v["retired_order"].as_array_mut().expect("list").push(live);
    });
    assert!(error.contains("COOP-INV-DISJOINT.1"), "{error}");
    // The retired identifier 3 renamed to the live 1, in the retired set and in the order.
    let error = refused_keeping_lengths(|v| {
        let live = v["scenes"][0][0].clone();
        v["retired"][0][0] = live.clone();
        v["retired_order"][0] = live;
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
    // An entry of the order replaced by the other retired identifier, by a live one, or by
    // one that is neither.
    let replacements = [
        json!("00000000-0000-0000-0000-000000000004"),
        json!("00000000-0000-0000-0000-000000000001"),
        json!("00000000-0000-0000-0000-000000000009"),
    ];
    for replacement in replacements {
        let error = refused_keeping_lengths(|v| v["retired_order"][0] = replacement);
        assert!(error.contains("COOP-INV-RETIRED-ORDER.1"), "{error}");
    }
}

/// A permuted retirement order is not a corruption: it is the state that retiring 4 before 3
/// reaches, and it loads with its order as written.
#[test]
fn a_permuted_retirement_order_is_another_history() {
    let mut value = serde_json::to_value(reachable()).expect("serializes");
    value["retired_order"]
        .as_array_mut()
        .expect("list")
        .reverse();
    let state: State = serde_json::from_value(value).expect("a reachable state loads");
    let order: Vec<SceneId> = state.retired_oldest_first().map(|(id, _)| id).collect();
    assert_eq!(order, [id(4), id(3)]);
}

#[test]
fn coop_inv_retired_bound_1() {
    // A capacity of 0 is refused before any invariant, as `State::new` refuses it.
    let error = refused(|v| v["limits"]["retired_capacity"] = json!(0));
    assert!(
        error.contains("retired_capacity must be at least 1"),
        "{error}"
    );
    // One below the two identifiers retired: the bound is exact.
    let error = refused_keeping_lengths(|v| v["limits"]["retired_capacity"] = json!(1));
    assert!(error.contains("COOP-INV-RETIRED-BOUND.1"), "{error}");
}

#[test]
fn coop_inv_live_bound_1() {
    let error = refused(|v| v["limits"]["max_scenes"] = json!(1));
    assert!(error.contains("COOP-INV-LIVE-BOUND.1"), "{error}");
}

#[test]
fn coop_inv_live_phase_1() {
    for terminal in ["succeeded", "failed"] {
        let error = refused_keeping_lengths(|v| first_scene(v)["phase"] = json!(terminal));
        assert!(error.contains("COOP-INV-LIVE-PHASE.1"), "{error}");
    }
}

#[test]
fn coop_inv_age_1() {
    let error = refused_keeping_lengths(|v| first_scene(v)["age_ms"] = json!(TTL_MS + 1));
    assert!(error.contains("COOP-INV-AGE.1"), "{error}");
    // Every age is at the TTL: a TTL one lower leaves every scene over it.
    let error = refused_keeping_lengths(|v| v["limits"]["ttl_ms"] = json!(TTL_MS - 1));
    assert!(error.contains("COOP-INV-AGE.1"), "{error}");
}

#[test]
fn coop_inv_module_1() {
    let error = refused(|v| v["policies"] = json!([]));
    assert!(error.contains("COOP-INV-MODULE.1"), "{error}");
    // A live scene moved to a module that was not configured.
    let error = refused_keeping_lengths(|v| {
        first_scene(v)["module"] = serde_json::to_value(INTERSECTION).expect("serializes");
    });
    assert!(error.contains("COOP-INV-MODULE.1"), "{error}");
}

/// `[COOP-INV-RETIRED-ORDER.1]` with 40 retired identifiers, more than any model remembers: an
/// exact order passes, a repeated entry is refused.
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
