//! The ROS interface definitions in `server/msg/` and `server/srv/` name exactly the fields the
//! node reads and writes: each message's fields are its serialized keys, and the
//! service's request fields are those the sync reads.

use cooperation_adapters::rtc::Uuid;
use cooperation_server::scenes::{SceneArray, SceneState};
use cooperation_server::sync::{self, Activation, SyncResponse, SyncResult};
use serde::Serialize;
use serde_json::{json, Value};

fn definition(path: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The field names of a definition's lines (comments and blank lines left out).
fn names(text: &str) -> Vec<String> {
    text.lines()
        .map(|line| line.split('#').next().unwrap_or_default().trim())
        .filter(|line| !line.is_empty())
        .map(|line| {
            let mut words = line.split_whitespace();
            let _type = words.next();
            words.next().expect("a field has a name").to_owned()
        })
        .collect()
}

/// The keys a value serializes with, in order.
fn keys(value: &impl Serialize) -> Vec<String> {
    match serde_json::to_value(value).expect("serializes") {
        Value::Object(map) => map.keys().cloned().collect(),
        other => panic!("not an object: {other}"),
    }
}

fn sorted(mut list: Vec<String>) -> Vec<String> {
    list.sort();
    list
}

#[test]
fn each_message_names_the_fields_the_node_writes() {
    let uuid = Uuid::default();
    let result = SyncResult {
        uuid,
        success: true,
        message: String::new(),
    };
    let activation = Activation {
        uuid,
        activated: false,
        force_activated: false,
        force_deactivated: false,
    };
    // serde_json orders an object's keys by name: compare as sets, and the count.
    let cases = [
        ("msg/SyncResult.msg", keys(&result)),
        ("msg/Activation.msg", keys(&activation)),
        ("msg/SceneArray.msg", keys(&SceneArray::default())),
        ("msg/SceneState.msg", keys(&SceneState::default())),
    ];
    for (path, written) in cases {
        assert_eq!(sorted(names(&definition(path))), sorted(written), "{path}");
    }
}

#[test]
fn the_sync_service_names_what_the_node_reads_and_answers() {
    let text = definition("srv/SyncCooperateStatus.srv");
    let (request, response) = text
        .split_once("\n---\n")
        .expect("a request and a response");
    assert_eq!(
        sorted(names(response)),
        sorted(keys(&SyncResponse::default()))
    );
    // A request with exactly the definition's fields reads (the request refuses unknown fields).
    let uuid = json!({"uuid": vec![0_u8; 16]});
    let values = [
        ("interface", json!("intersection")),
        ("statuses", json!([])),
        ("sequences", json!([{"uuid": uuid, "sequence": "change"}])),
        ("removed", json!([uuid])),
    ];
    let request_names = names(request);
    assert_eq!(request_names.len(), values.len(), "{request_names:?}");
    let object: serde_json::Map<String, Value> = request_names
        .iter()
        .map(|name| {
            let value = values
                .iter()
                .find(|(known, _)| known == name)
                .unwrap_or_else(|| panic!("the request does not read {name:?}"))
                .1
                .clone();
            (name.clone(), value)
        })
        .collect();
    let args = Value::Object(object).to_string();
    sync::read_json(args.as_bytes()).expect("the definition's request reads");
    // The sequence message's fields are those a stated sequence reads.
    assert_eq!(
        names(&definition("msg/StatedSequence.msg")),
        ["uuid", "sequence"]
    );
}
