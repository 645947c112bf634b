//! The AD API on the wire: hand-written JSON requests through the service handlers, the factor
//! streams, and every class of malformed input with its typed error.

mod wire_fixtures;

use cooperation::wire::{self, FieldPath, Malformed, PathSegment, Service};
use cooperation::*;
use wire_fixtures::*;

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
    let response = wire::set_commands(&mut state, &request);
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
        SceneId::try_from(&wire::from_json::<wire::Uuid>(unpadded).unwrap()),
        Ok(A)
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
    let stamp = wire::Time {
        sec: 1_700_000_000,
        nanosec: 250_000_000,
    };

    let velocity = wire::velocity_factors(&state, stamp);
    assert_eq!(velocity.header.stamp, stamp);
    assert_eq!(velocity.header.frame_id, "map");
    let order: Vec<SceneId> = velocity
        .factors
        .iter()
        .map(|f| SceneId::try_from(&f.cooperation[0].uuid).unwrap())
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
    let stamp = wire::Time {
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
    let stamp = wire::Time::default();
    assert!(wire::velocity_factors(&state, stamp).factors.is_empty());
    assert!(wire::steering_factors(&state, stamp).factors.is_empty());
}

// -------------------------------------------------------------------------------------------
// Malformed requests: each class, its typed error, and no change
// -------------------------------------------------------------------------------------------

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

#[test]
fn undefined_and_unknown_decisions_are_refused_naming_the_field() {
    let mut state = with_scenes();
    let a = list(A);
    for (value, expected) in [
        (
            "7",
            "commands[0].cooperator.decision: 7 is not a CooperationDecision constant",
        ),
        (
            "255",
            "commands[0].cooperator.decision: 255 is not a CooperationDecision constant",
        ),
        (
            "0",
            "commands[0].cooperator.decision: CooperationDecision.UNKNOWN (0) is not accepted \
             here; expected DEACTIVATE, ACTIVATE, AUTONOMOUS or UNDECIDED",
        ),
    ] {
        let request = command(&a, value);
        let fault = command_fault(&request);
        assert_eq!(fault.to_string(), expected);
        assert_eq!(fault.path().to_string(), "commands[0].cooperator.decision");
        assert_eq!(
            fault.path().segments(),
            [
                PathSegment::Field("commands".into()),
                PathSegment::Index(0),
                PathSegment::Field("cooperator".into()),
                PathSegment::Field("decision".into()),
            ]
        );
        refused(&mut state, Service::SetCommands, &request, &fault);
    }
    assert!(matches!(
        command_fault(&command(&a, "7")),
        Malformed::UndefinedConstant {
            constants: "CooperationDecision",
            value: 7,
            ..
        }
    ));
    assert!(matches!(
        command_fault(&command(&a, "0")),
        Malformed::UnacceptedConstant {
            constant: "CooperationDecision.UNKNOWN",
            value: 0,
            ..
        }
    ));
    // A missing decision is rosbridge's default, 0: UNKNOWN.
    let missing = format!(r#"{{"commands": [{{"uuid": {{"uuid": {a}}}}}]}}"#);
    assert!(matches!(
        command_fault(&missing),
        Malformed::UnacceptedConstant { value: 0, .. }
    ));
    refused(
        &mut state,
        Service::SetCommands,
        &missing,
        &command_fault(&missing),
    );
}

#[test]
fn the_first_fault_in_batch_order_is_named() {
    let mut state = with_scenes();
    let request = format!(
        r#"{{"commands": [
            {{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 2}}}},
            {{"uuid": {{"uuid": {b}}}, "cooperator": {{"decision": 1}}}},
            {{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 9}}}},
            {{"uuid": {{"uuid": [1, 2]}}, "cooperator": {{"decision": 1}}}}
        ]}}"#,
        a = list(A),
        b = list(B)
    );
    let fault = command_fault(&request);
    assert_eq!(
        fault.to_string(),
        "commands[2].cooperator.decision: 9 is not a CooperationDecision constant"
    );
    refused(&mut state, Service::SetCommands, &request, &fault);
}

#[test]
fn uuids_of_the_wrong_length_are_refused() {
    let mut state = with_scenes();
    let a = A.to_bytes();
    let short = format!("{:?}", &a[..15]);
    let long = format!("{:?}", [&a[..], &[0]].concat());
    for (uuid, len) in [
        (short.as_str(), 15),
        (long.as_str(), 17),
        ("[]", 0),
        // Base64 of 12 bytes: valid base64, not a UUID.
        (r#""AAECAwQFBgcICQoL""#, 12),
        (r#""""#, 0),
    ] {
        let request = command(uuid, "1");
        let fault = command_fault(&request);
        assert_eq!(
            fault,
            Malformed::UuidLength {
                path: fault.path().clone(),
                len
            }
        );
        assert_eq!(
            fault.to_string(),
            format!("commands[0].uuid.uuid: a UUID has 16 bytes, not {len}")
        );
        refused(&mut state, Service::SetCommands, &request, &fault);
    }
    // A command without a UUID: rosbridge's default is the empty array.
    let missing = r#"{"commands": [{"cooperator": {"decision": 1}}]}"#;
    assert!(matches!(
        command_fault(missing),
        Malformed::UuidLength { len: 0, .. }
    ));
    refused(
        &mut state,
        Service::SetCommands,
        missing,
        &command_fault(missing),
    );
}

#[test]
fn uuid_strings_that_are_not_base64_are_refused() {
    let mut state = with_scenes();
    for (uuid, says) in [
        (r#""PyqcEFt+TSGaDB4vOktcbQ!=""#, "'!' at offset 22"),
        // The hyphenated text form is not what rosbridge sends for a uint8[16].
        (
            r#""3f2a9c10-5b7e-4d21-9a0c-1e2f3a4b5c6d""#,
            "'-' at offset 8",
        ),
        // URL-safe base64 is another alphabet.
        (r#""PyqcEFt-TSGaDB4vOktcbQ==""#, "'-' at offset 7"),
        (r#""PyqcEFt+TSGaDB4vOktcbQ=""#, "no base64 text is 23 long"),
    ] {
        let request = command(uuid, "1");
        let fault = command_fault(&request);
        assert!(matches!(fault, Malformed::Shape { .. }), "{fault:?}");
        assert_eq!(fault.path().to_string(), "commands[0].uuid.uuid");
        let message = fault.to_string();
        assert!(
            message.starts_with("commands[0].uuid.uuid: not base64: ") && message.contains(says),
            "{message}"
        );
        refused(&mut state, Service::SetCommands, &request, &fault);
    }
}

#[test]
fn json_of_another_shape_is_refused_naming_the_field() {
    let mut state = with_scenes();
    let a = list(A);
    for (request, at, says) in [
        // A decision as a string, a float, negative, beyond uint8.
        (
            command(&a, r#""2""#),
            "commands[0].cooperator.decision",
            "invalid type: string",
        ),
        (
            command(&a, "2.0"),
            "commands[0].cooperator.decision",
            "invalid type: floating point",
        ),
        (
            command(&a, "-1"),
            "commands[0].cooperator.decision",
            "invalid value: integer `-1`",
        ),
        (
            command(&a, "256"),
            "commands[0].cooperator.decision",
            "invalid value: integer `256`",
        ),
        // A UUID byte beyond uint8, and a UUID of the wrong type.
        (
            command("[1, 2, 300]", "1"),
            "commands[0].uuid.uuid[2]",
            "invalid value: integer `300`",
        ),
        (
            command("7", "1"),
            "commands[0].uuid.uuid",
            "invalid type: integer `7`",
        ),
        (
            command("null", "1"),
            "commands[0].uuid.uuid",
            "invalid type: null",
        ),
        // A field the message does not have, a field twice.
        (
            format!(
                r#"{{"commands": [{{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 1}}, "operator": 1}}]}}"#
            ),
            "commands[0].operator",
            "unknown field `operator`, expected `uuid` or `cooperator`",
        ),
        (
            format!(
                r#"{{"commands": [{{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 1}}, "cooperator": {{"decision": 2}}}}]}}"#
            ),
            "commands[0]",
            "duplicate field `cooperator`",
        ),
        (
            r#"{"command": []}"#.to_owned(),
            "command",
            "unknown field `command`",
        ),
        // Not an object, not a list.
        ("null".to_owned(), "", "invalid type: null"),
        (
            r#"{"commands": {}}"#.to_owned(),
            "commands",
            "invalid type: map",
        ),
    ] {
        let fault = command_fault(&request);
        assert!(
            matches!(fault, Malformed::Shape { .. }),
            "{request}: {fault:?}"
        );
        assert_eq!(fault.path().to_string(), at, "{request}: {fault}");
        let message = fault.to_string();
        let prefix = if at.is_empty() {
            String::new()
        } else {
            format!("{at}: ")
        };
        assert!(
            message.starts_with(&format!("{prefix}{says}")) && message.contains(" at line "),
            "{request}: {message}"
        );
        refused(&mut state, Service::SetCommands, &request, &fault);
    }
}

#[test]
fn text_that_is_not_json_is_refused() {
    let mut state = with_scenes();
    for (request, says) in [
        ("", "EOF while parsing a value at line 1 column 0"),
        (r#"{"commands": ["#, "EOF while parsing"),
        (
            r#"{"commands": []} {}"#,
            "trailing characters at line 1 column 18",
        ),
        (r#"{"commands": [}"#, "expected value"),
        ("{'commands': []}", "key must be a string"),
        ("\u{feff}{}", "expected value"),
    ] {
        let fault = command_fault(request);
        assert!(
            matches!(fault, Malformed::NotJson { .. }),
            "{request}: {fault:?}"
        );
        let message = fault.to_string();
        assert!(
            message.contains("not JSON: ") && message.contains(says),
            "{request}: {message}"
        );
        refused(&mut state, Service::SetCommands, request, &fault);
    }
    // Invalid UTF-8 in a string.
    let mut bytes = br#"{"policies": [{"behavior": ""#.to_vec();
    bytes.extend([0xff, 0xfe]);
    bytes.extend(br#""}]}"#);
    let before = state.clone();
    let response = json(&Service::SetPolicies.call_json(&mut state, &bytes));
    assert_eq!(response["status"]["code"], 50_004);
    assert!(response["status"]["message"]
        .as_str()
        .unwrap()
        .contains("not JSON"));
    assert_eq!(state, before);
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

#[test]
fn unknown_behaviors_sequences_and_policies_are_refused_naming_the_field() {
    let mut state = with_scenes();
    let setting = |behavior: &str, sequence: &str, policy: &str| {
        format!(
            r#"{{"policies": [{{"behavior": "lane-change", "sequence": "", "policy": 1}},
                {{"behavior": {behavior:?}, "sequence": {sequence:?}, "policy": {policy}}}]}}"#
        )
    };
    for (request, expected) in [
        (
            setting("lane_change", "", "1"),
            Malformed::UnknownBehavior {
                path: policies_1("behavior"),
                given: "lane_change".into(),
            },
        ),
        (
            setting("", "", "1"),
            Malformed::UnknownBehavior {
                path: policies_1("behavior"),
                given: String::new(),
            },
        ),
        (
            // Listed by the design page once, no longer a PlanningBehavior value.
            setting("emergency-operation", "", "1"),
            Malformed::UnknownBehavior {
                path: policies_1("behavior"),
                given: "emergency-operation".into(),
            },
        ),
        (
            setting("avoidance", "back", "1"),
            Malformed::UnknownSequence {
                path: policies_1("sequence"),
                given: "back".into(),
            },
        ),
        (
            setting("avoidance", "CHANGE", "1"),
            Malformed::UnknownSequence {
                path: policies_1("sequence"),
                given: "CHANGE".into(),
            },
        ),
        (
            setting("avoidance", "change", "0"),
            Malformed::UndefinedConstant {
                path: policies_1("policy"),
                constants: "CooperationPolicy",
                value: 0,
            },
        ),
        (
            setting("avoidance", "change", "3"),
            Malformed::UndefinedConstant {
                path: policies_1("policy"),
                constants: "CooperationPolicy",
                value: 3,
            },
        ),
    ] {
        let fault = policy_fault(&request);
        assert_eq!(fault, expected);
        refused(&mut state, Service::SetPolicies, &request, &fault);
    }
    assert_eq!(
        policy_fault(&setting("lane_change", "", "1")).to_string(),
        r#"policies[1].behavior: "lane_change" is not a PlanningBehavior value"#
    );
    assert_eq!(
        policy_fault(&setting("avoidance", "back", "1")).to_string(),
        r#"policies[1].sequence: "back" is not a PlanningSequence value or the empty string"#
    );
    assert_eq!(
        policy_fault(&setting("avoidance", "change", "0")).to_string(),
        "policies[1].policy: 0 is not a CooperationPolicy constant"
    );
    // A missing policy is 0.
    let missing = r#"{"policies": [{"behavior": "lane-change"}]}"#;
    assert!(matches!(
        policy_fault(missing),
        Malformed::UndefinedConstant { value: 0, .. }
    ));
}

#[test]
fn get_policies_takes_an_empty_request_only() {
    let mut state = with_scenes();
    let fault = wire::from_json::<wire::GetCooperationPoliciesRequest>(br#"{"all": true}"#)
        .expect_err("no fields");
    assert!(matches!(fault, Malformed::Shape { .. }));
    assert!(fault
        .to_string()
        .starts_with("all: unknown field `all`, there are no fields"));
    refused(&mut state, Service::GetPolicies, r#"{"all": true}"#, &fault);
    let fault = wire::from_json::<wire::GetCooperationPoliciesRequest>(b"").expect_err("empty");
    refused(&mut state, Service::GetPolicies, "", &fault);
}

// -------------------------------------------------------------------------------------------
// Batch rules are the core's: the handler answers with its rejection
// -------------------------------------------------------------------------------------------

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

#[test]
fn duplicate_ids_in_a_batch_are_the_cores_rejection() {
    let mut state = with_scenes();
    let request = format!(
        r#"{{"commands": [
            {{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 2}}}},
            {{"uuid": {{"uuid": "{a64}"}}, "cooperator": {{"decision": 2}}}}
        ]}}"#,
        a = list(A),
        a64 = wire::Uuid::from(A).to_base64()
    );
    core_rejects(
        &mut state,
        Service::SetCommands,
        &request,
        Rule::CommandDuplicate,
    );
    let message = json(&Service::SetCommands.call_json(&mut state, request.as_bytes()));
    assert_eq!(
        message["status"]["message"],
        format!(
            "no command applied: command 1 (scene {A}): invalid: the batch names this scene twice"
        )
    );
}

#[test]
fn duplicate_modules_in_a_batch_are_the_cores_rejection() {
    let mut state = with_scenes();
    let request = r#"{"policies": [
        {"behavior": "lane-change", "sequence": "", "policy": 2},
        {"behavior": "avoidance", "sequence": "change", "policy": 2},
        {"behavior": "lane-change", "sequence": "", "policy": 1}
    ]}"#;
    core_rejects(
        &mut state,
        Service::SetPolicies,
        request,
        Rule::PolicyDuplicate,
    );
}

#[test]
fn the_cores_other_batch_rules_come_back_as_parameter_errors() {
    let mut state = with_scenes();
    let unknown = SceneId::from_u128(0xdead);
    core_rejects(
        &mut state,
        Service::SetCommands,
        &command(&list(unknown), "1"),
        Rule::CommandUnknown,
    );
    // A retired scene, a scene that is no longer cancellable.
    update(&mut state, A, Phase::Running);
    update(&mut state, A, Phase::Aborting);
    core_rejects(
        &mut state,
        Service::SetCommands,
        &command(&list(A), "1"),
        Rule::CommandNotCancellable,
    );
    update(&mut state, A, Phase::Failed);
    core_rejects(
        &mut state,
        Service::SetCommands,
        &command(&list(A), "1"),
        Rule::CommandRetired,
    );
    // A known behaviour whose module has no policy.
    core_rejects(
        &mut state,
        Service::SetPolicies,
        r#"{"policies": [{"behavior": "intersection", "sequence": "", "policy": 1}]}"#,
        Rule::PolicyUnknown,
    );
    core_rejects(
        &mut state,
        Service::SetPolicies,
        r#"{"policies": [{"behavior": "avoidance", "sequence": "return", "policy": 1}]}"#,
        Rule::PolicyUnknown,
    );
    // Over the batch limit.
    let entry = format!(
        r#"{{"uuid": {{"uuid": {}}}, "cooperator": {{"decision": 1}}}}"#,
        list(B)
    );
    let request = format!(
        r#"{{"commands": [{}]}}"#,
        vec![entry; MAX_BATCH + 1].join(",")
    );
    core_rejects(&mut state, Service::SetCommands, &request, Rule::BatchLimit);
}

// -------------------------------------------------------------------------------------------
// Factor messages into the core
// -------------------------------------------------------------------------------------------

#[test]
fn malformed_factors_are_refused_naming_the_field() {
    let state = with_scenes();
    let stamp = wire::Time::default();
    let velocity = wire::velocity_factors(&state, stamp);
    let steering = wire::steering_factors(&state, stamp);
    assert!(velocity.to_factors().is_ok() && steering.to_factors().is_ok());

    let check = |result: Result<Vec<VelocityFactor>, Malformed>, expected: &str| {
        assert_eq!(result.expect_err(expected).to_string(), expected);
    };
    let mut bad = velocity.clone();
    bad.header.frame_id = "base_link".into();
    check(
        bad.to_factors(),
        r#"header.frame_id: "base_link"; factor poses are in the "map" frame"#,
    );
    let mut bad = velocity.clone();
    bad.factors[0].status = 3;
    check(
        bad.to_factors(),
        "factors[0].status: 3 is not a VelocityFactor status constant",
    );
    let mut bad = velocity.clone();
    bad.factors[0].cooperation.clear();
    check(
        bad.to_factors(),
        "factors[0].cooperation: empty; a scene's factor carries the scene's cooperation status",
    );
    let mut bad = velocity.clone();
    let extra = bad.factors[0].cooperation[0].clone();
    bad.factors[0].cooperation.push(extra);
    check(
        bad.to_factors(),
        "factors[0].cooperation: 2 entries; a factor has at most 1",
    );
    let mut bad = velocity.clone();
    bad.factors[0].cooperation[0].autonomous.decision = wire::CooperationDecision::AUTONOMOUS;
    check(
        bad.to_factors(),
        "factors[0].cooperation[0].autonomous.decision: CooperationDecision.AUTONOMOUS (3) is \
         not accepted here; expected DEACTIVATE or ACTIVATE (a module decision)",
    );
    let mut bad = velocity.clone();
    bad.factors[0].cooperation[0].uuid.uuid.pop();
    check(
        bad.to_factors(),
        "factors[0].cooperation[0].uuid.uuid: a UUID has 16 bytes, not 15",
    );
    let mut bad = velocity;
    bad.factors[0].behavior = "user-extension".into();
    check(
        bad.to_factors(),
        r#"factors[0].behavior: "user-extension" is not a PlanningBehavior value"#,
    );

    let check = |result: Result<Vec<SteeringFactor>, Malformed>, expected: &str| {
        assert_eq!(result.expect_err(expected).to_string(), expected);
    };
    let mut bad = steering.clone();
    // 2 was TRYING, a status since removed.
    bad.factors[0].status = 2;
    check(
        bad.to_factors(),
        "factors[0].status: 2 is not a SteeringFactor status constant",
    );
    let mut bad = steering.clone();
    bad.factors[0].direction = 4;
    check(
        bad.to_factors(),
        "factors[0].direction: 4 is not a SteeringFactor direction constant",
    );
    let mut bad = steering;
    bad.factors[0].cooperation[0].cooperator.decision = 5;
    check(
        bad.to_factors(),
        "factors[0].cooperation[0].cooperator.decision: 5 is not a CooperationDecision constant",
    );
}

#[test]
fn factors_keep_non_finite_numbers_the_core_takes_but_json_cannot_carry_them() {
    let mut state = state();
    register(
        &mut state,
        A,
        LANE_CHANGE,
        Decision::Activate,
        Geometry::velocity(f32::NAN),
    );
    register(
        &mut state,
        B,
        AVOIDANCE,
        Decision::Activate,
        Geometry::steering(Direction::Left, f32::NEG_INFINITY, f32::INFINITY),
    );
    let velocity = wire::velocity_factors(&state, wire::Time::default());
    assert!(velocity.factors[0].distance.is_nan());
    let mut core = Vec::new();
    state.velocity_factors_into(&mut core);
    assert_eq!(velocity.to_factors(), Ok(core));
    let steering = wire::steering_factors(&state, wire::Time::default());
    assert_eq!(
        steering.factors[0].distance,
        [f32::NEG_INFINITY, f32::INFINITY]
    );

    // JSON has no NaN or infinity: they are written `null`, which does not read back.
    let text = wire::to_json(&velocity);
    assert_eq!(
        json(&text)["factors"][0]["distance"],
        serde_json::Value::Null
    );
    let fault = wire::from_json::<wire::VelocityFactorArray>(&text).expect_err("null");
    assert_eq!(fault.path().to_string(), "factors[0].distance");
    assert!(
        fault
            .to_string()
            .contains("invalid type: null, expected f32"),
        "{fault}"
    );
}

// -------------------------------------------------------------------------------------------
// Limits: the input pays for what it asks
// -------------------------------------------------------------------------------------------

#[test]
fn a_giant_batch_is_the_cores_batch_limit_and_changes_nothing() {
    let mut state = with_scenes();
    let before = state.clone();
    let entry = format!(
        r#"{{"uuid": {{"uuid": {}}}, "cooperator": {{"decision": 1}}}}"#,
        list(B)
    );
    // As large a batch as a request under the size limit holds.
    let request = format!(r#"{{"commands": [{}]}}"#, vec![entry; 8_000].join(","));
    assert!(request.len() <= wire::MAX_REQUEST_BYTES);
    let response = json(&Service::SetCommands.call_json(&mut state, request.as_bytes()));
    assert_eq!(
        response["status"]["message"],
        format!("the batch has 8000 entries; at most {MAX_BATCH} are accepted")
    );
    assert_eq!(state, before);
}

#[test]
fn deep_nesting_is_refused_where_the_messages_end() {
    // The messages nest a few levels deep and unknown fields are refused rather than skipped,
    // so the reader never descends further than the message does.
    let mut state = with_scenes();
    for depth in [200, 100_000] {
        let request = format!(
            r#"{{"commands": {}{}}}"#,
            "[".repeat(depth),
            "]".repeat(depth)
        );
        let fault = command_fault(&request);
        // The list form: the command's first field, the UUID's first field, its first byte.
        assert_eq!(fault.path().to_string(), "commands[0].uuid.uuid[0]");
        assert!(
            fault
                .to_string()
                .contains("invalid type: sequence, expected u8"),
            "{fault}"
        );
        refused(&mut state, Service::SetCommands, &request, &fault);

        let request = format!(
            r#"{{"commands": [{{"uuid": {}}}]}}"#,
            r#"{"uuid":"#.repeat(depth)
        );
        let fault = command_fault(&request);
        assert_eq!(fault.path().to_string(), "commands[0].uuid.uuid");
        assert!(
            fault
                .to_string()
                .contains("invalid type: map, expected a list"),
            "{fault}"
        );
        refused(&mut state, Service::SetCommands, &request, &fault);
    }
}

#[test]
fn long_strings_are_quoted_short_in_messages() {
    let mut state = with_scenes();
    let behavior = "x".repeat(1 << 19);
    let request = format!(r#"{{"policies": [{{"behavior": "{behavior}", "policy": 1}}]}}"#);
    let fault = policy_fault(&request);
    assert_eq!(
        fault,
        Malformed::UnknownBehavior {
            path: fault.path().clone(),
            given: behavior.clone()
        }
    );
    let message = fault.to_string();
    assert!(message.len() < 200, "{} bytes", message.len());
    assert!(
        message.contains(&format!("… ({} bytes)", 1 << 19)),
        "{message}"
    );
    refused(&mut state, Service::SetPolicies, &request, &fault);

    // The reader's explanations quote the input too; they are shortened in the middle.
    let field = "y".repeat(1 << 19);
    let request = format!(r#"{{"policies": [{{"{field}": 1}}]}}"#);
    let fault = policy_fault(&request);
    assert_eq!(fault.path().segments()[2], PathSegment::Field(field));
    let message = fault.to_string();
    assert!(message.starts_with(&format!("policies[0].{}…: unknown field", "y".repeat(64))));
    assert!(message.len() < 700, "{} bytes", message.len());
    assert!(message.ends_with("line 1 column 524305"), "{message}");
    refused(&mut state, Service::SetPolicies, &request, &fault);

    // A UUID given as a megabyte of base64 is a UUID of the wrong length.
    let request = command(&format!("\"{}\"", "A".repeat(1 << 20)), "1");
    assert!(matches!(
        command_fault(&request),
        Malformed::UuidLength { len: 786_432, .. }
    ));
}
