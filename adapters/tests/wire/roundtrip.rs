//! Property tests of the wire module: every message survives JSON; conversions into the core
//! and back are exact where both sides can hold the value; the handlers answer every request,
//! well-formed or not, as the core would, and never panic on any bytes.

use super::strategies::*;
use super::wire_fixtures::*;
use cooperation::*;
use cooperation_adapters::wire::{self, Malformed, Service};
use proptest::prelude::*;
use proptest::sample::select;
use serde::{de::DeserializeOwned, Serialize};
use std::fmt::Debug;

// -------------------------------------------------------------------------------------------
// JSON round trips of every message
// -------------------------------------------------------------------------------------------

fn json_round_trip<T: Serialize + DeserializeOwned + PartialEq + Debug>(
    message: &T,
) -> Result<(), TestCaseError> {
    let text = wire::to_json(message);
    let read = wire::from_json::<T>(&text);
    prop_assert_eq!(
        read.as_ref(),
        Ok(message),
        "{}",
        String::from_utf8_lossy(&text)
    );
    Ok(())
}

proptest! {
    #[test]
    fn ros_shapes_survive_json(
        time in time(),
        header in header(),
        point in point(),
        quaternion in quaternion(),
        pose in pose(),
        uuid in uuid(),
    ) {
        json_round_trip(&time)?;
        json_round_trip(&header)?;
        json_round_trip(&point)?;
        json_round_trip(&quaternion)?;
        json_round_trip(&pose)?;
        json_round_trip(&uuid)?;
    }

    #[test]
    fn uuids_survive_json_in_base64(uuid in uuid()) {
        let text = format!(r#"{{"uuid": "{}"}}"#, uuid.to_base64());
        prop_assert_eq!(wire::from_json::<wire::Uuid>(text.as_bytes()), Ok(uuid));
        let unpadded = format!(r#"{{"uuid": "{}"}}"#, uuid.to_base64().trim_end_matches('='));
        prop_assert_eq!(wire::from_json::<wire::Uuid>(unpadded.as_bytes()), Ok(uuid));
    }

    #[test]
    fn cooperation_messages_survive_json(
        decision in decision(),
        status in status(),
        command in command(),
        policy in policy(),
        response in response_status(),
    ) {
        json_round_trip(&decision)?;
        json_round_trip(&status)?;
        json_round_trip(&command)?;
        json_round_trip(&policy)?;
        json_round_trip(&response)?;
    }

    #[test]
    fn factor_messages_survive_json(
        velocity in velocity_factor(),
        steering in steering_factor(),
        velocity_array in velocity_array(),
        steering_array in steering_array(),
    ) {
        json_round_trip(&velocity)?;
        json_round_trip(&steering)?;
        json_round_trip(&velocity_array)?;
        json_round_trip(&steering_array)?;
    }

    #[test]
    fn service_messages_survive_json(
        commands in commands_request(),
        policies in policies_request(),
        status in response_status(),
        listed in prop::collection::vec(policy(), 0..4),
    ) {
        json_round_trip(&commands)?;
        json_round_trip(&wire::SetCooperationCommandsResponse { status: status.clone() })?;
        json_round_trip(&policies)?;
        json_round_trip(&wire::SetCooperationPoliciesResponse { status: status.clone() })?;
        json_round_trip(&wire::GetCooperationPoliciesRequest {})?;
        json_round_trip(&wire::GetCooperationPoliciesResponse { status, policies: listed })?;
    }
}

// -------------------------------------------------------------------------------------------
// Conversions: core → wire → core is the identity; wire → core → wire is, where it parses
// -------------------------------------------------------------------------------------------

proptest! {
    #[test]
    fn core_values_survive_the_wire(
        id in scene_id(),
        decision in select(Decision::ALL.to_vec()),
        operator in select(OperatorDecision::ALL.to_vec()),
        module in module(),
        policy in select(Policy::ALL.to_vec()),
        status in core_status(),
        pose in core_pose(),
        velocity in core_velocity_factor(),
        steering in core_steering_factor(),
    ) {
        prop_assert_eq!(SceneId::from(wire::Uuid::from(id)), id);
        prop_assert_eq!(Decision::try_from(wire::CooperationDecision::from(decision)), Ok(decision));
        prop_assert_eq!(
            OperatorDecision::try_from(wire::CooperationDecision::from(operator)),
            Ok(operator)
        );
        let command = Command { id, decision: operator };
        prop_assert_eq!(Command::try_from(&wire::CooperationCommand::from(command)), Ok(command));
        let setting = PolicySetting { module, policy };
        prop_assert_eq!(
            PolicySetting::try_from(&wire::CooperationPolicy::from(setting)),
            Ok(setting)
        );
        prop_assert_eq!(
            CooperationStatus::try_from(&wire::CooperationStatus::from(status)),
            Ok(status)
        );
        prop_assert_eq!(Pose::from(wire::Pose::from(pose)), pose);
        // Factors compare by bit pattern, NaNs included.
        prop_assert_eq!(
            VelocityFactor::try_from(&wire::VelocityFactor::from(velocity.clone())),
            Ok(velocity)
        );
        prop_assert_eq!(
            SteeringFactor::try_from(&wire::SteeringFactor::from(steering.clone())),
            Ok(steering)
        );
    }

    #[test]
    fn core_batches_survive_the_wire(
        commands in prop::collection::vec(
            (scene_id(), select(OperatorDecision::ALL.to_vec()))
                .prop_map(|(id, decision)| Command { id, decision }),
            0..8,
        ),
        settings in prop::collection::vec(
            (module(), select(Policy::ALL.to_vec()))
                .prop_map(|(module, policy)| PolicySetting { module, policy }),
            0..8,
        ),
        velocity in prop::collection::vec(core_velocity_factor(), 0..4),
        steering in prop::collection::vec(core_steering_factor(), 0..4),
        stamp in time(),
    ) {
        let request: wire::SetCooperationCommandsRequest = commands.iter().copied().collect();
        prop_assert_eq!(request.to_commands(), Ok(commands));
        let request: wire::SetCooperationPoliciesRequest = settings.iter().copied().collect();
        prop_assert_eq!(request.to_policies(), Ok(settings));
        let header = wire::Header { stamp, frame_id: wire::FRAME_ID.to_owned() };
        let array = wire::VelocityFactorArray {
            header: header.clone(),
            factors: velocity.iter().cloned().map(Into::into).collect(),
        };
        prop_assert_eq!(array.to_factors(), Ok(velocity));
        let array = wire::SteeringFactorArray {
            header,
            factors: steering.iter().cloned().map(Into::into).collect(),
        };
        prop_assert_eq!(array.to_factors(), Ok(steering));
    }

    #[test]
    fn wire_values_that_parse_come_back_unchanged(
        uuid in uuid(),
        decision in decision(),
        status in status(),
        command in command(),
        policy in policy(),
        velocity in velocity_factor(),
        steering in steering_factor(),
    ) {
        // Each conversion accepts exactly its message's meaningful values...
        prop_assert_eq!(
            OperatorDecision::try_from(decision).is_ok(),
            (1..=4).contains(&decision.decision)
        );
        prop_assert_eq!(Decision::try_from(decision).is_ok(), (1..=2).contains(&decision.decision));
        // ...and what it accepts, it gives back unchanged.
        prop_assert_eq!(wire::Uuid::from(SceneId::from(uuid)), uuid);
        if let Ok(operator) = OperatorDecision::try_from(decision) {
            prop_assert_eq!(wire::CooperationDecision::from(operator), decision);
        }
        if let Ok(module_decision) = Decision::try_from(decision) {
            prop_assert_eq!(wire::CooperationDecision::from(module_decision), decision);
        }
        if let Ok(core) = CooperationStatus::try_from(&status) {
            prop_assert_eq!(wire::CooperationStatus::from(core), status);
        }
        if let Ok(core) = Command::try_from(&command) {
            prop_assert_eq!(wire::CooperationCommand::from(core), command);
        }
        match PolicySetting::try_from(&policy) {
            Ok(core) => prop_assert_eq!(wire::CooperationPolicy::from(core), policy),
            Err(fault) => prop_assert!(
                !(1..=2).contains(&policy.policy)
                    || policy.behavior.parse::<Behavior>().is_err()
                    || policy.sequence.parse::<Sequence>().is_err(),
                "{}", fault
            ),
        }
        // Factors, `detail` included.
        if let Ok(core) = VelocityFactor::try_from(&velocity) {
            prop_assert_eq!(core.detail.as_str(), velocity.detail.as_str());
            prop_assert_eq!(wire::VelocityFactor::from(core), velocity);
        }
        if let Ok(core) = SteeringFactor::try_from(&steering) {
            prop_assert_eq!(core.detail.as_str(), steering.detail.as_str());
            prop_assert_eq!(wire::SteeringFactor::from(core), steering);
        }
    }
}

// -------------------------------------------------------------------------------------------
// The handlers: exactly the core's answer for what parses, a PARAMETER_ERROR for the rest
// -------------------------------------------------------------------------------------------

/// A state with the fixtures' two scenes, one of them possibly no longer cancellable or
/// retired, and possibly an operator decision on B.
fn a_state() -> impl Strategy<Value = State> {
    (0..4usize, any::<bool>()).prop_map(|(phase, decided)| {
        let mut state = with_scenes();
        let phases = [Phase::Running, Phase::Aborting, Phase::Failed];
        for phase in phases.iter().take(phase) {
            update(&mut state, A, *phase);
        }
        if decided {
            let commands = vec![Command {
                id: B,
                decision: OperatorDecision::Activate,
            }];
            state
                .apply(&Input::SetCommands { commands })
                .expect("B is live and cancellable");
        }
        state
    })
}

/// Commands that mostly name the fixtures' scenes.
fn fixture_commands() -> impl Strategy<Value = wire::SetCooperationCommandsRequest> {
    let uuid = prop_oneof![
        3 => select(vec![A, B]).prop_map(wire::Uuid::from),
        1 => uuid(),
    ];
    let command = (uuid, decision())
        .prop_map(|(uuid, cooperator)| wire::CooperationCommand { uuid, cooperator });
    prop::collection::vec(command, 0..=MAX_BATCH + 1)
        .prop_map(|commands| wire::SetCooperationCommandsRequest { commands })
}

proptest! {
    #[test]
    fn set_commands_answers_as_the_core_or_names_the_fault(
        mut state in a_state(),
        request in fixture_commands(),
    ) {
        let before = state.clone();
        let answer = wire::set_commands(&mut state, &request);
        match request.to_commands() {
            Err(fault) => {
                prop_assert_eq!(answer.response.status, fault.to_status());
                prop_assert_eq!(&state, &before);
            }
            Ok(commands) => {
                let mut expected = before.clone();
                let len = commands.len();
                let core = expected.apply(&Input::SetCommands { commands });
                prop_assert_eq!(answer.response.status, wire::ResponseStatus::for_batch(len, &core));
                prop_assert_eq!(&state, &expected);
                if core.is_err() {
                    prop_assert_eq!(&state, &before);
                }
            }
        }
        // The answer says the state changed exactly when it did.
        prop_assert_eq!(answer.changed, state != before);
    }

    #[test]
    fn set_policies_answers_as_the_core_or_names_the_fault(
        mut state in a_state(),
        request in policies_request(),
    ) {
        let before = state.clone();
        let answer = wire::set_policies(&mut state, &request);
        match request.to_policies() {
            Err(fault) => {
                prop_assert_eq!(answer.response.status, fault.to_status());
                prop_assert_eq!(&state, &before);
            }
            Ok(policies) => {
                let mut expected = before.clone();
                let len = policies.len();
                let core = expected.apply(&Input::SetPolicies { policies });
                prop_assert_eq!(answer.response.status, wire::ResponseStatus::for_batch(len, &core));
                prop_assert_eq!(&state, &expected);
                if core.is_err() {
                    prop_assert_eq!(&state, &before);
                }
            }
        }
        // The answer says the state changed exactly when it did.
        prop_assert_eq!(answer.changed, state != before);
    }

    #[test]
    fn get_policies_lists_the_cores_policies(state in a_state()) {
        let response = wire::get_policies(&state, &wire::GetCooperationPoliciesRequest {});
        prop_assert!(response.status.success);
        let listed: Vec<PolicySetting> = response
            .policies
            .iter()
            .map(|p| PolicySetting::try_from(p).unwrap())
            .collect();
        prop_assert_eq!(listed, state.policies().collect::<Vec<_>>());
    }
}

// -------------------------------------------------------------------------------------------
// JSON calls: no bytes make them panic, and a refusal changes nothing
// -------------------------------------------------------------------------------------------

/// Answers `request` to `service`, checking that the answer is the service's response message
/// and that a refusal left the state as it was.
fn call(state: &mut State, service: Service, request: &[u8]) -> Result<(), TestCaseError> {
    let before = state.clone();
    let response = service.call_json(state, request);
    let status = match service {
        Service::SetCommands => {
            wire::from_json::<wire::SetCooperationCommandsResponse>(&response).map(|r| r.status)
        }
        Service::SetPolicies => {
            wire::from_json::<wire::SetCooperationPoliciesResponse>(&response).map(|r| r.status)
        }
        Service::GetPolicies => {
            wire::from_json::<wire::GetCooperationPoliciesResponse>(&response).map(|r| r.status)
        }
    };
    let status: Result<wire::ResponseStatus, Malformed> = status;
    let status = status.map_err(|e| TestCaseError::fail(format!("response unreadable: {e}")))?;
    if status.success {
        prop_assert!(status.code == 0 || status.code == wire::ResponseStatus::NO_EFFECT);
    } else {
        prop_assert_eq!(status.code, wire::ResponseStatus::PARAMETER_ERROR);
        prop_assert!(!status.message.is_empty());
        prop_assert_eq!(&*state, &before);
    }
    Ok(())
}

/// A JSON request, then perhaps damaged: cut short, a byte changed, or a byte inserted.
fn damaged(json: Vec<u8>) -> impl Strategy<Value = Vec<u8>> {
    let len = json.len();
    (0..4u8, 0..=len, any::<u8>()).prop_map(move |(how, at, byte)| {
        let mut bytes = json.clone();
        match how {
            0 => {}
            1 => bytes.truncate(at),
            2 => {
                if let Some(b) = bytes.get_mut(at) {
                    *b = byte;
                }
            }
            _ => bytes.insert(at, byte),
        }
        bytes
    })
}

proptest! {
    #[test]
    fn no_bytes_make_a_call_panic(
        mut state in a_state(),
        service in select(Service::ALL.to_vec()),
        bytes in prop::collection::vec(any::<u8>(), 0..64),
    ) {
        call(&mut state, service, &bytes)?;
    }

    #[test]
    fn damaged_requests_are_answered_and_refusals_change_nothing(
        mut state in a_state(),
        (service, bytes) in prop_oneof![
            fixture_commands()
                .prop_flat_map(|r| damaged(wire::to_json(&r)))
                .prop_map(|b| (Service::SetCommands, b)),
            policies_request()
                .prop_flat_map(|r| damaged(wire::to_json(&r)))
                .prop_map(|b| (Service::SetPolicies, b)),
            damaged(b"{}".to_vec()).prop_map(|b| (Service::GetPolicies, b)),
        ],
    ) {
        call(&mut state, service, &bytes)?;
    }
}
