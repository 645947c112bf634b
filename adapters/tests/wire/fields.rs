//! The wire module against the message definitions (`adapters/tests/data/messages.txt`): every JSON
//! field name, in order and of the right kind, and every constant with its value and width; and
//! that every message refuses each of its fields given twice.

use std::collections::BTreeMap;
use std::fmt;

use cooperation_adapters::wire::{self, Malformed};
use cooperation_adapters::Time;
use serde::de::{Deserialize, Deserializer, IgnoredAny, MapAccess, Visitor};
use serde_json::Value;

/// One message definition.
#[derive(Debug, Default)]
struct Definition {
    /// (type, name), in order.
    fields: Vec<(String, String)>,
    /// name → (type, value as written).
    constants: BTreeMap<String, (String, String)>,
}

fn definitions() -> BTreeMap<String, Definition> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/data/messages.txt");
    let text = std::fs::read_to_string(path).expect("readable");
    let mut definitions = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        if let Some(entry) = line.strip_prefix("  ") {
            let name = current.clone().expect("an entry inside a block");
            let definition: &mut Definition = definitions.get_mut(&name).unwrap();
            let (declaration, value) = match entry.split_once(" = ") {
                Some((declaration, value)) => (declaration, Some(value)),
                None => (entry, None),
            };
            let (ty, field) = declaration.split_once(' ').expect("TYPE NAME");
            match value {
                Some(value) => {
                    let old = definition
                        .constants
                        .insert(field.to_owned(), (ty.to_owned(), value.to_owned()));
                    assert!(old.is_none(), "{name}.{field} twice");
                }
                None => definition.fields.push((ty.to_owned(), field.to_owned())),
            }
        } else {
            let old = definitions.insert(line.to_owned(), Definition::default());
            assert!(old.is_none(), "{line} twice");
            current = Some(line.to_owned());
        }
    }
    definitions
}

/// A JSON object's keys in the order written.
struct Keys(Vec<String>);

impl<'de> Deserialize<'de> for Keys {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct KeysVisitor;
        impl<'de> Visitor<'de> for KeysVisitor {
            type Value = Keys;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Keys, A::Error> {
                let mut keys = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    map.next_value::<IgnoredAny>()?;
                    keys.push(key);
                }
                Ok(Keys(keys))
            }
        }
        deserializer.deserialize_map(KeysVisitor)
    }
}

/// The JSON the wire module writes for a default instance of each message, by full name.
fn written() -> BTreeMap<&'static str, Vec<u8>> {
    use wire::*;
    fn json<T: serde::Serialize + Default>() -> Vec<u8> {
        wire::to_json(&T::default())
    }
    BTreeMap::from([
        ("builtin_interfaces/Time", json::<Time>()),
        ("std_msgs/Header", json::<Header>()),
        ("geometry_msgs/Point", json::<Point>()),
        ("geometry_msgs/Quaternion", json::<Quaternion>()),
        ("geometry_msgs/Pose", json::<Pose>()),
        ("unique_identifier_msgs/UUID", json::<Uuid>()),
        (
            "autoware_adapi_v1_msgs/CooperationDecision",
            json::<CooperationDecision>(),
        ),
        (
            "autoware_adapi_v1_msgs/CooperationStatus",
            json::<CooperationStatus>(),
        ),
        (
            "autoware_adapi_v1_msgs/CooperationCommand",
            json::<CooperationCommand>(),
        ),
        (
            "autoware_adapi_v1_msgs/CooperationPolicy",
            json::<CooperationPolicy>(),
        ),
        (
            "autoware_adapi_v1_msgs/VelocityFactor",
            json::<VelocityFactor>(),
        ),
        (
            "autoware_adapi_v1_msgs/VelocityFactorArray",
            json::<VelocityFactorArray>(),
        ),
        (
            "autoware_adapi_v1_msgs/SteeringFactor",
            json::<SteeringFactor>(),
        ),
        (
            "autoware_adapi_v1_msgs/SteeringFactorArray",
            json::<SteeringFactorArray>(),
        ),
        (
            "autoware_adapi_v1_msgs/ResponseStatus",
            json::<ResponseStatus>(),
        ),
        (
            "autoware_adapi_v1_msgs/SetCooperationCommands_Request",
            json::<SetCooperationCommandsRequest>(),
        ),
        (
            "autoware_adapi_v1_msgs/SetCooperationCommands_Response",
            json::<SetCooperationCommandsResponse>(),
        ),
        (
            "autoware_adapi_v1_msgs/SetCooperationPolicies_Request",
            json::<SetCooperationPoliciesRequest>(),
        ),
        (
            "autoware_adapi_v1_msgs/SetCooperationPolicies_Response",
            json::<SetCooperationPoliciesResponse>(),
        ),
        (
            "autoware_adapi_v1_msgs/GetCooperationPolicies_Request",
            json::<GetCooperationPoliciesRequest>(),
        ),
        (
            "autoware_adapi_v1_msgs/GetCooperationPolicies_Response",
            json::<GetCooperationPoliciesResponse>(),
        ),
    ])
}

/// The messages that only name values (constants, no fields): no wire type is serialized.
const CONSTANTS_ONLY: [&str; 2] = [
    "autoware_adapi_v1_msgs/PlanningBehavior",
    "autoware_adapi_v1_msgs/PlanningSequence",
];

/// Whether a JSON value has the kind a field of type `ty` is written as.
fn has_kind(ty: &str, value: &Value) -> bool {
    if ty.ends_with(']') {
        return value.is_array();
    }
    match ty {
        "bool" => value.is_boolean(),
        "string" => value.is_string(),
        "float32" | "float64" => value.is_f64(),
        "int8" | "int16" | "int32" | "int64" => value.is_i64(),
        "uint8" | "uint16" | "uint32" | "uint64" => value.is_u64(),
        _ => value.is_object(),
    }
}

#[test]
fn json_field_names_are_the_definitions_in_order_and_kind() {
    let definitions = definitions();
    let written = written();
    for (name, definition) in &definitions {
        if CONSTANTS_ONLY.contains(&name.as_str()) {
            assert!(definition.fields.is_empty(), "{name} has fields");
            assert!(!written.contains_key(name.as_str()));
            continue;
        }
        let text = written
            .get(name.as_str())
            .unwrap_or_else(|| panic!("no wire type for {name}"));
        let Keys(keys) = serde_json::from_slice(text).unwrap();
        let names: Vec<&str> = definition.fields.iter().map(|(_, n)| n.as_str()).collect();
        assert_eq!(keys, names, "{name}: {}", String::from_utf8_lossy(text));
        let value: Value = serde_json::from_slice(text).unwrap();
        for (ty, field) in &definition.fields {
            assert!(
                has_kind(ty, &value[field]),
                "{name}.{field}: {ty} written as {}",
                value[field]
            );
            // A field of a message type: that message is defined here too.
            let element = ty.split('[').next().unwrap();
            if !has_kind(element, &Value::Object(Default::default())) {
                continue;
            }
            assert!(
                definitions.contains_key(element),
                "{name}.{field}: {element} undefined"
            );
        }
        // And the wire type reads back what it wrote, but nothing else: an unknown field is
        // refused, as rosbridge refuses one.
        let mut with_extra = value.clone();
        if let Value::Object(map) = &mut with_extra {
            map.insert("not_a_field".into(), Value::Null);
        }
        let extra = serde_json::to_vec(&with_extra).unwrap();
        let result = read_as(name, &extra);
        assert!(
            result
                .as_ref()
                .is_err_and(|e| e.contains("unknown field `not_a_field`")),
            "{name}: {result:?}"
        );
        assert_eq!(read_as(name, text), Ok(()), "{name}");
    }
    for name in written.keys() {
        assert!(definitions.contains_key(*name), "{name} is not defined");
    }
}

/// Reads `text` as the wire type of the message `name`.
fn read_as(name: &str, text: &[u8]) -> Result<(), String> {
    use wire::*;
    fn read<T: serde::de::DeserializeOwned>(text: &[u8]) -> Result<(), String> {
        wire::from_json::<T>(text)
            .map(drop)
            .map_err(|e| e.to_string())
    }
    match name.rsplit('/').next().unwrap() {
        "Time" => read::<Time>(text),
        "Header" => read::<Header>(text),
        "Point" => read::<Point>(text),
        "Quaternion" => read::<Quaternion>(text),
        "Pose" => read::<Pose>(text),
        "UUID" => read::<Uuid>(text),
        "CooperationDecision" => read::<CooperationDecision>(text),
        "CooperationStatus" => read::<CooperationStatus>(text),
        "CooperationCommand" => read::<CooperationCommand>(text),
        "CooperationPolicy" => read::<CooperationPolicy>(text),
        "VelocityFactor" => read::<VelocityFactor>(text),
        "VelocityFactorArray" => read::<VelocityFactorArray>(text),
        "SteeringFactor" => read::<SteeringFactor>(text),
        "SteeringFactorArray" => read::<SteeringFactorArray>(text),
        "ResponseStatus" => read::<ResponseStatus>(text),
        "SetCooperationCommands_Request" => read::<SetCooperationCommandsRequest>(text),
        "SetCooperationCommands_Response" => read::<SetCooperationCommandsResponse>(text),
        "SetCooperationPolicies_Request" => read::<SetCooperationPoliciesRequest>(text),
        "SetCooperationPolicies_Response" => read::<SetCooperationPoliciesResponse>(text),
        "GetCooperationPolicies_Request" => read::<GetCooperationPoliciesRequest>(text),
        "GetCooperationPolicies_Response" => read::<GetCooperationPoliciesResponse>(text),
        other => panic!("no wire type for {other}"),
    }
}

/// The wire module's constants: `(message, name, type, value)`, type as ROS spells it.
fn constants() -> Vec<(&'static str, &'static str, &'static str, String)> {
    fn ros_type<T: 'static>(_: &T) -> &'static str {
        let id = std::any::TypeId::of::<T>();
        if id == std::any::TypeId::of::<u8>() {
            "uint8"
        } else if id == std::any::TypeId::of::<u16>() {
            "uint16"
        } else if id == std::any::TypeId::of::<&str>() {
            "string"
        } else {
            "unexpected"
        }
    }
    fn written<T: fmt::Debug + 'static>(value: T) -> (&'static str, String) {
        (ros_type(&value), format!("{value:?}"))
    }
    macro_rules! constants {
        ($message:literal: $ty:ident { $($name:ident),* $(,)? }) => {
            vec![$({
                let (ty, value) = written(wire::$ty::$name);
                (concat!("autoware_adapi_v1_msgs/", $message), stringify!($name), ty, value)
            }),*]
        };
    }
    [
        constants!("CooperationDecision": CooperationDecision {
            UNKNOWN, DEACTIVATE, ACTIVATE, AUTONOMOUS, UNDECIDED,
        }),
        constants!("CooperationPolicy": CooperationPolicy { OPTIONAL, REQUIRED }),
        constants!("PlanningBehavior": PlanningBehavior {
            UNKNOWN, AVOIDANCE, CROSSWALK, GOAL_PLANNER, INTERSECTION, LANE_CHANGE, MERGE,
            NO_DRIVABLE_LANE, NO_STOPPING_AREA, REAR_CHECK, ROUTE_OBSTACLE, SIDEWALK,
            START_PLANNER, STOP_SIGN, SURROUNDING_OBSTACLE, TRAFFIC_SIGNAL,
            USER_DEFINED_DETECTION_AREA, VIRTUAL_TRAFFIC_LIGHT, RUN_OUT, ADAPTIVE_CRUISE,
            ROUNDABOUT,
        }),
        constants!("PlanningSequence": PlanningSequence { CHANGE, RETURN }),
        constants!("VelocityFactor": VelocityFactor { UNKNOWN, APPROACHING, STOPPED }),
        constants!("SteeringFactor": SteeringFactor {
            UNKNOWN, LEFT, RIGHT, STRAIGHT, APPROACHING, TURNING,
        }),
        constants!("ResponseStatus": ResponseStatus {
            UNKNOWN, SERVICE_UNREADY, SERVICE_TIMEOUT, TRANSFORM_ERROR, PARAMETER_ERROR,
            DEPRECATED, NO_EFFECT,
        }),
    ]
    .concat()
}

#[test]
fn constants_are_the_definitions_with_their_values_and_widths() {
    let defined: BTreeMap<(String, String), (String, String)> = definitions()
        .into_iter()
        .flat_map(|(message, definition)| {
            definition
                .constants
                .into_iter()
                .map(move |(name, typed)| ((message.clone(), name), typed))
        })
        .collect();
    let in_code: BTreeMap<(String, String), (String, String)> = constants()
        .into_iter()
        .map(|(message, name, ty, value)| {
            (
                (message.to_owned(), name.to_owned()),
                (ty.to_owned(), value),
            )
        })
        .collect();
    assert_eq!(in_code, defined);
}

#[test]
fn every_behavior_the_core_knows_is_a_planning_behavior_value() {
    let values: Vec<String> = constants()
        .into_iter()
        .filter(|(message, ..)| message.ends_with("/PlanningBehavior"))
        .map(|(.., value)| value.trim_matches('"').to_owned())
        .collect();
    for behavior in cooperation::Behavior::ALL {
        assert!(values.iter().any(|v| v == behavior.as_str()), "{behavior}");
    }
    // Every value but UNKNOWN (the empty string) is a behaviour of the core.
    assert_eq!(values.len(), cooperation::Behavior::ALL.len() + 1);
}

/// What a number field of type `ty` must take and refuse: `(accepted, refused)`.
fn bounds(ty: &str) -> Option<(Vec<Value>, Vec<Value>)> {
    let numbers = |accepted: &[i128], refused: &[i128]| {
        let json = |n: &i128| serde_json::from_str::<Value>(&n.to_string()).unwrap();
        Some((
            accepted.iter().map(json).collect(),
            refused.iter().map(json).collect(),
        ))
    };
    match ty {
        "uint8" => numbers(&[0, 255], &[-1, 256]),
        "uint16" => numbers(&[0, 65_535], &[-1, 65_536]),
        "uint32" => numbers(&[0, 4_294_967_295], &[-1, 4_294_967_296]),
        "int32" => numbers(
            &[-2_147_483_648, 2_147_483_647],
            &[-2_147_483_649, 2_147_483_648],
        ),
        _ => None,
    }
}

/// `builtin_interfaces/Time.nanosec`: a uint32, and below a second.
fn nanosec_bounds() -> Option<(Vec<Value>, Vec<Value>)> {
    let json = |n: i64| Value::from(n);
    Some((
        [0, 999_999_999].map(json).to_vec(),
        [-1, 1_000_000_000, 4_294_967_295, 4_294_967_296]
            .map(json)
            .to_vec(),
    ))
}

/// `element` as the value of a field of type `ty`: itself, or in an array of the right size.
fn as_field(ty: &str, element: Value) -> Value {
    match ty.split_once('[') {
        None => element,
        Some((_, size)) => {
            let fixed = size.trim_end_matches(']').parse::<usize>().unwrap_or(1);
            Value::Array(vec![element; fixed])
        }
    }
}

#[test]
fn number_fields_have_the_definitions_widths() {
    let definitions = definitions();
    let written = written();
    let mut checked = 0;
    for (name, definition) in &definitions {
        let Some(text) = written.get(name.as_str()) else {
            continue;
        };
        let default: Value = serde_json::from_slice(text).unwrap();
        for (ty, field) in &definition.fields {
            let element = ty.split('[').next().unwrap();
            let with = |value: Value| {
                let mut message = default.clone();
                message[field] = as_field(ty, value);
                serde_json::to_vec(&message).unwrap()
            };
            // A time's nanoseconds are within their second: a uint32 below 1 000 000 000.
            let range = if field == "nanosec" {
                nanosec_bounds()
            } else {
                bounds(element)
            };
            if let Some((accepted, refused)) = range {
                for value in accepted {
                    assert_eq!(
                        read_as(name, &with(value.clone())),
                        Ok(()),
                        "{name}.{field} = {value}"
                    );
                }
                for value in refused {
                    let result = read_as(name, &with(value.clone()));
                    assert!(result.is_err(), "{name}.{field} = {value} accepted");
                }
                checked += 1;
            } else if element == "float32" || element == "float64" {
                // 2^24 + 1 is a float64, and no float32: a float32 field rounds it.
                let read = read_back(name, &with(Value::from(16_777_217)));
                let expected = if element == "float32" {
                    16_777_216.0
                } else {
                    16_777_217.0
                };
                assert_eq!(
                    read[field],
                    as_field(ty, Value::from(expected)),
                    "{name}.{field}"
                );
                checked += 1;
            }
        }
    }
    // Every number field of every message: Time 2, Point 3, Quaternion 4, UUID 1, decision 1,
    // policy 1, velocity factor 2, steering factor 3, response status 1.
    assert_eq!(checked, 18);
}

/// Reads `text` as the message `name` and writes it again.
fn read_back(name: &str, text: &[u8]) -> Value {
    use wire::*;
    fn again<T: serde::de::DeserializeOwned + serde::Serialize>(text: &[u8]) -> Value {
        let message: T = wire::from_json(text).unwrap();
        serde_json::from_slice(&wire::to_json(&message)).unwrap()
    }
    match name.rsplit('/').next().unwrap() {
        "Point" => again::<Point>(text),
        "Quaternion" => again::<Quaternion>(text),
        "VelocityFactor" => again::<VelocityFactor>(text),
        "SteeringFactor" => again::<SteeringFactor>(text),
        other => panic!("no float fields in {other}"),
    }
}

/// Every field of `T` given twice, each in turn: refused where the message is, naming the
/// field. Returns how many fields `T` has.
fn each_field_twice<
    T: serde::de::DeserializeOwned + serde::Serialize + Default + std::fmt::Debug,
>() -> usize {
    let serde_json::Value::Object(fields) = serde_json::to_value(T::default()).expect("writes")
    else {
        panic!("a message is an object")
    };
    for (name, value) in &fields {
        let value = value.to_string();
        let text = format!(r#"{{"{name}": {value}, "{name}": {value}}}"#);
        let fault = wire::from_json::<T>(text.as_bytes()).expect_err(&text);
        assert!(
            matches!(fault, Malformed::Shape { .. }),
            "{text}: {fault:?}"
        );
        assert!(fault.path().is_root(), "{text}: {fault}");
        assert!(
            fault
                .to_string()
                .starts_with(&format!("duplicate field `{name}`")),
            "{text}: {fault}"
        );
    }
    fields.len()
}

#[test]
fn a_field_given_twice_is_refused_in_every_message() {
    let counts = [
        each_field_twice::<Time>(),
        each_field_twice::<wire::Header>(),
        each_field_twice::<wire::Point>(),
        each_field_twice::<wire::Quaternion>(),
        each_field_twice::<wire::Pose>(),
        each_field_twice::<wire::Uuid>(),
        each_field_twice::<wire::CooperationDecision>(),
        each_field_twice::<wire::CooperationStatus>(),
        each_field_twice::<wire::CooperationCommand>(),
        each_field_twice::<wire::CooperationPolicy>(),
        each_field_twice::<wire::VelocityFactor>(),
        each_field_twice::<wire::VelocityFactorArray>(),
        each_field_twice::<wire::SteeringFactor>(),
        each_field_twice::<wire::SteeringFactorArray>(),
        each_field_twice::<wire::ResponseStatus>(),
        each_field_twice::<wire::SetCooperationCommandsRequest>(),
        each_field_twice::<wire::SetCooperationCommandsResponse>(),
        each_field_twice::<wire::SetCooperationPoliciesRequest>(),
        each_field_twice::<wire::SetCooperationPoliciesResponse>(),
        each_field_twice::<wire::GetCooperationPoliciesRequest>(),
        each_field_twice::<wire::GetCooperationPoliciesResponse>(),
    ];
    assert_eq!(counts.iter().sum::<usize>(), 52, "{counts:?}");
}
