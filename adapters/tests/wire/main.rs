//! The AD API on the wire: hand-written JSON requests through the service handlers, the factor
//! streams, and every class of malformed input with its typed error.
//!
//! One binary with a module per concern; `tests/wire_hostile.rs` is a binary of its own, because
//! it counts allocations with a global allocator.

mod core_rules;
mod extensions;
mod fields;
mod malformed;
mod mixed;
mod requests;
mod roundtrip;
mod strategies;
mod visibility;
mod wire_fixtures;

use cooperation::*;
use cooperation_adapters::wire::{self, Malformed, Service};
use cooperation_adapters::{FieldPath, PathSegment, Time};
use wire_fixtures::*;

/// A UUID's bytes as the JSON list.
fn list(id: SceneId) -> String {
    format!("{:?}", id.to_bytes())
}

/// Sends `request` to `service` as JSON, asserting a `PARAMETER_ERROR` whose message is
/// `malformed`'s, and no change of state. Also checks the typed path gives the same fault.
fn refused(state: &mut State, service: Service, request: &str, malformed: &Malformed) {
    let before = state.clone();
    let response = json(&service.call_json(state, request.as_bytes()));
    assert_eq!(
        *state, before,
        "{request}: a refused request changed the state"
    );
    assert_eq!(response["status"]["success"], false, "{request}");
    assert_eq!(
        response["status"]["code"],
        u64::from(wire::ResponseStatus::PARAMETER_ERROR),
        "{request}"
    );
    assert_eq!(
        response["status"]["message"],
        malformed.to_string(),
        "{request}"
    );
    if service == Service::GetPolicies {
        assert_eq!(response["policies"], serde_json::json!([]));
    }
}

/// The fault of a `set_commands` request, found by decoding then converting.
fn command_fault(request: &str) -> Malformed {
    let decoded = wire::from_json::<wire::SetCooperationCommandsRequest>(request.as_bytes());
    match decoded {
        Err(malformed) => malformed,
        Ok(request) => request.to_commands().expect_err("a fault"),
    }
}

/// The fault of a `set_policies` request.
fn policy_fault(request: &str) -> Malformed {
    let decoded = wire::from_json::<wire::SetCooperationPoliciesRequest>(request.as_bytes());
    match decoded {
        Err(malformed) => malformed,
        Ok(request) => request.to_policies().expect_err("a fault"),
    }
}

fn command(uuid: &str, decision: &str) -> String {
    format!(
        r#"{{"commands": [{{"uuid": {{"uuid": {uuid}}}, "cooperator": {{"decision": {decision}}}}}]}}"#
    )
}

/// The path `policies[1].{field}`.
fn policies_1(field: &str) -> FieldPath {
    let path: FieldPath = [
        PathSegment::Field("policies".into()),
        PathSegment::Index(1),
        PathSegment::Field(field.into()),
    ]
    .into_iter()
    .collect();
    assert_eq!(path.to_string(), format!("policies[1].{field}"));
    path
}

/// Sends a well-formed request the core rejects, asserting the response carries the core's
/// rejection for `rule`, and no change.
fn core_rejects(state: &mut State, service: Service, request: &str, rule: Rule) {
    let before = state.clone();
    let rejection = match service {
        Service::SetCommands => {
            let request: wire::SetCooperationCommandsRequest =
                wire::from_json(request.as_bytes()).unwrap();
            let commands = request.to_commands().expect("well-formed");
            state.clone().apply(&Input::SetCommands { commands })
        }
        Service::SetPolicies => {
            let request: wire::SetCooperationPoliciesRequest =
                wire::from_json(request.as_bytes()).unwrap();
            let policies = request.to_policies().expect("well-formed");
            state.clone().apply(&Input::SetPolicies { policies })
        }
        Service::GetPolicies => unreachable!("get_policies rejects nothing"),
    }
    .expect_err("the core rejects it");
    assert_eq!(rejection.rule(), rule);
    let response = json(&service.call_json(state, request.as_bytes()));
    assert_eq!(
        *state, before,
        "{request}: a rejected request changed the state"
    );
    assert_eq!(
        response["status"],
        serde_json::json!({
            "success": false,
            "code": wire::ResponseStatus::PARAMETER_ERROR,
            "message": rejection.to_string(),
        })
    );
}
