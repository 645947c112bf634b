//! Malformed requests: each class, its typed error, and no change.

use super::*;

// -------------------------------------------------------------------------------------------
// Malformed requests: each class, its typed error, and no change
// -------------------------------------------------------------------------------------------

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
            {{"uuid": {{"uuid": {b}}}, "cooperator": {{"decision": 0}}}}
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
        assert!(matches!(fault, Malformed::Shape { .. }), "{fault:?}");
        assert_eq!(fault.path().to_string(), "commands[0].uuid.uuid");
        let message = fault.to_string();
        assert!(
            message.starts_with(&format!(
                "commands[0].uuid.uuid: a UUID has 16 bytes, not {len} at line 1 column "
            )),
            "{message}"
        );
        refused(&mut state, Service::SetCommands, &request, &fault);
    }
    // A command without a UUID: rosbridge fills a missing `uint8[16]` with zeros, so it names
    // the nil UUID, which no scene here has; the core refuses it as unknown.
    let missing = r#"{"commands": [{"cooperator": {"decision": 1}}]}"#;
    let commands = wire::from_json::<wire::SetCooperationCommandsRequest>(missing.as_bytes())
        .expect("reads")
        .to_commands()
        .expect("converts");
    assert_eq!(commands[0].id, SceneId::from_bytes([0; 16]));
    let before = state.clone();
    let response = json(&Service::SetCommands.call_json(&mut state, missing.as_bytes()));
    assert_eq!(state, before);
    assert_eq!(response["status"]["success"], false);
    assert_eq!(
        response["status"]["code"],
        u64::from(wire::ResponseStatus::PARAMETER_ERROR)
    );
    assert!(
        response["status"]["message"]
            .as_str()
            .is_some_and(|message| message.ends_with("unknown scene")),
        "{response}"
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

#[test]
fn invalid_behaviors_sequences_and_policies_are_refused_naming_the_field() {
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
            Malformed::InvalidBehavior {
                path: policies_1("behavior"),
                given: "lane_change".into(),
                problem: NameProblem::Character { at: 4 },
            },
        ),
        (
            setting("", "", "1"),
            Malformed::InvalidBehavior {
                path: policies_1("behavior"),
                given: String::new(),
                problem: NameProblem::Empty,
            },
        ),
        (
            setting(&"x".repeat(25), "", "1"),
            Malformed::InvalidBehavior {
                path: policies_1("behavior"),
                given: "x".repeat(25),
                problem: NameProblem::TooLong { len: 25 },
            },
        ),
        (
            setting("avoidance", "Back", "1"),
            Malformed::InvalidSequence {
                path: policies_1("sequence"),
                given: "Back".into(),
                problem: NameProblem::Character { at: 0 },
            },
        ),
        (
            setting("avoidance", "CHANGE", "1"),
            Malformed::InvalidSequence {
                path: policies_1("sequence"),
                given: "CHANGE".into(),
                problem: NameProblem::Character { at: 0 },
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
        "policies[1].behavior: \"lane_change\" is no PlanningBehavior value or extension name: \
         byte 4 is not a lower-case ASCII letter, digit or '-'"
    );
    assert_eq!(
        policy_fault(&setting("avoidance", "Back", "1")).to_string(),
        "policies[1].sequence: \"Back\" is no PlanningSequence value or extension name: it does \
         not start with a lower-case ASCII letter"
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
