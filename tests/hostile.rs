//! Hostile input at the core's own boundaries: identifiers as text, the serde forms of the core
//! types (unknown fields, repeated fields, states the core cannot reach, floats JSON has no
//! number for), and arithmetic on limits at their extremes. Each test names the class of input
//! it refuses or survives. The adapters' forms are `adapters/tests/hostile.rs`.

use crate::common::forms::refuses_unknown_and_repeated_fields;
use crate::common::*;
use cooperation::*;
use proptest::prelude::*;
use serde_json::{json, Value};

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

/// Every input, the serialized state, and each output type:
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
