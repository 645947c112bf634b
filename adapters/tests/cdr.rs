//! The CDR form against Cyclone DDS's: for each message, the encoder's bytes equal the bytes
//! `cyclonedds.idl` writes for the same value (`adapters/tests/data/cdr/*.hex`, written by
//! `tools/cdr-golden`, which CI runs with `--check`), and those bytes read back to the value.
//! Then hostile bytes: every prefix of every message, every single-byte change, and random
//! bytes are read without a panic, and the refusals the module's docs name are each seen.

use cooperation_adapters::cdr::{self, CdrError};
use cooperation_adapters::rtc::{self, CooperateStatus, CooperateStatusArray};
use cooperation_adapters::sync::{StatedSequence, SyncCooperateStatusRequest};
use cooperation_adapters::wire::*;
use cooperation_adapters::Time;
use proptest::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;

fn golden(name: &str) -> Vec<u8> {
    let path = format!("{}/data/cdr/{name}.hex", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let text = text.trim();
    (0..text.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&text[i..i + 2], 16).expect("hex"))
        .collect()
}

fn uuid(first: u8) -> Uuid {
    Uuid {
        uuid: core::array::from_fn(|i| first.wrapping_add(u8::try_from(i).expect("below 16"))),
    }
}

fn pose(x: f64, y: f64) -> Pose {
    Pose {
        position: Point { x, y, z: 0.0 },
        orientation: Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.5,
            w: 0.5,
        },
    }
}

const fn decision(decision: u8) -> CooperationDecision {
    CooperationDecision { decision }
}

fn policy(behavior: &str, sequence: &str, policy: u8) -> CooperationPolicy {
    CooperationPolicy {
        behavior: behavior.into(),
        sequence: sequence.into(),
        policy,
    }
}

fn status(success: bool, code: u16, message: &str) -> ResponseStatus {
    ResponseStatus {
        success,
        code,
        message: message.into(),
    }
}

/// The samples of `tools/cdr_golden.py`, value for value.
fn velocity_factors() -> VelocityFactorArray {
    VelocityFactorArray {
        header: Header {
            stamp: Time::new(1_700_000_000, 123_456_789),
            frame_id: "map".into(),
        },
        factors: vec![
            VelocityFactor {
                pose: pose(1.5, -2.25),
                distance: 12.5,
                status: 1,
                behavior: "intersection".into(),
                sequence: String::new(),
                detail: "odd".into(),
                cooperation: vec![CooperationStatus {
                    uuid: uuid(0),
                    autonomous: decision(2),
                    cooperator: decision(4),
                    cancellable: true,
                }],
            },
            VelocityFactor {
                pose: Pose::default(),
                distance: 3.0,
                status: 2,
                behavior: "crosswalk".into(),
                sequence: "x".into(),
                detail: String::new(),
                cooperation: vec![],
            },
        ],
    }
}

fn steering_factors() -> SteeringFactorArray {
    SteeringFactorArray {
        header: Header {
            stamp: Time::new(5, 6),
            frame_id: "base_link".into(),
        },
        factors: vec![SteeringFactor {
            pose: [pose(10.0, 1.0), pose(60.0, 4.5)],
            distance: [25.0, 70.5],
            direction: 2,
            status: 3,
            behavior: "lane-change".into(),
            sequence: "change".into(),
            detail: "a".into(),
            cooperation: vec![CooperationStatus {
                uuid: uuid(240),
                autonomous: decision(1),
                cooperator: decision(3),
                cancellable: false,
            }],
        }],
    }
}

fn set_commands_request() -> SetCooperationCommandsRequest {
    SetCooperationCommandsRequest {
        commands: vec![
            CooperationCommand {
                uuid: uuid(0),
                cooperator: decision(2),
            },
            CooperationCommand {
                uuid: Uuid { uuid: [0xab; 16] },
                cooperator: decision(4),
            },
        ],
    }
}

fn cooperate_status_array() -> CooperateStatusArray {
    CooperateStatusArray {
        stamp: Time::new(10, 20),
        statuses: vec![CooperateStatus {
            stamp: Time::new(9, 999_999_999),
            uuid: rtc::Uuid {
                uuid: core::array::from_fn(|i| 1 + i as u8),
            },
            module: rtc::Module::new(rtc::Module::INTERSECTION),
            safe: true,
            requested: false,
            command_status: rtc::Command::new(rtc::Command::ACTIVATE),
            state: rtc::Lifecycle::new(rtc::Lifecycle::RUNNING),
            auto_mode: false,
            start_distance: 10.25,
            finish_distance: 10.25,
        }],
    }
}

/// The encoder writes Cyclone's bytes, and they read back to the value.
fn same_as_cyclone<T>(name: &str, value: &T)
where
    T: Serialize + DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let bytes = golden(name);
    assert_eq!(
        cdr::to_vec(value).expect("encodes"),
        bytes,
        "{name}: encoder"
    );
    assert_eq!(
        &cdr::from_slice::<T>(&bytes).expect("decodes"),
        value,
        "{name}: decoder"
    );
}

#[test]
fn every_message_is_written_as_cyclone_writes_it_and_read_back() {
    same_as_cyclone("velocity_factors", &velocity_factors());
    same_as_cyclone("steering_factors", &steering_factors());
    same_as_cyclone("set_commands_request", &set_commands_request());
    same_as_cyclone(
        "set_commands_response",
        &SetCooperationCommandsResponse {
            status: status(false, 50_004, "commands[1].cooperator.decision is 9"),
        },
    );
    same_as_cyclone(
        "set_policies_request",
        &SetCooperationPoliciesRequest {
            policies: vec![
                policy("lane-change", "", 1),
                policy("avoidance", "return", 2),
            ],
        },
    );
    same_as_cyclone(
        "set_policies_response",
        &SetCooperationPoliciesResponse {
            status: status(true, 0, ""),
        },
    );
    same_as_cyclone("get_policies_request", &GetCooperationPoliciesRequest {});
    same_as_cyclone(
        "get_policies_response",
        &GetCooperationPoliciesResponse {
            status: status(true, 0, ""),
            policies: vec![policy("intersection", "", 2)],
        },
    );
    same_as_cyclone("cooperate_status_array", &cooperate_status_array());
}

fn refused<T: DeserializeOwned + core::fmt::Debug>(bytes: &[u8]) -> CdrError {
    cdr::from_slice::<T>(bytes).expect_err("refused")
}

#[test]
fn each_refusal_the_docs_name_is_seen() {
    let good = golden("set_policies_request");
    // A truncated message, at every length.
    for len in 0..good.len() {
        refused::<SetCooperationPoliciesRequest>(&good[..len]);
    }
    // An unknown encapsulation (big-endian plain CDR).
    let mut big = good.clone();
    big[1] = 0;
    assert!(refused::<SetCooperationPoliciesRequest>(&big)
        .message
        .contains("not little-endian"));
    // More than padding after the message.
    let mut long = good.clone();
    long.extend([0, 0, 0, 0]);
    assert!(refused::<SetCooperationPoliciesRequest>(&long)
        .message
        .contains("follow the message"));
    let mut padded = good.clone();
    padded.extend([0, 7, 0]);
    cdr::from_slice::<SetCooperationPoliciesRequest>(&padded).expect("three bytes of padding");
    // Padding inside a message is not read either: the three bytes before a response's code.
    let mut response = golden("get_policies_response");
    assert_eq!(response[4 + 1], 0);
    response[4 + 1] = 0x99;
    assert_eq!(
        cdr::from_slice::<GetCooperationPoliciesResponse>(&response).expect("reads"),
        cdr::from_slice::<GetCooperationPoliciesResponse>(&golden("get_policies_response"))
            .expect("reads")
    );
    // A string without its NUL: the first behaviour's last byte.
    let mut unterminated = good.clone();
    let nul = 4 + 4 + 4 + "lane-change".len();
    assert_eq!(unterminated[nul], 0);
    unterminated[nul] = b'!';
    let error = refused::<SetCooperationPoliciesRequest>(&unterminated);
    assert!(error.message.contains("NUL"), "{error}");
    assert_eq!(error.offset, 8, "{error}");
    // A string holding a NUL before its end (which no writer can write back).
    let mut inner = good.clone();
    inner[12 + 4] = 0;
    assert!(refused::<SetCooperationPoliciesRequest>(&inner)
        .message
        .contains("before its end"));
    // A string that is not UTF-8.
    let mut garbled = good.clone();
    garbled[12] = 0xff;
    assert!(refused::<SetCooperationPoliciesRequest>(&garbled)
        .message
        .contains("UTF-8"));
    // A count beyond the bytes left.
    let mut counted = good.clone();
    counted[4..8].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(refused::<SetCooperationPoliciesRequest>(&counted)
        .message
        .contains("exceeds"));
    // A boolean that is neither 0 nor 1.
    let mut response = golden("set_policies_response");
    response[4] = 2;
    assert!(refused::<SetCooperationPoliciesResponse>(&response)
        .message
        .contains("boolean"));
    // Writing: a string holding a NUL.
    let nul = SetCooperationPoliciesRequest {
        policies: vec![policy("lane\0change", "", 1)],
    };
    assert!(cdr::to_vec(&nul).unwrap_err().message.contains("NUL"));
}

/// A value its own type refuses, inside a message, is placed at the offset where the value
/// starts, not at the start of the message.
#[test]
fn a_value_its_type_refuses_is_refused_at_its_own_offset() {
    // The status's stamp: after the array's stamp (8 bytes) and the statuses' count (4).
    let mut array = cdr::to_vec(&cooperate_status_array()).expect("writes");
    let nanosec = 4 + 12 + 4;
    assert_eq!(array[nanosec..nanosec + 4], 999_999_999_u32.to_le_bytes());
    array[nanosec..nanosec + 4].copy_from_slice(&2_000_000_000_u32.to_le_bytes());
    let error = refused::<CooperateStatusArray>(&array);
    assert!(error.message.contains("nanosec"), "{error}");
    assert_eq!(error.offset, 12, "{error}");

    // A sync's stated sequence that is no sequence name: its string's length field, after the
    // interface (4 + 17 bytes, padded to 24), two counts and the UUID.
    let request = SyncCooperateStatusRequest {
        interface: "lane_change_left".to_owned(),
        sequences: vec![StatedSequence {
            uuid: rtc::Uuid { uuid: [7; 16] },
            sequence: cooperation::Sequence::Change,
        }],
        ..SyncCooperateStatusRequest::default()
    };
    let mut bytes = cdr::to_vec(&request).expect("writes");
    let name = 4 + 24 + 4 + 4 + 16;
    assert_eq!(bytes[name + 4..name + 4 + 7], *b"change\0");
    bytes[name + 4] = b'C';
    let error = refused::<SyncCooperateStatusRequest>(&bytes);
    assert!(error.message.contains("Change"), "{error}");
    assert_eq!(error.offset, name - 4, "{error}");
}

#[test]
fn every_single_byte_change_reads_or_is_refused() {
    for name in [
        "velocity_factors",
        "steering_factors",
        "set_commands_request",
    ] {
        let good = golden(name);
        for at in 0..good.len() {
            for value in [0, 1, 2, 0x7f, 0x80, 0xff] {
                let mut bytes = good.clone();
                bytes[at] = value;
                // None may panic; a success writes back the same data (the header's options,
                // which a reader ignores, and padding aside).
                if let Ok(read) = cdr::from_slice::<SetCooperationCommandsRequest>(&bytes) {
                    let again = cdr::to_vec(&read).expect("writes what it read");
                    assert_eq!(again[4..], bytes[4..again.len()], "{name} at {at}");
                }
                let _ = cdr::from_slice::<VelocityFactorArray>(&bytes);
                let _ = cdr::from_slice::<SteeringFactorArray>(&bytes);
            }
        }
    }
}

proptest! {
    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..256)) {
        let mut framed = cdr::CDR_LE.to_vec();
        framed.extend(&bytes);
        let _ = cdr::from_slice::<SetCooperationCommandsRequest>(&framed);
        let _ = cdr::from_slice::<SetCooperationPoliciesRequest>(&framed);
        let _ = cdr::from_slice::<GetCooperationPoliciesRequest>(&framed);
        let _ = cdr::from_slice::<VelocityFactorArray>(&framed);
        let _ = cdr::from_slice::<CooperateStatusArray>(&framed);
    }

    #[test]
    fn commands_round_trip(commands in proptest::collection::vec(
        (any::<[u8; 16]>(), any::<u8>()), 0..20)) {
        let request = SetCooperationCommandsRequest {
            commands: commands
                .into_iter()
                .map(|(uuid, cooperator)| CooperationCommand {
                    uuid: Uuid { uuid },
                    cooperator: decision(cooperator),
                })
                .collect(),
        };
        let bytes = cdr::to_vec(&request).expect("encodes");
        prop_assert_eq!(bytes.len(), 8 + 17 * request.commands.len());
        prop_assert_eq!(cdr::from_slice::<SetCooperationCommandsRequest>(&bytes).expect("decodes"), request);
    }
}
