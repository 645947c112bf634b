//! Hostile input at the core's own boundaries: identifiers as text, the serde forms of the core
//! and RTC types (unknown fields, repeated fields, states the core cannot reach, floats JSON
//! has no number for), and arithmetic on limits and stamps at their extremes. Each test names
//! the class of input it refuses or survives.

mod common;

use common::*;
use cooperation::rtc::{self, Rtc};
use cooperation::*;
use proptest::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::{json, Value};

// ---------------------------------------------------------------------------------------------
// Walking a serialized value
// ---------------------------------------------------------------------------------------------

/// The paths of every JSON object inside `value`, itself included.
fn object_paths(value: &Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match value {
        Value::Object(map) => {
            out.push(path.clone());
            for (key, inner) in map {
                path.push(key.clone());
                object_paths(inner, path, out);
                path.pop();
            }
        }
        Value::Array(items) => {
            for (index, inner) in items.iter().enumerate() {
                path.push(index.to_string());
                object_paths(inner, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn object_at<'a>(value: &'a mut Value, path: &[String]) -> &'a mut serde_json::Map<String, Value> {
    let mut at = value;
    for step in path {
        at = match at {
            Value::Object(map) => map.get_mut(step).expect("a key on the path"),
            Value::Array(items) => &mut items[step.parse::<usize>().expect("an index")],
            _ => unreachable!("paths lead through objects and arrays"),
        };
    }
    at.as_object_mut().expect("an object")
}

/// JSON text of `value` with the first entry of the object at `path` written twice.
fn with_first_entry_twice(value: &Value, path: &[String]) -> String {
    match value {
        Value::Object(map) => {
            let mut entries: Vec<String> = map
                .iter()
                .map(|(key, inner)| {
                    let inner = match path.split_first() {
                        Some((step, rest)) if step == key => with_first_entry_twice(inner, rest),
                        _ => inner.to_string(),
                    };
                    format!("{}:{inner}", Value::String(key.clone()))
                })
                .collect();
            if path.is_empty() {
                let first = entries[0].clone();
                entries.insert(1, first);
            }
            format!("{{{}}}", entries.join(","))
        }
        Value::Array(items) => {
            let entries: Vec<String> = items
                .iter()
                .enumerate()
                .map(|(index, inner)| match path.split_first() {
                    Some((step, rest)) if *step == index.to_string() => {
                        with_first_entry_twice(inner, rest)
                    }
                    _ => inner.to_string(),
                })
                .collect();
            format!("[{}]", entries.join(","))
        }
        other => other.to_string(),
    }
}

/// `value`'s JSON reads back as `value`; with an unknown field added to any object in it, or
/// with any object's first field written twice, it is refused.
fn refuses_unknown_and_repeated_fields<T>(value: &T) -> usize
where
    T: Serialize + DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let json = serde_json::to_value(value).expect("serializes");
    assert_eq!(
        &serde_json::from_value::<T>(json.clone()).expect("reads back"),
        value
    );
    let mut paths = Vec::new();
    object_paths(&json, &mut Vec::new(), &mut paths);
    for path in &paths {
        let mut extended = json.clone();
        object_at(&mut extended, path).insert("unexpected".to_owned(), json!(0));
        let error = serde_json::from_value::<T>(extended).expect_err("an unknown field");
        // An enum's tag is an object of one key: a second is refused as such.
        let said = error.to_string();
        assert!(
            said.contains("unknown field") || said.contains("single key"),
            "at {path:?}: {said}"
        );
        let mut original = json.clone();
        let object = object_at(&mut original, path);
        let Some(first) = object.keys().next() else {
            continue;
        };
        // An enum's tag: an object of one key, a variant's name. Any second key is refused.
        let tag = object.len() == 1 && first.starts_with(|c: char| c.is_ascii_uppercase());
        let text = with_first_entry_twice(&json, path);
        let error = serde_json::from_str::<T>(&text).expect_err("a field given twice");
        let said = error.to_string();
        assert!(
            tag || said.contains("duplicate field"),
            "at {path:?}: {text}: {said}"
        );
    }
    paths.len()
}

// ---------------------------------------------------------------------------------------------
// Values that reach every serde type
// ---------------------------------------------------------------------------------------------

fn velocity() -> Geometry {
    Geometry::Velocity {
        pose: Pose {
            position: [1.0, 2.0, 3.0],
            orientation: [0.0, 0.0, 0.0, 1.0],
        },
        distance: Distance(12.5),
        status: VelocityStatus::Approaching,
    }
}

/// Every input variant, each with its nested objects.
fn every_input() -> Vec<Input> {
    let module = LANE_CHANGE;
    vec![
        Input::Register {
            id: id(1),
            module,
            report: Report::new(
                Decision::Activate,
                Geometry::steering(Direction::Left, 1.0, 2.0),
            )
            .requesting(),
        },
        Input::Update {
            id: id(1),
            module,
            phase: Phase::Running,
            report: Report::new(Decision::Deactivate, velocity()),
        },
        Input::Remove { id: id(1), module },
        Input::SetCommands {
            commands: vec![Command {
                id: id(1),
                decision: OperatorDecision::Autonomous,
            }],
        },
        Input::SetPolicies {
            policies: vec![PolicySetting {
                module,
                policy: Policy::Optional,
            }],
        },
        Input::Tick { elapsed_ms: 5 },
    ]
}

/// A state with a scene of each kind, a retired identifier and a policy of each kind.
fn busy_state() -> State {
    let mut state = state();
    for input in [
        Input::Register {
            id: id(1),
            module: LANE_CHANGE,
            report: Report::new(
                Decision::Activate,
                Geometry::steering(Direction::Right, 3.0, 9.0),
            ),
        },
        Input::Register {
            id: id(2),
            module: AVOIDANCE,
            report: Report::new(Decision::Deactivate, velocity()).requesting(),
        },
        register(id(3), LANE_CHANGE, Decision::Activate),
        Input::Remove {
            id: id(3),
            module: LANE_CHANGE,
        },
    ] {
        state.apply(&input).expect("applies");
    }
    state
}

/// `[COOP-API-SET-COMMANDS.1]`-shaped inputs, the serialized state, and each output type:
/// no object in any of them takes an unknown field or a field twice.
#[test]
fn core_forms_refuse_unknown_and_repeated_fields() {
    let mut objects = 0;
    for input in every_input() {
        objects += refuses_unknown_and_repeated_fields(&input);
    }
    let state = busy_state();
    objects += refuses_unknown_and_repeated_fields(&state);
    let mut statuses = Vec::new();
    state.statuses_into(&mut statuses);
    objects += refuses_unknown_and_repeated_fields(&statuses);
    let mut velocity_factors = Vec::new();
    state.velocity_factors_into(&mut velocity_factors);
    objects += refuses_unknown_and_repeated_fields(&velocity_factors);
    let mut steering_factors = Vec::new();
    state.steering_factors_into(&mut steering_factors);
    objects += refuses_unknown_and_repeated_fields(&steering_factors);
    objects += refuses_unknown_and_repeated_fields(&Limits::default());
    assert!(objects > 40, "only {objects} objects were tried");
}

/// The RTC messages, as the adapter writes them and as requests arrive.
#[test]
fn rtc_forms_refuse_unknown_and_repeated_fields() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut interface = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    interface
        .update_cooperate_status(id(1), true, rtc::State::RUNNING, 10.0, 60.0, true)
        .expect("registers");
    let stamp = rtc::Time::new(7, 5);
    let statuses = interface.view().cooperate_status_array(stamp);
    let mut objects = refuses_unknown_and_repeated_fields(&statuses);
    let request = rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]);
    objects += refuses_unknown_and_repeated_fields(&request);
    let reply = interface.cooperate_commands(&request);
    objects += refuses_unknown_and_repeated_fields(&reply.response);
    objects += refuses_unknown_and_repeated_fields(&rtc.auto_mode_status_array(&state, stamp));
    objects += refuses_unknown_and_repeated_fields(&rtc::AutoModeRequest { enable: true });
    objects += refuses_unknown_and_repeated_fields(&rtc::AutoModeWithModuleRequest {
        module: rtc::Module::default(),
        enable: true,
    });
    objects += refuses_unknown_and_repeated_fields(&rtc.bindings()[0]);
    assert!(objects > 20, "only {objects} objects were tried");
}

// ---------------------------------------------------------------------------------------------
// Identifiers as text
// ---------------------------------------------------------------------------------------------

/// A hyphen counts only where the 8-4-4-4-12 form puts it: 32 characters with hyphens
/// anywhere are not an identifier, nor are 36 with one out of place.
#[test]
fn uuid_text_takes_hyphens_only_in_their_places() {
    for text in [
        "--------------------------------",
        "-000000000000000000000000000abcd",
        "0000000000000000000000000000abc-",
        "00000000-0000-0000-0000-0000000abc",
        "0000000-00000-0000-0000-00000000abcd",
        "00000000-0000-0000-0000-00000000abc-",
    ] {
        assert!(text.parse::<SceneId>().is_err(), "{text}");
        let input = json!({ "Remove": { "id": text, "module": LANE_CHANGE } });
        assert!(serde_json::from_value::<Input>(input).is_err(), "{text}");
    }
    assert_eq!(
        "00000000-0000-0000-0000-00000000abcd".parse(),
        Ok(id(0xabcd))
    );
    assert_eq!("0000000000000000000000000000abcd".parse(), Ok(id(0xabcd)));
}

// ---------------------------------------------------------------------------------------------
// Serialized states
// ---------------------------------------------------------------------------------------------

fn state_json() -> Value {
    serde_json::to_value(busy_state()).expect("serializes")
}

fn read_state(value: Value) -> Result<State, String> {
    serde_json::from_value::<State>(value).map_err(|e| e.to_string())
}

/// A serialized state is read only with limits `State::new` accepts.
#[test]
fn serialized_state_limits_are_those_state_new_accepts() {
    for (limit, message) in [
        ("max_scenes", "max_scenes must be at least 1"),
        ("retired_capacity", "retired_capacity must be at least 1"),
        ("max_batch", "max_batch must be at least 1"),
    ] {
        let mut value = state_json();
        value["limits"][limit] = json!(0);
        let error = read_state(value).expect_err("a zero limit");
        assert!(error.contains(message), "{error}");
    }
}

/// An entry listed twice is refused, where reading it used to keep the last one.
#[test]
fn serialized_state_lists_no_entry_twice() {
    for (list, expected) in [
        ("policies", "is listed twice"),
        ("scenes", "is listed twice"),
        ("retired", "is listed twice"),
        ("retired_order", "RETIRED-ORDER"),
    ] {
        let mut value = state_json();
        let entries = value[list].as_array_mut().expect("a list");
        let first = entries[0].clone();
        entries.push(first);
        let error = read_state(value).expect_err("an entry twice");
        assert!(error.contains(list) || list == "retired_order", "{error}");
        assert!(error.contains(expected), "{list}: {error}");
    }
}

/// The example that used to get through: a retired identifier listed twice, with a capacity
/// of one, read as one; a `Remove` then retired a second and broke `[COOP-INV-RETIRED-BOUND.1]`.
#[test]
fn a_state_read_back_stays_within_its_invariants() {
    let mut value = state_json();
    value["limits"]["retired_capacity"] = json!(1);
    let retired = value["retired"][0].clone();
    value["retired"]
        .as_array_mut()
        .expect("a list")
        .push(retired);
    assert!(read_state(value).is_err());
}

/// Every invariant the core keeps is checked on reading: a scene that is both live and
/// retired is refused.
#[test]
fn a_state_the_core_cannot_reach_is_refused() {
    let mut value = state_json();
    let live = value["scenes"][0][0].clone();
    value["retired"][0][0] = live.clone();
    value["retired_order"][0] = live;
    let error = read_state(value).expect_err("live and retired");
    assert!(error.contains("DISJOINT"), "{error}");
}

// ---------------------------------------------------------------------------------------------
// Floats
// ---------------------------------------------------------------------------------------------

proptest! {
    /// Every distance and pose coordinate, NaNs and infinities included, reads back with the
    /// bits it was written with, so a state holding any geometry reads back equal.
    #[test]
    fn every_float_reads_back_exactly(
        distances in proptest::array::uniform2(any::<u32>()),
        coordinates in proptest::array::uniform7(any::<u64>()),
    ) {
        let [x, y, z, qx, qy, qz, qw] = coordinates.map(f64::from_bits);
        let pose = Pose { position: [x, y, z], orientation: [qx, qy, qz, qw] };
        let geometry = Geometry::Steering {
            poses: [pose, Pose::default()],
            distances: distances.map(|bits| Distance(f32::from_bits(bits))),
            direction: Direction::Straight,
            status: SteeringStatus::Turning,
        };
        let mut state = state();
        state.apply(&Input::Register { id: id(9), module: LANE_CHANGE, report: Report::new(Decision::Activate, geometry) }).expect("registers");
        let text = serde_json::to_string(&state).expect("serializes");
        prop_assert_eq!(serde_json::from_str::<State>(&text).expect("reads back"), state);
    }
}

/// The written forms of the floats JSON has no number for.
#[test]
fn non_finite_floats_have_written_forms() {
    let write = |d: f32| serde_json::to_string(&Distance(d)).expect("serializes");
    assert_eq!(write(f32::INFINITY), r#""inf""#);
    assert_eq!(write(f32::NEG_INFINITY), r#""-inf""#);
    assert_eq!(write(f32::NAN), r#""NaN:0x7fc00000""#);
    assert_eq!(write(-f32::NAN), r#""NaN:0xffc00000""#);
    let pose = Pose {
        position: [f64::NAN, 0.0, 0.0],
        orientation: [0.0; 4],
    };
    let text = serde_json::to_string(&pose).expect("serializes");
    assert!(text.contains(r#""NaN:0x7ff8000000000000""#), "{text}");
    for bad in [
        r#""nan""#,
        r#""NaN""#,
        r#""NaN:0x7f800000""#,
        r#""NaN:0x7FC00000""#,
        r#""Infinity""#,
        "null",
    ] {
        assert!(serde_json::from_str::<Distance>(bad).is_err(), "{bad}");
    }
}

/// A number beyond the range of a distance's `f32` is refused, not read as an infinity; the
/// largest `f32`, as it is written, reads back.
#[test]
fn a_distance_beyond_f32_is_refused() {
    let error = serde_json::from_str::<Distance>("1e39").expect_err("out of range");
    assert!(error.to_string().contains("fits a 32-bit float"), "{error}");
    assert!(serde_json::from_str::<Distance>("-1e39").is_err());
    let max = serde_json::to_string(&Distance(f32::MAX)).expect("serializes");
    assert_eq!(
        serde_json::from_str::<Distance>(&max).expect("reads back"),
        Distance(f32::MAX)
    );
}

// ---------------------------------------------------------------------------------------------
// RTC: arithmetic at the extremes, and one base64
// ---------------------------------------------------------------------------------------------

/// The adapter's bound on its routes adds the live count and the retired capacity: with the
/// largest capacity `State::new` accepts, it saturates instead of overflowing.
#[test]
fn rtc_route_bound_saturates_at_the_largest_capacity() {
    let mut rtc = Rtc::standard();
    let mut config = Config::new(rtc.policies(false));
    config.limits.retired_capacity = usize::MAX;
    let mut state = State::new(config).expect("valid");
    let mut interface = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    interface
        .update_cooperate_status(id(1), true, rtc::State::RUNNING, 1.0, 2.0, false)
        .expect("registers");
    interface.remove_cooperate_status(id(1)).expect("removes");
    rtc.tick(&mut state, 1).expect("ticks");
    assert_eq!(rtc.route_count(), 1);
}

/// A stamp moved back saturates at both ends of the representable times, whatever its
/// `nanosec`; and no message is read with a `nanosec` of a second or more.
#[test]
fn rtc_time_saturates_and_nanosec_stays_below_a_second() {
    let latest = rtc::Time::new(i32::MAX, 999_999_999);
    assert_eq!(rtc::Time::new(i32::MAX, u32::MAX).before_ms(0), latest);
    assert_eq!(rtc::Time::new(i32::MAX, u32::MAX).before_ms(1), latest);
    assert_eq!(
        rtc::Time::new(0, 1_500_000_000).before_ms(0),
        rtc::Time::new(1, 500_000_000)
    );
    assert_eq!(
        rtc::Time::new(i32::MIN, 0).before_ms(u64::MAX),
        rtc::Time::new(i32::MIN, 0)
    );
    let error = serde_json::from_value::<rtc::Time>(json!({ "sec": 1, "nanosec": 1_000_000_000 }))
        .expect_err("a whole second");
    assert!(error.to_string().contains("nanosec"), "{error}");
    let time = serde_json::from_value::<rtc::Time>(json!({ "sec": -1, "nanosec": 999_999_999 }));
    assert_eq!(time.expect("in range"), rtc::Time::new(-1, 999_999_999));
    // One type with the AD API's time, read as rosbridge reads it: a field left out is 0.
    let time = serde_json::from_value::<rtc::Time>(json!({ "sec": 5 })).expect("reads");
    assert_eq!(time, rtc::Time::new(5, 0));
    let wire: cooperation::wire::Time = time;
    assert_eq!(wire, cooperation::wire::Time { sec: 5, nanosec: 0 });
}

proptest! {
    /// The RTC and AD API readers take the same base64 strings for a UUID: each byte string's
    /// canonical text, padded or not, and nothing whose last digit sets bits past the data.
    #[test]
    fn rtc_and_wire_read_the_same_base64(bytes in proptest::array::uniform16(any::<u8>()), last in 0u8..64) {
        let canonical = cooperation::wire::Uuid { uuid: bytes.to_vec() }.to_base64();
        let alphabet = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut variant = canonical.clone().into_bytes();
        variant[21] = alphabet[usize::from(last)];
        let variant = String::from_utf8(variant).expect("ASCII");
        for text in [canonical.clone(), canonical.trim_end_matches('=').to_owned(), variant.clone()] {
            let rtc = serde_json::from_value::<rtc::Uuid>(json!({ "uuid": text })).ok().map(|u| u.uuid);
            let wire = serde_json::from_value::<cooperation::wire::Uuid>(json!({ "uuid": text })).ok().map(|u| u.uuid);
            prop_assert_eq!(rtc.map(|b| b.to_vec()), wire.clone(), "{}", text);
            // The last of 22 digits carries 2 bits of data and 4 past its end.
            prop_assert_eq!(wire.is_some(), text != variant || last & 0x0f == 0, "{}", text);
        }
    }
}

/// The example of `docs/wire.md`: `…Dw==` is bytes 0 to 15; `…Dx==` sets bits past them.
#[test]
fn the_documented_base64_example() {
    let read = |text: &str| {
        cooperation::wire::from_json::<cooperation::wire::Uuid>(
            format!(r#"{{"uuid": "{text}"}}"#).as_bytes(),
        )
    };
    let bytes: Vec<u8> = (0..16).collect();
    assert_eq!(
        read("AAECAwQFBgcICQoLDA0ODw==").expect("canonical").uuid,
        bytes
    );
    let error = read("AAECAwQFBgcICQoLDA0ODx==").expect_err("stray bits");
    assert!(
        error.to_string().contains("past the end of the data"),
        "{error}"
    );
}
