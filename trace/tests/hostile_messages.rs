//! Hostile records and the messages they get: a key given twice, an unknown field, an array
//! or `null` where an object belongs, and echoed input kept short and printable.

use std::io;

use cooperation_trace::*;

const CONFIG: &str = r#"{"config": {"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}}"#;

const MODULE: &str = r#"{"behavior": "lane-change", "sequence": ""}"#;

const POSE: &str = r#"{"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}"#;

const ID: &str = "00000000-0000-0000-0000-000000000001";

/// The longest error message a record may get: its field path and explanation are cut.
const SHORT: usize = 512;

fn replay_text(text: &str) -> Result<Summary, TraceError> {
    replay(text.as_bytes(), io::sink(), &Options::default(), false)
}

/// The error for a trace of the config line followed by `line`, which is line 2.
fn error_of(line: &str) -> TraceError {
    let text = format!("{CONFIG}\n{line}\n");
    let error = replay_text(&text).expect_err(line);
    assert_eq!(error.line, Some(2), "{line}: {error}");
    assert_eq!(
        validate(text.as_bytes(), &Options::default()).expect_err(line),
        error
    );
    error
}

/// The error for a trace whose first line is the configuration `config`.
fn config_error(config: &str) -> TraceError {
    let text = format!("{{\"config\": {config}}}\n{{\"at_ms\": 0}}\n");
    let error = replay_text(&text).expect_err(config);
    assert_eq!(error.line, Some(1), "{config}: {error}");
    error
}

fn json_field(error: &TraceError) -> &str {
    match &error.kind {
        ErrorKind::Json { field, .. } => field,
        other => panic!("not a JSON error: {other:?}"),
    }
}

fn register(geometry: &str) -> String {
    format!(
        r#"{{"input": {{"Register": {{"id": "{ID}", "module": {MODULE}, "decision": "activate", "geometry": {geometry}}}}}}}"#
    )
}

fn velocity(pose: &str) -> String {
    format!(r#"{{"Velocity": {{"pose": {pose}, "distance": 10.0, "status": "approaching"}}}}"#)
}

fn status(fields: &str) -> String {
    format!(
        r#"{{"observed": [{{"id": "{ID}", "module_decision": "activate", "operator_decision": "none", "cancellable": true{fields}}}]}}"#
    )
}

fn wire_status(uuid: &str, fields: &str) -> String {
    format!(
        r#"{{"observed": [{{"uuid": {uuid}, "autonomous": {{"decision": 2}}, "cooperator": {{"decision": 4}}, "cancellable": true{fields}}}]}}"#
    )
}

const WIRE_UUID: &str = r#"{"uuid": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]}"#;

/// Checks that the error is a JSON error at `field` whose message has `words`.
fn check(error: &TraceError, field: &str, words: &str, what: &str) {
    assert_eq!(json_field(error), field, "{what}: {error}");
    assert!(error.to_string().contains(words), "{what}: {error}");
}

#[test]
fn a_key_given_twice_is_refused_wherever_it_is() {
    let remove = format!(r#"{{"Remove": {{"id": "{ID}", "module": {MODULE}}}}}"#);
    for (line, field) in [
        (r#"{"at_ms": 1, "at_ms": 1}"#.to_owned(), "at_ms"),
        // The same key written with an escape.
        (r#"{"at_ms": 1, "at\u005fms": 2}"#.to_owned(), "at_ms"),
        (
            format!(r#"{{"input": {remove}, "input": {remove}}}"#),
            "input",
        ),
        (
            format!(
                r#"{{"input": {{"Remove": {{"id": "{ID}", "module": {MODULE}}}, "Remove": {{"id": "{ID}", "module": {MODULE}}}}}}}"#
            ),
            "input.Remove",
        ),
        (
            format!(
                r#"{{"input": {{"Remove": {{"id": "{ID}", "id": "{ID}", "module": {MODULE}}}}}}}"#
            ),
            "input.Remove.id",
        ),
        (
            format!(
                r#"{{"input": {{"Remove": {{"id": "{ID}", "module": {{"behavior": "lane-change", "behavior": "merge", "sequence": ""}}}}}}}}"#
            ),
            "input.Remove.module.behavior",
        ),
        (
            register(
                r#"{"Velocity": {"pose": {"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0], "position": [1.0, 0.0, 0.0]}, "distance": 10.0, "status": "approaching"}}"#,
            ),
            "input.Register.geometry.Velocity.pose.position",
        ),
        (
            format!(
                r#"{{"input": {{"SetCommands": {{"commands": [{{"id": "{ID}", "decision": "activate", "decision": "deactivate"}}]}}}}}}"#
            ),
            "input.SetCommands.commands[0].decision",
        ),
        (
            status(r#", "module_decision": "deactivate""#),
            "observed[0].module_decision",
        ),
        (
            status(r#", "cancellable": false"#),
            "observed[0].cancellable",
        ),
        (
            wire_status(WIRE_UUID, r#", "autonomous": {"decision": 1}"#),
            "observed[0].autonomous",
        ),
        (
            wire_status(
                r#"{"uuid": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1], "uuid": "AAAAAAAAAAAAAAAAAAAAAg=="}"#,
                "",
            ),
            "observed[0].uuid.uuid",
        ),
        (
            wire_status(
                WIRE_UUID,
                r#", "cooperator": {"decision": 4, "decision": 2}"#,
            ),
            "observed[0].cooperator",
        ),
    ] {
        check(&error_of(&line), field, "given twice", &line);
    }
    for (config, field) in [
        (r#"{"policies": [], "policies": []}"#, "config.policies"),
        (
            r#"{"policies": [], "limits": {"ttl_ms": 1, "ttl_ms": 2}}"#,
            "config.limits.ttl_ms",
        ),
        (
            r#"{"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional", "policy": "required"}]}"#,
            "config.policies[0].policy",
        ),
    ] {
        check(&config_error(config), field, "given twice", config);
        // A configuration file is read the same way.
        let error = parse_config(config).expect_err(config);
        assert_eq!(json_field(&error), field, "{config}");
    }
}

#[test]
fn unknown_fields_are_refused_in_inputs() {
    let module = MODULE;
    let update = |extra: &str| {
        format!(
            r#"{{"input": {{"Update": {{"id": "{ID}", "module": {module}, "phase": "running", "decision": "activate", "geometry": {}{extra}}}}}}}"#,
            velocity(POSE)
        )
    };
    for (line, field) in [
        (
            format!(
                r#"{{"input": {{"Register": {{"id": "{ID}", "module": {module}, "decision": "activate", "requsted": true, "geometry": {}}}}}}}"#,
                velocity(POSE)
            ),
            "input.Register.requsted",
        ),
        (update(r#", "requsted": true"#), "input.Update.requsted"),
        (
            format!(
                r#"{{"input": {{"Remove": {{"id": "{ID}", "module": {module}, "phase": "running"}}}}}}"#
            ),
            "input.Remove.phase",
        ),
        (
            r#"{"input": {"SetCommands": {"commands": [], "force": true}}}"#.to_owned(),
            "input.SetCommands.force",
        ),
        (
            format!(
                r#"{{"input": {{"SetCommands": {{"commands": [{{"id": "{ID}", "decision": "activate", "why": "x"}}]}}}}}}"#
            ),
            "input.SetCommands.commands[0].why",
        ),
        (
            r#"{"input": {"SetPolicies": {"policies": [], "all": true}}}"#.to_owned(),
            "input.SetPolicies.all",
        ),
        (
            format!(
                r#"{{"input": {{"SetPolicies": {{"policies": [{{"module": {module}, "policy": "required", "until": 5}}]}}}}}}"#
            ),
            "input.SetPolicies.policies[0].until",
        ),
        (
            format!(
                r#"{{"input": {{"Remove": {{"id": "{ID}", "module": {{"behavior": "lane-change", "sequence": "", "name": "x"}}}}}}}}"#
            ),
            "input.Remove.module.name",
        ),
        (
            r#"{"input": {"Tick": {"elapsed_ms": 5, "at": 1}}}"#.to_owned(),
            "input.Tick.at",
        ),
    ] {
        check(&error_of(&line), field, "unknown field", &line);
    }
}

#[test]
fn unknown_fields_are_refused_in_geometry() {
    let steering = |extra: &str| {
        register(&format!(
            r#"{{"Steering": {{"poses": [{POSE}, {POSE}], "distances": [1.0, 2.0], "direction": "left", "status": "turning"{extra}}}}}"#
        ))
    };
    for (line, field) in [
        (
            register(
                r#"{"Velocity": {"pose": {"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}, "distance": 10.0, "status": "approaching", "speed": 3.0}}"#,
            ),
            "input.Register.geometry.Velocity.speed",
        ),
        (
            register(&velocity(
                r#"{"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0], "frame": "map"}"#,
            )),
            "input.Register.geometry.Velocity.pose.frame",
        ),
        (
            steering(r#", "lane": 2"#),
            "input.Register.geometry.Steering.lane",
        ),
    ] {
        check(&error_of(&line), field, "unknown field", &line);
    }
}

#[test]
fn unknown_fields_are_refused_in_the_configuration_and_observations() {
    for (config, field) in [
        (r#"{"policies": [], "limit": {}}"#, "config.limit"),
        (
            r#"{"policies": [], "limits": {"ttl": 5}}"#,
            "config.limits.ttl",
        ),
        (
            r#"{"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional", "default": true}]}"#,
            "config.policies[0].default",
        ),
        (
            r#"{"policies": [{"module": {"behavior": "lane-change", "sequence": "", "x": 1}, "policy": "optional"}]}"#,
            "config.policies[0].module.x",
        ),
    ] {
        check(&config_error(config), field, "unknown field", config);
    }
    for (line, field) in [
        (status(r#", "cancelable": false"#), "observed[0].cancelable"),
        (
            wire_status(WIRE_UUID, r#", "cancelable": false"#),
            "observed[0].cancelable",
        ),
        (
            wire_status(
                r#"{"uuid": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1], "id": 1}"#,
                "",
            ),
            "observed[0].uuid.id",
        ),
        // A field of one form in the other.
        (
            status(r#", "cooperator": {"decision": 4}"#),
            "observed[0].cooperator",
        ),
        (
            wire_status(WIRE_UUID, &format!(r#", "id": "{ID}""#)),
            "observed[0].id",
        ),
    ] {
        let error = error_of(&line);
        assert_eq!(json_field(&error), field, "{line}: {error}");
    }
    // The fields of a replay's JSON scene are taken, so that its scenes can be pasted in.
    let scene = status(
        r#", "module": {"behavior": "lane-change", "sequence": ""}, "phase": "waiting", "policy": null, "merged_decision": "activate", "force_activated": false, "force_deactivated": false"#,
    );
    let observed = parse_record(2, &scene).expect("a replay's scene is a status");
    assert!(matches!(
        observed,
        Record::At {
            event: Event::Observed(_),
            ..
        }
    ));
    // ... but checked.
    let error = error_of(&status(r#", "phase": "Sleeping""#));
    assert_eq!(json_field(&error), "observed[0].phase");
}

#[test]
fn an_array_is_not_an_object() {
    for (line, field) in [
        (
            format!(r#"{{"input": {{"Remove": ["{ID}", {MODULE}]}}}}"#),
            "input.Remove",
        ),
        (
            format!(
                r#"{{"input": {{"Remove": {{"id": "{ID}", "module": ["lane-change", ""]}}}}}}"#
            ),
            "input.Remove.module",
        ),
        (
            register(&format!(r#"{{"Velocity": [{POSE}, 10.0, "approaching"]}}"#)),
            "input.Register.geometry.Velocity",
        ),
        (
            register(&velocity("[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]")),
            "input.Register.geometry.Velocity.pose",
        ),
        (
            format!(r#"{{"input": {{"SetCommands": {{"commands": [["{ID}", "activate"]]}}}}}}"#),
            "input.SetCommands.commands[0]",
        ),
        (
            format!(r#"{{"input": {{"SetCommands": [[["{ID}", "activate"]]]}}}}"#),
            "input.SetCommands",
        ),
        (
            format!(r#"{{"observed": [["{ID}", "activate", "none", true]]}}"#),
            "observed[0]",
        ),
        (
            wire_status(WIRE_UUID, "").replace(r#"{"decision": 2}"#, "[2]"),
            "observed[0].autonomous",
        ),
        (
            wire_status(WIRE_UUID, "").replace(r#"{"decision": 4}"#, "[4]"),
            "observed[0].cooperator",
        ),
        (
            format!(r#"{{"input": {{"SetPolicies": {{"policies": [[{MODULE}, "required"]]}}}}}}"#),
            "input.SetPolicies.policies[0]",
        ),
        (
            wire_status("[[0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1]]", ""),
            "observed[0].uuid",
        ),
    ] {
        check(&error_of(&line), field, "expected an object", &line);
    }
    for (config, field) in [
        (r#"[[]]"#, "config"),
        (r#"{"policies": [], "limits": [1000]}"#, "config.limits"),
        (
            r#"{"policies": [[{"behavior": "lane-change", "sequence": ""}, "optional"]]}"#,
            "config.policies[0]",
        ),
    ] {
        check(&config_error(config), field, "expected an object", config);
    }
}

#[test]
fn null_is_not_a_missing_field() {
    let error = config_error("null");
    check(&error, "config", "null", "config null");
    for (line, field) in [
        (r#"{"at_ms": null}"#, "at_ms"),
        (r#"{"at_ms": 1, "input": null}"#, "input"),
        (r#"{"at_ms": 1, "observed": null}"#, "observed"),
        (
            r#"{"at_ms": 1, "factors": null, "observed": []}"#,
            "factors",
        ),
    ] {
        check(&error_of(line), field, "invalid type: null", line);
    }
    for (config, field) in [
        (r#"{"policies": null}"#, "config.policies"),
        (r#"{"policies": [], "limits": null}"#, "config.limits"),
        (
            r#"{"policies": [], "limits": {"max_scenes": null}}"#,
            "config.limits.max_scenes",
        ),
    ] {
        check(&config_error(config), field, "invalid type: null", config);
    }
}

#[test]
fn echoed_input_is_cut_short() {
    let long = "k".repeat(500_000);
    for line in [
        format!(r#"{{"{long}": 1}}"#),
        format!(r#"{{"at_ms": 1, "input": {{"{long}": {{}}}}}}"#),
        format!(r#"{{"at_ms": "{long}"}}"#),
        format!(r#"{{"at_ms": 1, "factors": "{long}", "observed": []}}"#),
        format!(r#"{{"at_ms": 1, "observed": [{{"id": "{long}"}}]}}"#),
        format!(r#"{{"{long}": 1, "{long}": 2}}"#),
    ] {
        let error = error_of(&line);
        let shown = error.to_string();
        assert!(
            shown.len() < SHORT,
            "{} bytes: {}",
            shown.len(),
            &shown[..SHORT]
        );
        assert!(shown.contains("kkkk"), "{shown}");
        assert!(json_field(&error).len() < 2 * 64 + 16, "{shown}");
        // A key in the path is cut at its end, an explanation in its middle.
        let field = json_field(&error);
        assert!(!field.contains("kk") || field.ends_with("k…"), "{shown}");
        assert!(
            shown.contains(" … ") || shown.contains("k…`: given twice"),
            "{shown}"
        );
    }
    // A configuration file too.
    let error = parse_config(&format!(r#"{{"policies": [], "{long}": 1}}"#)).unwrap_err();
    assert!(error.to_string().len() < SHORT, "{error}");
}

#[test]
fn echoed_input_is_printable() {
    for line in [
        "{\"\\u001b[2J\\u001b[31m\": 1}",
        "{\"at_ms\": 1, \"factors\": \"\\u001b]0;x\\u0007\\u202e\", \"observed\": []}",
        "{\"at_ms\": 1, \"input\": {\"\\r\\nerror: forged\": {}}}",
    ] {
        let shown = error_of(line).to_string();
        assert!(
            !shown
                .chars()
                .any(|c| c.is_control() || ('\u{202a}'..='\u{202e}').contains(&c)),
            "{shown:?}"
        );
    }
}

#[test]
fn field_paths_never_end_in_a_placeholder() {
    for (line, field) in [
        (
            r#"{"at_ms": 1, "input": {"Register": {5: 1}}}"#,
            "input.Register",
        ),
        (
            r#"{"at_ms": 1, "input": {"Remove": {"id""#,
            "input.Remove.id",
        ),
        (r#"{"at_ms": 1, "observed": [{"id": 1 2}]}"#, "observed[0]"),
        (
            r#"{"at_ms": 1, "observed": [{"cancellable": true, x}]}"#,
            "observed[0]",
        ),
        (r#"{"at_ms": 1, "input": {"#, "input"),
        (r#"{"at_ms": 1, "#, ""),
    ] {
        let error = error_of(line);
        assert_eq!(json_field(&error), field, "{line}: {error}");
        assert!(!error.to_string().contains('?'), "{line}: {error}");
    }
}

#[test]
fn parse_status_reads_one_status_in_either_form() {
    let core = format!(
        r#"{{"id": "{ID}", "module_decision": "activate", "operator_decision": "none", "cancellable": true}}"#
    );
    let wire = r#"{"uuid": {"uuid": "AAAAAAAAAAAAAAAAAAAAAQ=="}, "autonomous": {"decision": 2}, "cooperator": {"decision": 4}, "cancellable": true}"#;
    assert_eq!(parse_status(&core), parse_status(wire));
    let status = parse_status(wire).unwrap();
    assert_eq!(status.id, cooperation::SceneId::from_u128(1));
    // The AD API form's fields default as `cooperation_adapters::wire` reads them.
    let short = wire.replace(", \"cancellable\": true", "");
    assert!(!parse_status(&short).unwrap().cancellable);
    for (text, field) in [
        (
            core.replace("true}", "true, \"cancellable\": true}"),
            "cancellable",
        ),
        (
            wire.replace("{\"decision\": 2}", "{\"decision\": 9}"),
            "autonomous.decision",
        ),
        ("[]".to_owned(), ""),
        (format!("{core} {{}}"), ""),
    ] {
        match parse_status(&text) {
            Err(ErrorKind::Json { field: found, .. }) => assert_eq!(found, field, "{text}"),
            other => panic!("{text}: {other:?}"),
        }
    }
}
