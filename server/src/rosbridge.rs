//! The rosbridge v2 protocol: what a text frame asks, and the frames that answer it.
//!
//! The node answers `call_service`, `subscribe` and `unsubscribe`. Anything it cannot do is
//! answered with a `status` frame at level `error` that names the problem and echoes the
//! request's `id`; a `call_service` that fails is also answered with a `service_response`
//! whose `result` is `false`, so a client waiting for it is not left waiting.

use cooperation_ros::wire::Service;
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;

use crate::node::{Node, Topic};
use crate::sync;

/// What the connection does after a frame.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Action {
    /// Send this frame to the client.
    Send(String),
    /// Start sending the topic's publications.
    Subscribe(Topic),
    /// Stop.
    Unsubscribe(Topic),
}

/// The fields of a rosbridge frame the node reads; others (`compression`, `throttle_rate`,
/// `queue_length`, `fragment_size`) are accepted and not used.
#[derive(Deserialize)]
struct Envelope<'a> {
    op: String,
    #[serde(borrow, default)]
    id: Option<&'a RawValue>,
    #[serde(default)]
    service: Option<String>,
    #[serde(default)]
    topic: Option<String>,
    #[serde(default, rename = "type")]
    r#type: Option<String>,
    #[serde(borrow, default)]
    args: Option<&'a RawValue>,
}

#[derive(Serialize)]
struct Status<'a> {
    op: &'static str,
    level: &'static str,
    msg: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    id: Option<&'a RawValue>,
}

#[derive(Serialize)]
struct ServiceResponse<'a, V: Serialize + ?Sized> {
    op: &'static str,
    service: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    id: Option<&'a RawValue>,
    values: &'a V,
    result: bool,
}

/// A `status` frame at level `error`.
#[must_use]
pub fn error_status(msg: &str, id: Option<&RawValue>) -> String {
    let status = Status {
        op: "status",
        level: "error",
        msg,
        id,
    };
    serde_json::to_string(&status).unwrap_or_default()
}

/// The services the node answers, with their types.
const SYNC: (&str, &str) = (sync::NAME, sync::TYPE);

/// Whether a type a client names is `expected`, in ROS 2 form (`pkg/msg/Name`) or ROS 1 form
/// (`pkg/Name`).
fn same_type(given: &str, expected: &str) -> bool {
    given == expected || given == expected.replacen("/msg/", "/", 1).replacen("/srv/", "/", 1)
}

/// The fields of a frame that does not read as an [`Envelope`], read leniently, so that its
/// refusal can echo its `id` and a `call_service` can be answered.
#[derive(Deserialize)]
struct Salvage<'a> {
    #[serde(borrow, default)]
    op: Option<&'a RawValue>,
    #[serde(borrow, default)]
    id: Option<&'a RawValue>,
    #[serde(borrow, default)]
    service: Option<&'a RawValue>,
}

/// The refusal of a frame the node will not handle: a `status` naming `msg` with the frame's
/// `id` when it has one, and for a `call_service` also a failed `service_response`, so a
/// client waiting for it is not left waiting.
#[must_use]
pub fn refuse(frame: &str, msg: &str) -> Vec<Action> {
    let salvage = is_object(frame)
        .then(|| serde_json::from_str::<Salvage<'_>>(frame).ok())
        .flatten();
    let Some(salvage) = salvage else {
        return vec![Action::Send(error_status(msg, None))];
    };
    let calls = salvage.op.is_some_and(|op| op.get() == r#""call_service""#);
    if !calls {
        return vec![Action::Send(error_status(msg, salvage.id))];
    }
    let service = salvage
        .service
        .and_then(|service| serde_json::from_str::<String>(service.get()).ok())
        .unwrap_or_default();
    failed_call(&service, salvage.id, msg)
}

/// A `status` and a `service_response` with `result: false`, both saying `msg`.
fn failed_call(service: &str, id: Option<&RawValue>, msg: &str) -> Vec<Action> {
    let response = ServiceResponse {
        op: "service_response",
        service,
        id,
        values: msg,
        result: false,
    };
    vec![
        Action::Send(error_status(msg, id)),
        Action::Send(serde_json::to_string(&response).unwrap_or_default()),
    ]
}

/// Whether a frame is a JSON object, as rosbridge frames are. (Serde would also read a
/// struct from a list of its fields' values, which no rosbridge client sends.)
fn is_object(frame: &str) -> bool {
    frame.trim_start().starts_with('{')
}

/// The node's answer to one text frame, and, if it changed the core, the revision of the
/// state it made: send the answer once the streams show it ([`Node::published`]), so that
/// the client's next publication shows its change.
#[must_use]
pub fn handle(node: &Node, frame: &str) -> (Vec<Action>, Option<u64>) {
    if !is_object(frame) {
        let msg = match serde_json::from_str::<&RawValue>(frame) {
            Ok(_) => "not a rosbridge frame: a frame is a JSON object".to_owned(),
            Err(error) => format!("not JSON: {error}"),
        };
        return (vec![Action::Send(error_status(&msg, None))], None);
    }
    let envelope: Envelope<'_> = match serde_json::from_str(frame) {
        Ok(envelope) => envelope,
        Err(error) => {
            let msg = if serde_json::from_str::<&RawValue>(frame).is_ok() {
                format!("not a rosbridge frame: {error}")
            } else {
                format!("not JSON: {error}")
            };
            return (refuse(frame, &msg), None);
        }
    };
    if envelope.op == "call_service" {
        return call_service(node, &envelope);
    }
    (others(&envelope), None)
}

/// The answer to a frame that is not a service call: a subscription, or a refusal.
fn others(envelope: &Envelope<'_>) -> Vec<Action> {
    let id = envelope.id;
    let refuse = |msg: &str| vec![Action::Send(error_status(msg, id))];
    match envelope.op.as_str() {
        "subscribe" | "unsubscribe" => {
            let Some(name) = envelope.topic.as_deref() else {
                return refuse(&format!("{} without a topic", envelope.op));
            };
            let Some(topic) = Topic::from_name(name) else {
                return refuse(&format!(
                    "no topic {name:?}: this node publishes {:?} and {:?}",
                    Topic::Velocity.name(),
                    Topic::Steering.name()
                ));
            };
            if let Some(given) = envelope.r#type.as_deref() {
                if !given.is_empty() && !same_type(given, topic.type_name()) {
                    return refuse(&format!(
                        "topic {name:?} has type {:?}, not {given:?}",
                        topic.type_name()
                    ));
                }
            }
            if envelope.op == "subscribe" {
                vec![Action::Subscribe(topic)]
            } else {
                vec![Action::Unsubscribe(topic)]
            }
        }
        "advertise" | "unadvertise" | "publish" => refuse(&format!(
            "op {:?}: this node takes no publications; planning modules call {:?}",
            envelope.op,
            sync::NAME
        )),
        op => refuse(&format!(
            "unknown op {op:?}: this node answers call_service, subscribe and unsubscribe"
        )),
    }
}

fn call_service(node: &Node, envelope: &Envelope<'_>) -> (Vec<Action>, Option<u64>) {
    let id = envelope.id;
    let name = envelope.service.as_deref().unwrap_or_default();
    let failed = |msg: &str| (failed_call(name, id, msg), None);
    if envelope.service.is_none() {
        return failed("call_service without a service");
    }
    let ad_api = Service::from_name(name);
    let type_name = match ad_api {
        Some(service) => service.type_name(),
        None if name == SYNC.0 => SYNC.1,
        None => {
            let known: Vec<&str> = Service::ALL.iter().map(|s| s.name()).collect();
            return failed(&format!(
                "no service {name:?}: this node answers {}, and {:?} for planning modules",
                known.join(", "),
                SYNC.0
            ));
        }
    };
    if let Some(given) = envelope.r#type.as_deref() {
        if !given.is_empty() && !same_type(given, type_name) {
            return failed(&format!(
                "service {name:?} has type {type_name:?}, not {given:?}"
            ));
        }
    }
    let args = envelope.args.map_or("{}", RawValue::get).as_bytes();
    // An empty argument list is how some clients write an empty request.
    let args = if args == b"[]" {
        b"{}".as_slice()
    } else {
        args
    };
    // Each request is read before the core's lock is taken, and its response written once,
    // inside the frame that carries it.
    match ad_api {
        Some(service) => match service.read(args) {
            Ok(request) => {
                let (response, revision) = node.call(&request);
                (vec![respond(name, id, &response)], revision)
            }
            Err(malformed) => (vec![respond(name, id, &service.refusal(&malformed))], None),
        },
        None => {
            let response = match sync::read(args) {
                Ok(request) => node.sync(&request),
                Err(message) => sync::refused(message),
            };
            (vec![respond(name, id, &response)], None)
        }
    }
}

/// A successful `service_response` carrying `values`.
fn respond<V: Serialize>(service: &str, id: Option<&RawValue>, values: &V) -> Action {
    let response = ServiceResponse {
        op: "service_response",
        service,
        id,
        values,
        result: true,
    };
    Action::Send(serde_json::to_string(&response).unwrap_or_default())
}
