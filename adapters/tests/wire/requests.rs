//! The checked-in requests through the service handlers, and the factor streams.

use super::*;

// -------------------------------------------------------------------------------------------
// The checked-in requests
// -------------------------------------------------------------------------------------------

#[test]
fn set_commands_request_written_from_the_definitions_round_trips_through_the_handler() {
    let mut state = with_scenes();
    let request = data("set_commands_request.json");

    let response = Service::SetCommands.call_json(&mut state, request.as_bytes());

    assert_eq!(
        json(&response),
        json(data("set_commands_response.json").as_bytes())
    );
    let a = state.scene(A).unwrap();
    let b = state.scene(B).unwrap();
    assert_eq!(a.operator_decision(), OperatorDecision::Activate);
    assert_eq!(b.operator_decision(), OperatorDecision::Autonomous);
    // A: the operator overrides the module's deactivate; B: follows the module's activate.
    assert_eq!(state.merged_decision(A), Some(Decision::Activate));
    assert_eq!(state.merged_decision(B), Some(Decision::Activate));
}

#[test]
fn set_commands_request_decodes_to_the_typed_request() {
    let request: wire::SetCooperationCommandsRequest =
        wire::from_json(data("set_commands_request.json").as_bytes()).unwrap();
    assert_eq!(
        request.to_commands().unwrap(),
        [
            Command {
                id: A,
                decision: OperatorDecision::Activate
            },
            Command {
                id: B,
                decision: OperatorDecision::Autonomous
            },
        ]
    );
    // And the typed handler answers as the JSON one does.
    let mut state = with_scenes();
    let response = wire::set_commands(&mut state, &request).response;
    assert_eq!(
        response.status,
        wire::ResponseStatus {
            success: true,
            code: 0,
            message: String::new()
        }
    );
}

#[test]
fn base64_uuids_as_rosbridge_writes_them_are_the_same_request() {
    let lists: wire::SetCooperationCommandsRequest =
        wire::from_json(data("set_commands_request.json").as_bytes()).unwrap();
    let base64: wire::SetCooperationCommandsRequest =
        wire::from_json(data("set_commands_request_base64.json").as_bytes()).unwrap();
    assert_eq!(base64, lists);
    for command in &lists.commands {
        let text = format!(r#"{{"uuid": "{}"}}"#, command.uuid.to_base64());
        assert_eq!(
            wire::from_json::<wire::Uuid>(text.as_bytes()).unwrap(),
            command.uuid
        );
    }

    let mut state = with_scenes();
    let response = Service::SetCommands.call_json(
        &mut state,
        data("set_commands_request_base64.json").as_bytes(),
    );
    assert_eq!(
        json(&response),
        json(data("set_commands_response.json").as_bytes())
    );
    assert_eq!(
        state.scene(A).unwrap().operator_decision(),
        OperatorDecision::Activate
    );
    // Unpadded base64 is read too.
    let unpadded = br#"{"uuid": "PyqcEFt+TSGaDB4vOktcbQ"}"#;
    assert_eq!(
        SceneId::from(wire::from_json::<wire::Uuid>(unpadded).unwrap()),
        A
    );
    // Written back, a UUID is a list of numbers.
    assert_eq!(
        wire::to_json(&wire::Uuid::from(A)),
        br#"{"uuid":[63,42,156,16,91,126,77,33,154,12,30,47,58,75,92,109]}"#
    );
}

#[test]
fn set_and_get_policies_requests_round_trip_through_the_handlers() {
    let mut state = with_scenes();
    let response =
        Service::SetPolicies.call_json(&mut state, data("set_policies_request.json").as_bytes());
    assert_eq!(
        json(&response),
        json(data("set_policies_response.json").as_bytes())
    );
    assert_eq!(state.policy(LANE_CHANGE), Some(Policy::Required));
    assert_eq!(state.policy(AVOIDANCE), Some(Policy::Optional));
    // A has no operator decision: now required, it waits; B follows its module.
    assert_eq!(state.merged_decision(A), Some(Decision::Deactivate));
    assert_eq!(state.merged_decision(B), Some(Decision::Activate));

    let response = Service::GetPolicies.call_json(&mut state, b"{}");
    assert_eq!(
        json(&response),
        json(data("get_policies_response.json").as_bytes())
    );
    let typed = wire::get_policies(&state, &wire::GetCooperationPoliciesRequest {});
    assert_eq!(json(&wire::to_json(&typed)), json(&response));
}

#[test]
fn an_empty_batch_succeeds_with_the_no_effect_warning() {
    let mut state = with_scenes();
    let before = state.clone();
    for (service, request) in [
        (Service::SetCommands, &br#"{"commands": []}"#[..]),
        (Service::SetPolicies, br#"{"policies": []}"#),
        // rosbridge leaves out what the caller leaves out: a missing list is empty.
        (Service::SetCommands, b"{}"),
    ] {
        let response = json(&service.call_json(&mut state, request));
        assert_eq!(response["status"]["success"], true);
        assert_eq!(
            response["status"]["code"],
            u64::from(wire::ResponseStatus::NO_EFFECT)
        );
        assert_eq!(response["status"]["message"], "the batch is empty");
    }
    assert_eq!(state, before);
}

#[test]
fn a_request_may_list_its_fields_in_order_as_rosbridge_args_may() {
    let mut state = with_scenes();
    let positional = format!("[[[{{\"uuid\": {}}}, [2]]]]", list(A));
    let response = Service::SetCommands.call_json(&mut state, positional.as_bytes());
    assert_eq!(
        json(&response),
        json(data("set_commands_response.json").as_bytes())
    );
    assert_eq!(state.merged_decision(A), Some(Decision::Activate));
    // More values than fields is refused, and changes nothing.
    let before = state.clone();
    let fault = command_fault("[[], 5]");
    assert!(matches!(fault, Malformed::Shape { .. }), "{fault:?}");
    assert_eq!(
        fault.to_string(),
        "a list with more values than its field takes: trailing characters at line 1 column 6"
    );
    refused(&mut state, Service::SetCommands, "[[], 5]", &fault);
    assert_eq!(state, before);
    // So is a fixed-size array with too many values.
    let text = br#"{"factors": [{"distance": [1, 2, 3]}]}"#;
    let fault = wire::from_json::<wire::SteeringFactorArray>(text).expect_err("three distances");
    assert!(matches!(fault, Malformed::Shape { .. }), "{fault:?}");
    assert_eq!(fault.path().to_string(), "factors[0].distance");
    let text = br#"{"factors": [{"distance": [1]}]}"#;
    let fault = wire::from_json::<wire::SteeringFactorArray>(text).expect_err("one distance");
    assert_eq!(
        fault.to_string(),
        "factors[0].distance: invalid length 1, expected an array of length 2 at line 1 column 29"
    );
}

#[test]
fn services_by_name() {
    for service in Service::ALL {
        assert_eq!(Service::from_name(service.name()), Some(service));
        assert!(service.name().starts_with("/api/planning/cooperation/"));
        assert!(service
            .type_name()
            .starts_with("autoware_adapi_v1_msgs/srv/"));
    }
    assert_eq!(
        Service::from_name("/api/planning/cooperation/set_command"),
        None
    );
}

// -------------------------------------------------------------------------------------------
// The factor streams
// -------------------------------------------------------------------------------------------

#[test]
fn factor_streams_carry_the_cores_factors_in_the_map_frame() {
    let mut state = with_scenes();
    let far = SceneId::from_u128(7);
    register(
        &mut state,
        far,
        LANE_CHANGE,
        Decision::Activate,
        Geometry::velocity(80.0),
    );
    let near = SceneId::from_u128(8);
    let mut geometry = Geometry::velocity(5.0);
    if let Geometry::Velocity { pose, status, .. } = &mut geometry {
        pose.position = [1.5, -2.0, 0.25];
        pose.orientation = [0.0, 0.0, 0.6, 0.8];
        *status = VelocityStatus::Stopped;
    }
    register(
        &mut state,
        near,
        LANE_CHANGE,
        Decision::Deactivate,
        geometry,
    );
    update(&mut state, near, Phase::Running);
    update(&mut state, near, Phase::Aborting);
    let stamp = Time {
        sec: 1_700_000_000,
        nanosec: 250_000_000,
    };

    let velocity = wire::velocity_factors(&state, stamp);
    assert_eq!(velocity.header.stamp, stamp);
    assert_eq!(velocity.header.frame_id, "map");
    let order: Vec<SceneId> = velocity
        .factors
        .iter()
        .map(|f| SceneId::from(f.cooperation[0].uuid))
        .collect();
    assert_eq!(order, [near, A, far], "nearest first");
    let first = &velocity.factors[0];
    assert_eq!(first.distance, 5.0);
    assert_eq!(first.status, wire::VelocityFactor::STOPPED);
    assert_eq!(
        first.pose.position,
        wire::Point {
            x: 1.5,
            y: -2.0,
            z: 0.25
        }
    );
    assert_eq!(first.pose.orientation.w, 0.8);
    // A pose nobody set is published with the identity orientation, as rosbridge reads a
    // missing one.
    let unset = &velocity.factors[2].pose;
    assert_eq!(unset.orientation, wire::Quaternion::default());
    assert_eq!(unset.orientation.w, 1.0);
    assert_eq!(first.behavior, wire::PlanningBehavior::LANE_CHANGE);
    assert_eq!(first.sequence, "");
    assert_eq!(first.detail, "");
    assert_eq!(
        first.cooperation,
        [wire::CooperationStatus {
            uuid: near.into(),
            autonomous: wire::CooperationDecision {
                decision: wire::CooperationDecision::DEACTIVATE
            },
            cooperator: wire::CooperationDecision {
                decision: wire::CooperationDecision::UNDECIDED
            },
            cancellable: false,
        }]
    );
    // The stream is the core's list, converted: back to core types it is that list.
    let mut core = Vec::new();
    state.velocity_factors_into(&mut core);
    assert_eq!(velocity.to_factors(), Ok(core));

    let steering = wire::steering_factors(&state, stamp);
    assert_eq!(steering.header.frame_id, "map");
    let [b] = &steering.factors[..] else {
        panic!("one steering scene: {steering:?}")
    };
    assert_eq!(b.distance, [12.0, 40.0]);
    assert_eq!(b.direction, wire::SteeringFactor::RIGHT);
    assert_eq!(b.status, wire::SteeringFactor::APPROACHING);
    assert_eq!(b.behavior, wire::PlanningBehavior::AVOIDANCE);
    assert_eq!(b.sequence, wire::PlanningSequence::CHANGE);
    assert_eq!(
        b.cooperation[0].autonomous.decision,
        wire::CooperationDecision::ACTIVATE
    );
    assert!(b.cooperation[0].cancellable);
    let mut core = Vec::new();
    state.steering_factors_into(&mut core);
    assert_eq!(steering.to_factors(), Ok(core));
}

#[test]
fn factor_stream_json_is_shaped_as_the_messages() {
    let mut state = with_scenes();
    Service::SetCommands.call_json(&mut state, data("set_commands_request.json").as_bytes());
    let stamp = Time {
        sec: 42,
        nanosec: 7,
    };
    assert_eq!(
        json(&wire::to_json(&wire::velocity_factors(&state, stamp))),
        json(data("velocity_factors.json").as_bytes())
    );
    assert_eq!(
        json(&wire::to_json(&wire::steering_factors(&state, stamp))),
        json(data("steering_factors.json").as_bytes())
    );
    // And what is written reads back as the same message.
    let text = data("steering_factors.json");
    let read: wire::SteeringFactorArray = wire::from_json(text.as_bytes()).unwrap();
    assert_eq!(read, wire::steering_factors(&state, stamp));
}

#[test]
fn an_empty_state_streams_empty_arrays() {
    let state = state();
    let stamp = Time::default();
    assert!(wire::velocity_factors(&state, stamp).factors.is_empty());
    assert!(wire::steering_factors(&state, stamp).factors.is_empty());
}
