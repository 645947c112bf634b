//! The batch rules are the core's; factor messages into the core; the input pays for what it
//! asks.

use super::*;

// -------------------------------------------------------------------------------------------
// Batch rules are the core's: the handler answers with its rejection
// -------------------------------------------------------------------------------------------
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
    let stamp = Time::default();
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
    // An empty list is a factor of a module that does not cooperate, not a fault.
    let mut other = velocity.clone();
    other.factors[0].cooperation.clear();
    let read = other
        .to_factors()
        .expect("a factor without cooperation reads");
    assert_eq!(read[0].cooperation, None);
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
    let mut bad = velocity;
    bad.factors[0].behavior = "user_extension".into();
    check(
        bad.to_factors(),
        "factors[0].behavior: \"user_extension\" is no PlanningBehavior value or extension \
         name: byte 4 is not a lower-case ASCII letter, digit or '-'",
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
    let velocity = wire::velocity_factors(&state, Time::default());
    assert!(velocity.factors[0].distance.is_nan());
    let mut core = Vec::new();
    state.velocity_factors_into(&mut core);
    assert_eq!(velocity.to_factors(), Ok(core));
    let steering = wire::steering_factors(&state, Time::default());
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
                .contains("invalid type: map, expected 16 bytes"),
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
        Malformed::InvalidBehavior {
            path: fault.path().clone(),
            given: behavior.clone(),
            problem: NameProblem::TooLong { len: 1 << 19 },
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
    let fault = command_fault(&request);
    assert!(matches!(fault, Malformed::Shape { .. }), "{fault:?}");
    assert!(fault
        .to_string()
        .starts_with("commands[0].uuid.uuid: a UUID has 16 bytes, not 786432"));
}
