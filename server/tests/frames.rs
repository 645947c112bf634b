//! Any frame a client can send, generated: the node answers each without panicking, and
//! answers every `call_service` that carries an id with a `service_response` of that id, so no
//! caller is left waiting (`docs/server.md`, *The protocol*).

use cooperation_server::rosbridge::{handle, Action};
use cooperation_server::{Credentials, Grant, Node};
use proptest::prelude::*;
use serde_json::{json, Value};

const SETTINGS: &str = include_str!("../../config/cooperation.param.yaml");

fn node() -> Node {
    let config =
        cooperation_adapters::settings::parse(SETTINGS).expect("the default settings read");
    Node::new(config).expect("the default settings are a configuration")
}

/// JSON values of any shape, small.
fn any_json() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        any::<i64>().prop_map(|n| json!(n)),
        ".{0,12}".prop_map(Value::String),
    ];
    leaf.prop_recursive(3, 24, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(Value::Array),
            prop::collection::btree_map("[a-z_]{1,8}", inner, 0..4)
                .prop_map(|map| Value::Object(map.into_iter().collect())),
        ]
    })
}

/// Frames near the protocol: a known or unknown op, any id, service, topic, type and args.
fn frame() -> impl Strategy<Value = Value> {
    let op = prop_oneof![
        Just(json!("call_service")),
        Just(json!("subscribe")),
        Just(json!("unsubscribe")),
        Just(json!("publish")),
        any_json(),
    ];
    let service = prop_oneof![
        Just(json!("/api/planning/cooperation/set_commands")),
        Just(json!("/api/planning/cooperation/set_policies")),
        Just(json!("/api/planning/cooperation/get_policies")),
        Just(json!("/cooperation/rtc/sync")),
        any_json(),
    ];
    let topic = prop_oneof![Just(json!("/api/planning/velocity_factors")), any_json()];
    (
        op,
        any_json(),
        service,
        topic,
        any_json(),
        any_json(),
        any::<u8>(),
    )
        .prop_map(|(op, id, service, topic, r#type, args, present)| {
            let mut frame = serde_json::Map::new();
            for (bit, key, value) in [
                (1, "op", op),
                (2, "id", id),
                (4, "service", service),
                (8, "topic", topic),
                (16, "type", r#type),
                (32, "args", args),
            ] {
                if present & bit != 0 {
                    frame.insert(key.to_owned(), value);
                }
            }
            Value::Object(frame)
        })
}

/// A connection without a credential, an operator's and a planning module's.
fn grants() -> [Grant; 3] {
    let credentials = Credentials::parse(
        "operator panel abcdefghijklmnopqrstuvwxyz012345\n\
         module lanes bcdefghijklmnopqrstuvwxyz0123456 lane_change_left",
        &["lane_change_left"],
        1,
    )
    .expect("credentials");
    let [operator, module] = credentials.list() else {
        panic!("two credentials")
    };
    [
        Grant::Anyone,
        Grant::Credential(operator.clone()),
        Grant::Credential(module.clone()),
    ]
}

/// Every frame the node sends back, as JSON.
fn sent(actions: &[Action]) -> Vec<Value> {
    actions
        .iter()
        .filter_map(|action| match action {
            Action::Send(text) => Some(serde_json::from_str(text).expect("the node sends JSON")),
            Action::Subscribe { .. } | Action::Unsubscribe { .. } => None,
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn every_frame_is_answered_and_every_call_gets_its_response(frame in frame(), grant in 0..3usize) {
        let node = node();
        let text = frame.to_string();
        let (actions, _) = handle(&node, &text, &grants()[grant]);
        prop_assert!(!actions.is_empty(), "no answer to {text}");
        let sent = sent(&actions);
        let is_call = frame.get("op") == Some(&json!("call_service"));
        if let (true, Some(id)) = (is_call, frame.get("id")) {
            let response = sent.iter().find(|f| f["op"] == "service_response");
            prop_assert!(response.is_some(), "no service_response to {text}: {sent:?}");
            prop_assert_eq!(&response.expect("checked")["id"], id);
        }
        for status in sent.iter().filter(|f| f["op"] == "status") {
            prop_assert_eq!(&status["level"], "error");
            prop_assert!(status["msg"].as_str().is_some_and(|m| !m.is_empty()));
        }
    }

    #[test]
    fn any_text_is_answered_without_panicking(text in ".{0,64}", grant in 0..3usize) {
        let node = node();
        prop_assert!(!handle(&node, &text, &grants()[grant]).0.is_empty(), "no answer to {:?}", text);
    }
}
