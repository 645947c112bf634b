//! Hostile input to the wire module: requests over the size limit, memory on a read that
//! fails, numbers out of their type's range, fields named in the list form, a field given twice
//! in every message, and input echoed in messages.
//!
//! The memory tests count allocations with a process-wide allocator, so every test in this
//! file holds one lock while it runs: no other test allocates while a count is taken.

#[path = "wire/wire_fixtures.rs"]
mod wire_fixtures;

use std::alloc::System;
use std::sync::{Mutex, MutexGuard};

use cooperation::*;
use cooperation_adapters::wire::{self, Malformed, Service, MAX_REQUEST_BYTES};
use serde::de::DeserializeOwned;
use stats_alloc::{Region, StatsAlloc, INSTRUMENTED_SYSTEM};
use wire_fixtures::*;

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// Holds the file's lock: the test runs alone.
fn alone() -> MutexGuard<'static, ()> {
    ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Bytes allocated while `run` runs, growth by reallocation included: what it adds to the
/// process's memory at its peak is at most this.
fn allocated<R>(run: impl FnOnce() -> R) -> (usize, R) {
    let region = Region::new(GLOBAL);
    let result = run();
    (region.change().bytes_allocated, result)
}

/// One command for scene B, its UUID as a list of numbers.
fn command_b() -> String {
    format!(
        r#"{{"uuid": {{"uuid": {:?}}}, "cooperator": {{"decision": 1}}}}"#,
        B.to_bytes()
    )
}

/// `head`, as many `entry`s as fit, comma-separated, and `tail`: `len` bytes at most.
fn filled(len: usize, head: &str, entry: &str, tail: &str) -> String {
    let count = (len - head.len() - tail.len()) / (entry.len() + 1);
    format!("{head}{}{tail}", vec![entry; count].join(","))
}

/// `text` padded with `pad` to exactly `len` bytes.
fn padded(mut text: String, pad: char, len: usize) -> Vec<u8> {
    assert!(text.len() <= len);
    while text.len() < len {
        text.push(pad);
    }
    text.into_bytes()
}

/// `len` bytes: a `set_commands` request that fills them, then text that is not JSON.
fn with_trailing_junk(len: usize) -> Vec<u8> {
    let request = filled(len - 10, r#"{"commands": ["#, &command_b(), "]}");
    padded(format!("{request} junk"), 'x', len)
}

/// `request` sent to `service` as JSON: refused with `message`, the state unchanged.
fn refused_with(state: &mut State, service: Service, request: &[u8], message: &str) {
    let before = state.clone();
    let response = json(&service.call_json(state, request));
    assert_eq!(*state, before, "a refused request changed the state");
    assert_eq!(response["status"]["success"], false);
    assert_eq!(
        response["status"]["code"],
        u64::from(wire::ResponseStatus::PARAMETER_ERROR)
    );
    assert_eq!(response["status"]["message"], message);
}

// -------------------------------------------------------------------------------------------
// The size limit, and memory
// -------------------------------------------------------------------------------------------

#[test]
fn a_request_over_the_size_limit_is_refused_unread_saying_limit_and_size() {
    let _alone = alone();
    assert_eq!(MAX_REQUEST_BYTES, 1 << 20);
    let mut state = with_scenes();
    let requests = [
        (Service::SetCommands, r#"{"commands": []}"#),
        (Service::SetPolicies, r#"{"policies": []}"#),
        (Service::GetPolicies, "{}"),
    ];
    for (service, empty) in requests {
        // Up to the limit, a request is read (trailing white space is allowed).
        let at_limit = padded(empty.to_owned(), ' ', MAX_REQUEST_BYTES);
        let response = json(&service.call_json(&mut state, &at_limit));
        assert_eq!(response["status"]["success"], true, "{service:?}");
        // One byte more and it is refused, whatever it holds; nothing changes.
        let over = padded(empty.to_owned(), ' ', MAX_REQUEST_BYTES + 1);
        let fault = Malformed::TooLarge {
            path: cooperation_adapters::FieldPath::root(),
            len: MAX_REQUEST_BYTES + 1,
            max: MAX_REQUEST_BYTES,
        };
        assert_eq!(
            fault.to_string(),
            "the request is 1048577 bytes long; at most 1048576 bytes are read"
        );
        assert!(fault.path().is_root());
        refused_with(&mut state, service, &over, &fault.to_string());
        let commands = filled(
            8 * MAX_REQUEST_BYTES,
            r#"{"commands": ["#,
            &command_b(),
            "]}",
        );
        let (bytes, ()) = allocated(|| {
            refused_with(
                &mut state,
                service,
                commands.as_bytes(),
                &format!(
                    "the request is {} bytes long; at most 1048576 bytes are read",
                    commands.len()
                ),
            );
        });
        // Refused unread: the answer is all that is built.
        assert!(bytes < 64 * 1024, "{bytes} bytes allocated");
    }
}

#[test]
fn the_size_limit_holds_the_largest_default_batch_with_room_to_spare() {
    let _alone = alone();
    let mut state = State::new(Config::new([(LANE_CHANGE, Policy::Optional)])).expect("valid");
    let max_batch = Limits::default().max_batch;
    assert_eq!(max_batch, 1_024);
    // At its most verbose: pretty-printed, UUIDs as lists of three-digit numbers.
    let commands: wire::SetCooperationCommandsRequest = (0..max_batch)
        .map(|n| Command {
            id: SceneId::from_u128(u128::MAX - n as u128),
            decision: OperatorDecision::Undecided,
        })
        .collect();
    let policies = wire::SetCooperationPoliciesRequest {
        policies: vec![
            wire::CooperationPolicy {
                behavior: wire::PlanningBehavior::USER_DEFINED_DETECTION_AREA.to_owned(),
                sequence: wire::PlanningSequence::CHANGE.to_owned(),
                policy: wire::CooperationPolicy::REQUIRED,
            };
            max_batch
        ],
    };
    for (service, request) in [
        (
            Service::SetCommands,
            serde_json::to_vec_pretty(&commands).expect("writes"),
        ),
        (
            Service::SetPolicies,
            serde_json::to_vec_pretty(&policies).expect("writes"),
        ),
    ] {
        assert!(request.len() < 400 * 1024, "{} bytes", request.len());
        // Read: the core answers (these scenes and modules are unknown to it).
        let response = json(&service.call_json(&mut state, &request));
        let message = response["status"]["message"].as_str().expect("a message");
        assert!(!message.starts_with("the request is"), "{message}");
    }
    // 14 000 compact commands, 72 bytes each, fit; the core's batch limit refuses them.
    let compact = r#"{"uuid":{"uuid":"AAECAwQFBgcICQoLDA0ODw=="},"cooperator":{"decision":2}}"#;
    assert_eq!(compact.len(), 72);
    let request = format!(r#"{{"commands":[{}]}}"#, vec![compact; 14_000].join(","));
    assert!(request.len() <= MAX_REQUEST_BYTES);
    let response = json(&Service::SetCommands.call_json(&mut state, request.as_bytes()));
    assert_eq!(
        response["status"]["message"],
        "the batch has 14000 entries; at most 1024 are accepted"
    );
}

#[test]
fn a_read_that_fails_builds_nothing_but_the_message() {
    let _alone = alone();
    // The counter counts.
    let (bytes, boxed) = allocated(|| std::hint::black_box(vec![0_u8; 1000]));
    assert!(bytes >= 1000);
    drop(boxed);

    let mut state = with_scenes();
    let before = state.clone();
    // `from_json` reads any length; a request to a service, up to the limit.
    for len in [MAX_REQUEST_BYTES, 8 * MAX_REQUEST_BYTES] {
        let request = with_trailing_junk(len);
        assert_eq!(request.len(), len);
        let (failed, fault) = allocated(|| {
            wire::from_json::<wire::SetCooperationCommandsRequest>(&request)
                .expect_err("trailing junk")
        });
        assert!(matches!(fault, Malformed::NotJson { .. }), "{fault:?}");
        assert!(
            fault
                .to_string()
                .starts_with("not JSON: trailing characters"),
            "{fault}"
        );
        // The same message without the junk: the failed read cost no more.
        let message = request
            .get(..request.len() - request.iter().rev().take_while(|&&b| b == b'x').count() - 5)
            .expect("the message");
        let (read, _) =
            allocated(|| wire::from_json::<wire::SetCooperationCommandsRequest>(message));
        assert!(
            failed <= read + 1024,
            "{len} bytes: {failed} bytes allocated failing, {read} reading"
        );
        // A typical request takes less memory than twice its length.
        assert!(failed <= 2 * len, "{len} bytes: {failed} bytes allocated");
    }
    let request = with_trailing_junk(MAX_REQUEST_BYTES);
    let (bytes, response) = allocated(|| Service::SetCommands.call_json(&mut state, &request));
    let response = json(&response);
    assert_eq!(response["status"]["code"], 50_004);
    assert!(bytes <= 2 * request.len(), "{bytes} bytes allocated");
    assert_eq!(state, before);
}

#[test]
fn at_most_32_bytes_of_memory_per_request_byte_whatever_the_request() {
    let _alone = alone();
    let mut state = with_scenes();
    let before = state.clone();
    let max = MAX_REQUEST_BYTES;
    assert_eq!(std::mem::size_of::<wire::CooperationPolicy>(), 56);
    let uuid_bytes = filled(max, "[[[[[", "0", "]]]]]");
    let behavior = format!(r#"[[["{}"]]]"#, "x".repeat(max - 20));
    // The costliest forms: lists of empty entries, each a whole message in memory (56 bytes
    // for the 3 bytes `{},` of a policy setting), and long values.
    let requests = [
        (
            Service::SetCommands,
            filled(max, r#"{"commands":["#, "{}", "]}"),
        ),
        (Service::SetCommands, filled(max, "[[", "[]", "]]")),
        (
            Service::SetPolicies,
            filled(max, r#"{"policies":["#, "{}", "]}"),
        ),
        (Service::SetPolicies, filled(max, "[[", "[]", "]]")),
        (Service::SetCommands, uuid_bytes),
        (Service::SetPolicies, behavior),
        (Service::GetPolicies, filled(max, "[", "0", "]")),
    ];
    for (service, request) in requests {
        for junk in ["", "x"] {
            let request = format!("{request}{junk}");
            let request = request.get(..max.min(request.len())).expect("ASCII");
            let (bytes, _) = allocated(|| service.call_json(&mut state, request.as_bytes()));
            assert!(
                bytes <= 32 * request.len(),
                "{service:?} {}…: {bytes} bytes allocated for {} bytes",
                request.get(..20).expect("ASCII"),
                request.len()
            );
        }
    }
    assert_eq!(state, before);
}

// -------------------------------------------------------------------------------------------
// Numbers
// -------------------------------------------------------------------------------------------

/// The fault reading `text` as a `T`.
fn read_fault<T: DeserializeOwned + std::fmt::Debug>(text: &str) -> Malformed {
    wire::from_json::<T>(text.as_bytes()).expect_err(text)
}

#[test]
fn a_number_out_of_its_fields_range_is_named_with_the_field_and_type() {
    let _alone = alone();
    let f32_max = f32::MAX.to_string();
    for (fault, says) in [
        (
            read_fault::<wire::VelocityFactorArray>(r#"{"factors": [{"distance": 1e39}]}"#),
            "factors[0].distance: 1e39 is out of range for a 32-bit float (f32) at line 1 column 30",
        ),
        (
            read_fault::<wire::SteeringFactorArray>(r#"{"factors": [{"distance": [1, -3.5e38]}]}"#),
            "factors[0].distance[1]: -3.5e38 is out of range for a 32-bit float (f32) at line 1 column 37",
        ),
        (
            read_fault::<wire::VelocityFactorArray>("{\"factors\": [{\n  \"pose\": {\"position\": {\"x\": 1e309}}}]}"),
            "factors[0].pose.position.x: 1e309 is out of range for a 64-bit float (f64) at line 2 column 34",
        ),
        (
            read_fault::<wire::SetCooperationCommandsRequest>(r#"{"commands": [{"cooperator": {"decision": 1e400}}]}"#),
            "commands[0].cooperator.decision: 1e400 is out of range for an 8-bit unsigned integer (u8) at line 1 column 47",
        ),
        (
            read_fault::<wire::SetCooperationCommandsRequest>(r#"{"commands": [{"uuid": {"uuid": [0, 9e999]}}]}"#),
            "commands[0].uuid.uuid[1]: 9e999 is out of range for an 8-bit unsigned integer (u8) at line 1 column 41",
        ),
        (
            read_fault::<wire::SetCooperationCommandsRequest>(r#"{"commands": [{"uuid": {"uuid": 1e400}}]}"#),
            "commands[0].uuid.uuid: 1e400 is out of range for a 64-bit float (f64), the widest number read from JSON at line 1 column 37",
        ),
        (
            read_fault::<wire::SteeringFactorArray>(r#"{"header": {"stamp": {"sec": 1e400}}}"#),
            "header.stamp.sec: 1e400 is out of range for a 32-bit integer (i32) at line 1 column 34",
        ),
        // The list form names the same field.
        (
            read_fault::<wire::VelocityFactorArray>("[{}, [[{}, 1e39]]]"),
            "factors[0].distance: 1e39 is out of range for a 32-bit float (f32) at line 1 column 15",
        ),
    ] {
        assert!(matches!(fault, Malformed::Shape { .. }), "{fault:?}");
        assert_eq!(fault.to_string(), says);
    }
    // The largest f32 is in range; so is a number that rounds to zero.
    let text = format!(r#"{{"factors": [{{"distance": {f32_max}}}, {{"distance": 1e-99}}]}}"#);
    let array = wire::from_json::<wire::VelocityFactorArray>(text.as_bytes()).expect("in range");
    assert_eq!(array.factors[0].distance, f32::MAX);
    assert_eq!(array.factors[1].distance, 0.0);

    // A number of a thousand digits is quoted short.
    let digits = format!("1{}", "0".repeat(999));
    let fault = read_fault::<wire::VelocityFactorArray>(&format!(
        r#"{{"factors": [{{"distance": {digits}}}]}}"#
    ));
    assert_eq!(
        fault.to_string(),
        format!(
            "factors[0].distance: {}… (1000 characters) is out of range for a 32-bit float (f32) at line 1 column 1026",
            digits.get(..64).expect("ASCII")
        )
    );

    // Through a service: refused naming the field, nothing changes.
    let mut state = with_scenes();
    let request = format!(
        r#"[[{{"uuid": {{"uuid": {:?}}}, "cooperator": [1e400]}}]]"#,
        A.to_bytes()
    );
    refused_with(
        &mut state,
        Service::SetCommands,
        request.as_bytes(),
        "commands[0].cooperator.decision: 1e400 is out of range for an 8-bit unsigned integer (u8) at line 1 column 111",
    );
}

// -------------------------------------------------------------------------------------------
// The list form
// -------------------------------------------------------------------------------------------

#[test]
fn the_list_form_names_the_field_as_the_object_form_does() {
    let _alone = alone();
    let a = format!("{:?}", A.to_bytes());
    // The same fault written with objects and as lists of field values: the same path.
    let commands = |object: &str, list: &str, at: &str| {
        let by_name = read_fault::<wire::SetCooperationCommandsRequest>(object);
        let by_position = read_fault::<wire::SetCooperationCommandsRequest>(list);
        (by_name, by_position, at.to_owned())
    };
    let policies = |object: &str, list: &str, at: &str| {
        let by_name = read_fault::<wire::SetCooperationPoliciesRequest>(object);
        let by_position = read_fault::<wire::SetCooperationPoliciesRequest>(list);
        (by_name, by_position, at.to_owned())
    };
    let steering = |object: &str, list: &str, at: &str| {
        let by_name = read_fault::<wire::SteeringFactorArray>(object);
        let by_position = read_fault::<wire::SteeringFactorArray>(list);
        (by_name, by_position, at.to_owned())
    };
    for (by_name, by_position, at) in [
        commands(
            &format!(
                r#"{{"commands": [{{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": "2"}}}}]}}"#
            ),
            &format!(r#"[[[[{a}], ["2"]]]]"#),
            "commands[0].cooperator.decision",
        ),
        commands(
            r#"{"commands": [{}, {"uuid": {"uuid": [1, 2, 300]}}]}"#,
            "[[[], [[[1, 2, 300]]]]]",
            "commands[1].uuid.uuid[2]",
        ),
        commands(
            r#"{"commands": [{"uuid": {"uuid": "A!=="}}]}"#,
            r#"[[[["A!=="]]]]"#,
            "commands[0].uuid.uuid",
        ),
        commands(r#"{"commands": 5}"#, "[5]", "commands"),
        policies(
            r#"{"policies": [{"behavior": "lane-change", "sequence": 1}]}"#,
            r#"[[["lane-change", 1]]]"#,
            "policies[0].sequence",
        ),
        policies(
            r#"{"policies": [{"policy": -1}]}"#,
            r#"[[["", "", -1]]]"#,
            "policies[0].policy",
        ),
        steering(
            r#"{"header": {"stamp": {"nanosec": -1}}}"#,
            "[[[0, -1]]]",
            "header.stamp.nanosec",
        ),
        steering(
            r#"{"factors": [{"pose": [{}, {"orientation": {"w": "1"}}]}]}"#,
            r#"[{}, [[[{}, [[], [0, 0, 0, "1"]]]]]]"#,
            "factors[0].pose[1].orientation.w",
        ),
        steering(
            r#"{"factors": [{"cooperation": [{"cancellable": 1}]}]}"#,
            "[[], [[[{}, {}], [0, 0], 0, 0, \"\", \"\", \"\", [[[], [], [], 1]]]]]",
            "factors[0].cooperation[0].cancellable",
        ),
    ] {
        assert!(matches!(by_name, Malformed::Shape { .. }), "{by_name:?}");
        assert!(
            matches!(by_position, Malformed::Shape { .. }),
            "{by_position:?}"
        );
        assert_eq!(by_name.path().to_string(), at);
        assert_eq!(by_position.path().to_string(), at, "{by_position}");
    }

    // Conversion faults of a request in the list form name the same fields.
    let mut state = with_scenes();
    let request = format!(r#"[[[[{a}], [7]]]]"#);
    refused_with(
        &mut state,
        Service::SetCommands,
        request.as_bytes(),
        "commands[0].cooperator.decision: 7 is not a CooperationDecision constant",
    );
    let request = format!(r#"[[[[{a}], ["2"]]]]"#);
    let fault = read_fault::<wire::SetCooperationCommandsRequest>(&request);
    assert!(
        fault.to_string().starts_with(
            r#"commands[0].cooperator.decision: invalid type: string "2", expected u8"#
        ),
        "{fault}"
    );
    refused_with(
        &mut state,
        Service::SetCommands,
        request.as_bytes(),
        &fault.to_string(),
    );
    // A list longer than its message is still named where it is.
    let fault = read_fault::<wire::SetCooperationCommandsRequest>(&format!("[[[[{a}], [1], 5]]]"));
    assert_eq!(fault.path().to_string(), "commands[0]");
    assert!(
        fault
            .to_string()
            .starts_with("commands[0]: a list with more values than its field takes"),
        "{fault}"
    );
}

// -------------------------------------------------------------------------------------------
// A field given twice
// -------------------------------------------------------------------------------------------

#[test]
fn a_field_given_twice_is_refused_through_every_service() {
    let _alone = alone();
    // Every message refuses it (`tests/wire_fields.rs`); through each service, at every depth
    // of its request, the first time the same: refused naming the message, nothing changes.
    let mut state = with_scenes();
    let a = format!("{:?}", A.to_bytes());
    for (service, request, at) in [
        (Service::SetCommands, r#"{"commands": [], "commands": []}"#.to_owned(), ""),
        (
            Service::SetCommands,
            format!(r#"{{"commands": [{{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 2}}, "uuid": {{"uuid": {a}}}}}]}}"#),
            "commands[0]: ",
        ),
        (
            Service::SetCommands,
            format!(r#"{{"commands": [{{"uuid": {{"uuid": {a}, "uuid": "AAECAwQFBgcICQoLDA0ODw=="}}}}]}}"#),
            "commands[0].uuid: ",
        ),
        (
            Service::SetCommands,
            format!(r#"{{"commands": [{{"uuid": {{"uuid": {a}}}, "cooperator": {{"decision": 2, "decision": 2}}}}]}}"#),
            "commands[0].cooperator: ",
        ),
        (Service::SetPolicies, r#"{"policies": [], "policies": []}"#.to_owned(), ""),
        (
            Service::SetPolicies,
            r#"{"policies": [{"behavior": "lane-change", "sequence": "", "policy": 2, "policy": 1}]}"#.to_owned(),
            "policies[0]: ",
        ),
    ] {
        let fault = match service {
            Service::SetCommands => read_fault::<wire::SetCooperationCommandsRequest>(&request),
            _ => read_fault::<wire::SetCooperationPoliciesRequest>(&request),
        };
        assert!(fault.to_string().starts_with(&format!("{at}duplicate field")), "{fault}");
        refused_with(&mut state, service, request.as_bytes(), &fault.to_string());
    }
    // `get_policies` has no field to give twice: any field is refused.
    let fault = read_fault::<wire::GetCooperationPoliciesRequest>(r#"{"x": 1, "x": 1}"#);
    assert!(
        fault
            .to_string()
            .starts_with("x: unknown field `x`, there are no fields"),
        "{fault}"
    );
    refused_with(
        &mut state,
        Service::GetPolicies,
        br#"{"x": 1, "x": 1}"#,
        &fault.to_string(),
    );
}

// -------------------------------------------------------------------------------------------
// Input echoed in messages
// -------------------------------------------------------------------------------------------

#[test]
fn input_echoed_in_a_message_is_cut_short_and_stays_on_one_line() {
    let _alone = alone();
    let mut state = with_scenes();
    // A field name with a line break and a terminal escape, in the path and the explanation.
    let request = "{\"policies\": [{\"a\\nb\\u001b[2J\": 1}]}";
    let fault = read_fault::<wire::SetCooperationPoliciesRequest>(request);
    let message = fault.to_string();
    assert!(
        message.starts_with("policies[0].a\\nb\\u{1b}[2J: unknown field `a\\nb\\u{1b}[2J`"),
        "{message}"
    );
    assert!(!message.chars().any(char::is_control), "{message:?}");
    refused_with(
        &mut state,
        Service::SetPolicies,
        request.as_bytes(),
        &message,
    );

    // Long, in the path and the explanation: cut.
    let long = format!("{}\\n", "z".repeat(300));
    let request = format!(r#"{{"policies": [{{"{long}": 1}}]}}"#);
    let message = read_fault::<wire::SetCooperationPoliciesRequest>(&request).to_string();
    assert!(message.len() < 700, "{} bytes", message.len());
    assert!(!message.chars().any(char::is_control), "{message:?}");
    // Strings given as values are quoted with escapes.
    let request = "{\"policies\": [{\"behavior\": \"x\\ny\"}]}";
    let decoded = wire::from_json::<wire::SetCooperationPoliciesRequest>(request.as_bytes())
        .expect("a string");
    let message = decoded.to_policies().expect_err("unknown").to_string();
    assert_eq!(
        message,
        "policies[0].behavior: \"x\\ny\" is no PlanningBehavior value or extension name: byte 1 \
         is not a lower-case ASCII letter, digit or '-'"
    );
    refused_with(
        &mut state,
        Service::SetPolicies,
        request.as_bytes(),
        &message,
    );
}

#[test]
fn text_that_is_not_json_is_told_from_a_list_too_long() {
    let _alone = alone();
    for (text, at, says) in [
        // A string escape that is no character.
        (
            r#"{"policies": [{"behavior": "\ud800"}]}"#,
            "policies[0].behavior",
            "not JSON: unexpected end of hex escape at line 1 column 35",
        ),
        // A list that goes on, but not with a value.
        (
            "[[], ,]",
            "",
            "not JSON: trailing characters at line 1 column 6",
        ),
    ] {
        let fault = read_fault::<wire::SetCooperationPoliciesRequest>(text);
        assert!(
            matches!(fault, Malformed::NotJson { .. }),
            "{text}: {fault:?}"
        );
        assert_eq!(fault.path().to_string(), at);
        assert!(fault.to_string().ends_with(says), "{text}: {fault}");
    }
    // A list longer than its message, whatever follows the first value too many.
    let fault = read_fault::<wire::SetCooperationPoliciesRequest>(r#"[[], 5, "\ud800"]"#);
    assert_eq!(
        fault.to_string(),
        "a list with more values than its field takes: trailing characters at line 1 column 6"
    );
}
