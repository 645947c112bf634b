//! The AD API calls of spec §6.6 over the core (`cooperation_adapters::wire`): each call's response
//! status, whether it changed the state, and the typed read–answer–write path a server takes.

use crate::common::*;
use cooperation::*;
use cooperation_adapters::wire::{self, Request, Response, ResponseStatus, Service};
use cooperation_adapters::Host;

fn commands(list: &[(SceneId, OperatorDecision)]) -> wire::SetCooperationCommandsRequest {
    list.iter()
        .map(|&(id, decision)| Command { id, decision })
        .collect()
}

fn policy_request(list: &[(Module, Policy)]) -> wire::SetCooperationPoliciesRequest {
    list.iter()
        .map(|&(module, policy)| PolicySetting { module, policy })
        .collect()
}

/// `[COOP-API-SET-COMMANDS.1]`: the batch applies all or none and the answer is a status; a
/// refused batch names each failing command and changes nothing.
#[test]
fn coop_api_set_commands_1() {
    let mut state = with_scenes();
    let applied = wire::set_commands(
        &mut state,
        &commands(&[
            (id(1), OperatorDecision::Activate),
            (id(2), OperatorDecision::Autonomous),
        ]),
    );
    assert_eq!(applied.response.status, ResponseStatus::success());
    assert!(applied.changed);
    let before = state.clone();
    let rejected = wire::set_commands(
        &mut state,
        &commands(&[
            (id(9), OperatorDecision::Activate),
            (id(2), OperatorDecision::Deactivate),
        ]),
    );
    assert!(!rejected.response.status.success && !rejected.changed);
    assert_eq!(
        rejected.response.status.message,
        "no command applied: command 0 (scene 00000000-0000-0000-0000-000000000009): unknown scene"
    );
    assert_eq!(state, before);
    let too_many = wire::set_commands(
        &mut state,
        &commands(&[(id(1), OperatorDecision::Activate); 5]),
    );
    assert_eq!(
        too_many.response.status.code,
        ResponseStatus::PARAMETER_ERROR
    );
    assert_eq!(state, before);
}

/// `[COOP-API-SET-POLICIES.1]`: applies all or nothing and answers with a status.
#[test]
fn coop_api_set_policies_1() {
    let mut state = with_scenes();
    let answer = wire::set_policies(
        &mut state,
        &policy_request(&[(AVOIDANCE, Policy::Optional)]),
    );
    assert_eq!(answer.response.status, ResponseStatus::success());
    assert!(answer.changed);
    let answer = wire::set_policies(
        &mut state,
        &policy_request(&[
            (LANE_CHANGE, Policy::Required),
            (INTERSECTION, Policy::Required),
        ]),
    );
    assert!(!answer.response.status.success && !answer.changed);
    assert_eq!(answer.response.status.code, ResponseStatus::PARAMETER_ERROR);
    assert_eq!(state.policy(LANE_CHANGE), Some(Policy::Optional));
}

/// `[COOP-API-STATUS.1]`: success is code 0, an empty batch warns NO_EFFECT, a rejection is a
/// PARAMETER_ERROR whose message names each failing command.
#[test]
fn coop_api_status_1() {
    let mut state = with_scenes();
    let empty = wire::set_commands(&mut state, &commands(&[]));
    assert_eq!(
        empty.response.status,
        ResponseStatus {
            success: true,
            code: ResponseStatus::NO_EFFECT,
            message: "the batch is empty".into()
        }
    );
    assert!(!empty.changed);
    let empty = wire::set_policies(&mut state, &policy_request(&[]));
    assert_eq!(empty.response.status.code, ResponseStatus::NO_EFFECT);
    let rejected = wire::set_commands(
        &mut state,
        &commands(&[
            (id(1), OperatorDecision::Activate),
            (id(9), OperatorDecision::Activate),
        ]),
    );
    assert_eq!(
        rejected.response.status.code,
        ResponseStatus::PARAMETER_ERROR
    );
    assert_eq!(
        rejected.response.status.message,
        "no command applied: command 1 (scene 00000000-0000-0000-0000-000000000009): unknown scene"
    );
}

/// `get_policies` on the wire: success and every configured module's policy, in module order
/// (`[COOP-POL-GET.2]`), written as the AD API's `CooperationPolicy` messages.
#[test]
fn get_policies_lists_every_module_in_order() {
    let state = with_scenes();
    let response = wire::get_policies(&state, &wire::GetCooperationPoliciesRequest {});
    assert_eq!(response.status, ResponseStatus::success());
    let read: Vec<PolicySetting> = response
        .policies
        .iter()
        .map(|policy| PolicySetting::try_from(policy).expect("a policy the core wrote"))
        .collect();
    assert_eq!(read, state.policies().collect::<Vec<_>>());
}

/// A call that sets what is already set applies, and says that nothing changed: a server
/// publishes only on a change.
#[test]
fn setting_what_is_set_changes_nothing() {
    let mut state = with_scenes();
    let request = commands(&[(id(1), OperatorDecision::Activate)]);
    assert!(wire::set_commands(&mut state, &request).changed);
    let again = wire::set_commands(&mut state, &request);
    assert!(again.response.status.success && !again.changed);
    let optional = policy_request(&[(LANE_CHANGE, Policy::Optional)]);
    let again = wire::set_policies(&mut state, &optional);
    assert!(again.response.status.success && !again.changed);
    let required = policy_request(&[(LANE_CHANGE, Policy::Required)]);
    assert!(wire::set_policies(&mut state, &required).changed);
}

/// The path a server takes: read the request with no state at hand, answer it, write the typed
/// response once. A request that does not read is answered by the service's refusal, with the
/// field named, and reaches no state.
#[test]
fn a_call_is_read_then_answered_then_written() {
    let mut state = with_scenes();
    let json = br#"{"commands": [{"uuid": {"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,1]}, "cooperator": {"decision": 1}}]}"#;
    let request = Service::SetCommands.read(json).expect("reads");
    assert_eq!(request.service(), Service::SetCommands);
    let answer = request.answer(&mut state);
    assert!(answer.changed);
    assert_eq!(answer.response.status(), &ResponseStatus::success());
    assert_eq!(
        wire::to_json(&answer.response),
        br#"{"status":{"success":true,"code":0,"message":""}}"#
    );
    assert_eq!(
        state.scene(id(1)).map(Scene::operator_decision),
        Some(OperatorDecision::Deactivate)
    );

    // JSON of another shape does not read: the service's refusal names where.
    let malformed = Service::SetPolicies
        .read(br#"{"policies": {"behavior": "lane-change"}}"#)
        .expect_err("an object where a list goes");
    let refusal = Service::SetPolicies.refusal(&malformed);
    assert!(matches!(refusal, Response::SetPolicies(_)));
    assert!(
        refusal.status().message.starts_with("policies: "),
        "{}",
        refusal.status().message
    );
    // A message that reads but says what the core has no word for is refused by the answer,
    // which reaches no state either.
    let before = state.clone();
    let undefined = Service::SetPolicies
        .read(br#"{"policies": [{"behavior": "lane-change", "sequence": "", "policy": 9}]}"#)
        .expect("reads: any number fits the field");
    let answer = undefined.answer(&mut state);
    assert!(!answer.changed);
    assert_eq!(
        answer.response.status().message,
        "policies[0].policy: 9 is not a CooperationPolicy constant"
    );
    assert_eq!(state, before);

    let get = Service::GetPolicies.read(b"{}").expect("reads");
    assert!(matches!(get, Request::GetPolicies(_)));
    let answer = get.answer(&mut state);
    assert!(!answer.changed);
    let written = String::from_utf8(wire::to_json(&answer.response)).expect("UTF-8");
    assert!(written.starts_with(r#"{"status":{"success":true,"code":0,"message":""},"policies":["#));
}

/// A request over [`wire::MAX_REQUEST_BYTES`] is refused unread.
#[test]
fn a_request_over_the_limit_is_refused_unread() {
    let json = vec![b' '; wire::MAX_REQUEST_BYTES + 1];
    let refused = Service::GetPolicies.read(&json).expect_err("too large");
    assert!(matches!(refused, wire::Malformed::TooLarge { len, .. } if len == json.len()));
}

/// A host answers the AD API from its core, and its clock ticks the core by the time since the
/// last reading, never twice and never backwards.
#[test]
fn a_host_answers_and_keeps_time() {
    let (rtc, state) = rtc_setup(false);
    let mut host = Host::new(state, rtc);
    let request = Service::GetPolicies.read(b"{}").expect("reads");
    let answer = host.answer(&request);
    assert!(answer.response.status().success);
    let ticks = [
        host.advance_to(40).expect("ticks").map(|t| t.rule),
        host.advance_to(40).expect("ticks").map(|t| t.rule),
        host.advance_to(10).expect("ticks").map(|t| t.rule),
        host.advance_to(50).expect("ticks").map(|t| t.rule),
    ];
    assert_eq!(
        ticks,
        [Some(Rule::TimeAge), None, None, Some(Rule::TimeAge)]
    );
    assert_eq!(host.told_ms(), 50);
}
