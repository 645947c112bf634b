//! The messages' JSON shapes, parsing and round trips.

use super::*;
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// Messages
// ---------------------------------------------------------------------------------------------

#[test]
fn json_shapes_are_rosbridge_shapes() {
    let status = rtc::CooperateStatus {
        stamp: Time::new(1, 2),
        uuid: SceneId::from_u128(0x0102).into(),
        module: rtc::Module::new(rtc::Module::CROSSWALK),
        safe: true,
        requested: false,
        command_status: rtc::Command::new(rtc::Command::ACTIVATE),
        state: rtc::Lifecycle::new(rtc::Lifecycle::RUNNING),
        auto_mode: false,
        start_distance: 1.5,
        finish_distance: 2.5,
    };
    let json = serde_json::to_value(status).expect("serializes");
    assert_eq!(
        json,
        serde_json::json!({
            "stamp": {"sec": 1, "nanosec": 2},
            "uuid": {"uuid": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2]},
            "module": {"type": 10},
            "safe": true,
            "requested": false,
            "command_status": {"type": 1},
            "state": {"type": 1},
            "auto_mode": false,
            "start_distance": 1.5,
            "finish_distance": 2.5
        })
    );
    // `requested` is absent in messages from before it existed.
    let mut older = json.clone();
    older.as_object_mut().expect("object").remove("requested");
    assert_eq!(
        serde_json::from_value::<rtc::CooperateStatus>(older).expect("reads"),
        status
    );
}

#[test]
fn a_hand_written_command_request_parses() {
    let text = r#"{
        "stamp": {"sec": 0, "nanosec": 0},
        "commands": [
            {"uuid": {"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,7]}, "module": {"type": 1}, "command": {"type": 1}},
            {"uuid": {"uuid": "AAAAAAAAAAAAAAAAAAAACA=="}, "module": {"type": 0}, "command": {"type": 0}}
        ]
    }"#;
    let request: rtc::CooperateCommandsRequest = serde_json::from_str(text).expect("reads");
    assert_eq!(
        request.parse(),
        Ok(vec![
            Command {
                id: id(7),
                decision: OperatorDecision::Activate
            },
            Command {
                id: id(8),
                decision: OperatorDecision::Deactivate
            },
        ])
    );
    for bad in [
        r#"{"uuid": [1, 2, 3]}"#,
        r#"{"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]}"#,
        r#"{"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,256]}"#,
        r#"{"uuid": "AAAA"}"#,
        r#"{"uuid": 5}"#,
    ] {
        assert!(serde_json::from_str::<rtc::Uuid>(bad).is_err(), "{bad}");
    }
}

#[test]
fn statuses_parse_with_the_field_named() {
    let mut array = rtc::CooperateStatusArray {
        stamp: Time::default(),
        statuses: vec![rtc::CooperateStatus::default(); 2],
    };
    let parsed = array.parse().expect("all zero is valid");
    assert_eq!(parsed[0].phase, Phase::Waiting);
    assert_eq!(parsed[0].module, rtc::ModuleType::None);
    assert_eq!(parsed[0].command, Decision::Deactivate);
    array.statuses[1].state = rtc::Lifecycle::new(9);
    let field = array.parse().expect_err("undefined").field;
    assert_eq!(field.to_string(), "statuses[1].state.type");
    // The wire layer's path type, segment by segment.
    assert_eq!(
        field.segments(),
        [
            cooperation_adapters::PathSegment::Field("statuses".into()),
            cooperation_adapters::PathSegment::Index(1),
            cooperation_adapters::PathSegment::Field("state".into()),
            cooperation_adapters::PathSegment::Field("type".into()),
        ]
    );
    array.statuses[1].state = rtc::Lifecycle::new(rtc::Lifecycle::ABORTING);
    array.statuses[1].module = rtc::Module::new(20);
    assert_eq!(
        array.parse().expect_err("undefined").to_string(),
        "statuses[1].module.type is 20, which is not a Module constant (0 to 19)"
    );
}

#[test]
fn constants_convert_both_ways() {
    for phase in Phase::ALL {
        assert_eq!(rtc::Lifecycle::from(phase).phase(), Ok(phase));
    }
    for decision in Decision::ALL {
        assert_eq!(rtc::Command::from(decision).decision(), Ok(decision));
    }
    for module in rtc::ModuleType::ALL {
        assert_eq!(rtc::Module::from(module).module_type(), Ok(module));
    }
    assert_eq!(rtc::policy_for_auto_mode(true), Policy::Optional);
    assert_eq!(rtc::policy_for_auto_mode(false), Policy::Required);
}

fn any_time() -> impl Strategy<Value = Time> {
    (any::<i32>(), 0..1_000_000_000u32).prop_map(|(sec, nanosec)| Time { sec, nanosec })
}

fn any_uuid() -> impl Strategy<Value = rtc::Uuid> {
    any::<[u8; 16]>().prop_map(|uuid| rtc::Uuid { uuid })
}

fn any_module() -> impl Strategy<Value = rtc::Module> {
    any::<u8>().prop_map(rtc::Module::new)
}

fn any_distance() -> impl Strategy<Value = f32> {
    // JSON has no NaN or infinity.
    prop_oneof![
        -1.0e6f32..1.0e6,
        Just(0.0),
        Just(-0.0),
        Just(f32::MAX),
        Just(f32::MIN_POSITIVE)
    ]
}

fn any_status() -> impl Strategy<Value = rtc::CooperateStatus> {
    (
        (
            any_time(),
            any_uuid(),
            any_module(),
            any::<bool>(),
            any::<bool>(),
        ),
        (
            any::<u8>(),
            any::<u8>(),
            any::<bool>(),
            any_distance(),
            any_distance(),
        ),
    )
        .prop_map(
            |(
                (stamp, uuid, module, safe, requested),
                (command, state, auto_mode, start, finish),
            )| {
                rtc::CooperateStatus {
                    stamp,
                    uuid,
                    module,
                    safe,
                    requested,
                    command_status: rtc::Command::new(command),
                    state: rtc::Lifecycle::new(state),
                    auto_mode,
                    start_distance: start,
                    finish_distance: finish,
                }
            },
        )
}

fn any_command() -> impl Strategy<Value = rtc::CooperateCommand> {
    (any_uuid(), any_module(), any::<u8>()).prop_map(|(uuid, module, command)| {
        rtc::CooperateCommand {
            uuid,
            module,
            command: rtc::Command::new(command),
        }
    })
}

fn round_trips<T>(value: &T) -> Result<(), TestCaseError>
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let text = serde_json::to_string(value).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let back: T = serde_json::from_str(&text).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(&back, value, "{}", text);
    Ok(())
}

proptest! {
    #[test]
    fn every_message_round_trips_through_json(
        time in any_time(),
        uuid in any_uuid(),
        module in any_module(),
        command in any::<u8>(),
        state in any::<u8>(),
        statuses in proptest::collection::vec(any_status(), 0..4),
        commands in proptest::collection::vec(any_command(), 0..4),
        flags in any::<[bool; 2]>(),
    ) {
        let [enable, success] = flags;
        round_trips(&time)?;
        round_trips(&uuid)?;
        round_trips(&module)?;
        round_trips(&rtc::Command::new(command))?;
        round_trips(&rtc::Lifecycle::new(state))?;
        for status in &statuses {
            round_trips(status)?;
        }
        round_trips(&rtc::CooperateStatusArray { stamp: time, statuses })?;
        for command in &commands {
            round_trips(command)?;
            round_trips(&rtc::CooperateResponse { uuid: command.uuid, module: command.module, success })?;
        }
        round_trips(&rtc::CooperateCommandsResponse {
            responses: commands
                .iter()
                .map(|c| rtc::CooperateResponse { uuid: c.uuid, module: c.module, success })
                .collect(),
        })?;
        round_trips(&rtc::CooperateCommandsRequest { stamp: time, commands })?;
        let auto = rtc::AutoModeStatus { module, is_auto_mode: enable };
        round_trips(&auto)?;
        round_trips(&rtc::AutoModeStatusArray { stamp: time, statuses: vec![auto; 3] })?;
        round_trips(&rtc::AutoModeRequest { enable })?;
        round_trips(&rtc::AutoModeResponse { success })?;
        round_trips(&rtc::AutoModeWithModuleRequest { module, enable })?;
        round_trips(&rtc::AutoModeWithModuleResponse { success })?;
        round_trips(&rtc::ModuleType::from_value(module.r#type).unwrap_or(rtc::ModuleType::None))?;
    }

    /// A UUID reads the same from its array and from rosbridge's base64 form.
    #[test]
    fn uuid_reads_from_base64(bytes in any::<[u8; 16]>()) {
        let base64 = encode_base64(&bytes);
        let from_text: rtc::Uuid =
            serde_json::from_value(serde_json::json!({ "uuid": base64 })).expect("reads");
        prop_assert_eq!(from_text.uuid, bytes);
    }
}

/// Standard base64 with padding, to check the decoder against.
fn encode_base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let mut block = [0u8; 3];
        block[..chunk.len()].copy_from_slice(chunk);
        let n = (u32::from(block[0]) << 16) | (u32::from(block[1]) << 8) | u32::from(block[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * i)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}
