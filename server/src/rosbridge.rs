//! The rosbridge v2 protocol: what a text frame asks, and the frames that answer it.
//!
//! The node answers `call_service`, `subscribe` and `unsubscribe`, within what the
//! connection's [`Grant`] lets it do. Anything it cannot do is answered with a `status` frame at
//! level `error` that names the problem and echoes the request's `id`; a `call_service` that
//! fails is also answered with a `service_response` whose `result` is `false`, so a client
//! waiting for it is not left waiting. No field of a request is ignored silently: one the node
//! does not support (`compression` other than `none`, `fragment_size`) is refused, and a
//! `queue_length` over 1 is answered with a `status` at level `warning` saying what is done.

use std::time::Duration;

use cooperation_adapters::engine::{Endpoint, Request};
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;

use crate::auth::Grant;
use crate::node::{Node, Topic};
use crate::rosapi;
use cooperation_adapters::sync;

/// What the connection does after a frame.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Action {
    /// Send this frame to the client.
    Send(String),
    /// A subscription to the topic, by its `id` (the JSON text of the `id`, `None` without),
    /// sent at most once per `throttle`.
    Subscribe {
        /// The topic.
        topic: Topic,
        /// The subscription's `id`.
        id: Option<String>,
        /// Its `throttle_rate`.
        throttle: Duration,
    },
    /// The end of the subscription `id` to the topic; of every one of them without an `id`.
    Unsubscribe {
        /// The topic.
        topic: Topic,
        /// The subscription's `id`.
        id: Option<String>,
    },
}

/// The fields of a rosbridge frame the node reads; others are not read.
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
    /// Milliseconds between publications, at least.
    #[serde(default)]
    throttle_rate: Option<u64>,
    #[serde(default)]
    queue_length: Option<u64>,
    #[serde(default)]
    compression: Option<String>,
    #[serde(default)]
    fragment_size: Option<u64>,
}

impl Envelope<'_> {
    /// Why the frame asks for something the node does not do: a compression other than
    /// `none`, or fragments.
    fn unsupported(&self) -> Option<String> {
        if let Some(compression) = self.compression.as_deref() {
            if !compression.is_empty() && compression != "none" {
                return Some(format!(
                    "compression {compression:?}: this node sends JSON text only (compression \"none\")"
                ));
            }
        }
        self.fragment_size.map(|size| {
            format!("fragment_size {size}: this node sends every message whole; leave fragment_size out")
        })
    }
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
    status("error", msg, id)
}

fn status(level: &'static str, msg: &str, id: Option<&RawValue>) -> String {
    let status = Status {
        op: "status",
        level,
        msg,
        id,
    };
    serde_json::to_string(&status).unwrap_or_default()
}

/// Whether a type a client names is `expected`, in ROS 2 form (`pkg/msg/Name`) or ROS 1 form
/// (`pkg/Name`; `rosapi_msgs`'s services were in the package `rosapi` there).
pub(crate) fn same_type(given: &str, expected: &str) -> bool {
    let ros1 = expected.replacen("/msg/", "/", 1).replacen("/srv/", "/", 1);
    given == expected
        || given == ros1
        || ros1
            .strip_prefix("rosapi_msgs/")
            .is_some_and(|name| given.strip_prefix("rosapi/") == Some(name))
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
pub fn handle(node: &Node, frame: &str, grant: &Grant) -> (Vec<Action>, Option<u64>) {
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
        return call_service(node, &envelope, grant);
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
                let names: Vec<&str> = Topic::ALL.iter().map(|t| t.name()).collect();
                return refuse(&format!(
                    "no topic {name:?}: this node publishes {}",
                    names.join(", ")
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
            let sub_id = id.map(|id| id.get().to_owned());
            if envelope.op == "unsubscribe" {
                return vec![Action::Unsubscribe { topic, id: sub_id }];
            }
            if let Some(unsupported) = envelope.unsupported() {
                return refuse(&unsupported);
            }
            let mut actions = Vec::new();
            if let Some(length) = envelope.queue_length.filter(|length| *length > 1) {
                actions.push(Action::Send(status(
                    "warning",
                    &format!(
                        "queue_length {length}: this node keeps only the newest publication of a \
                         topic for each subscriber, as queue_length 1"
                    ),
                    id,
                )));
            }
            actions.push(Action::Subscribe {
                topic,
                id: sub_id,
                throttle: Duration::from_millis(envelope.throttle_rate.unwrap_or(0)),
            });
            actions
        }
        "auth" => refuse(
            "op \"auth\": this node takes a credential when the WebSocket opens, as an \
             Authorization: Bearer header or the URL's token parameter (docs/server.md)",
        ),
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

fn call_service(node: &Node, envelope: &Envelope<'_>, grant: &Grant) -> (Vec<Action>, Option<u64>) {
    let id = envelope.id;
    let name = envelope.service.as_deref().unwrap_or_default();
    let failed = |msg: &str| (failed_call(name, id, msg), None);
    if envelope.service.is_none() {
        return failed("call_service without a service");
    }
    if let Some(unsupported) = envelope.unsupported() {
        return failed(&unsupported);
    }
    let args = envelope.args.map_or("{}", RawValue::get).as_bytes();
    // An empty argument list is how some clients write an empty request.
    let args = if args == b"[]" {
        b"{}".as_slice()
    } else {
        args
    };
    if rosapi::SERVICES.contains(&name) {
        let given = envelope.r#type.as_deref().unwrap_or_default();
        if !given.is_empty() && !same_type(given, &rosapi::ros_type(name)) {
            return failed(&format!("service {name:?} has no type {given:?}"));
        }
        return match rosapi::answer(name, args, &node.endpoints()) {
            Some(Ok(values)) => (vec![respond(name, id, &values)], None),
            Some(Err(message)) => failed(&message),
            None => failed(&format!("no service {name:?}")),
        };
    }
    let Some(endpoint) = Endpoint::from_name(name) else {
        let known: Vec<&str> = Endpoint::ALL.iter().map(|e| e.name()).collect();
        return failed(&format!(
            "no service {name:?}: this node answers {} (the last for planning modules), and {}",
            known.join(", "),
            rosapi::SERVICES.join(", ")
        ));
    };
    if let Some(given) = envelope.r#type.as_deref() {
        if !given.is_empty() && !same_type(given, endpoint.ros_type()) {
            return failed(&format!(
                "service {name:?} has type {:?}, not {given:?}",
                endpoint.ros_type()
            ));
        }
    }
    if let Err(refusal) = grant.may_call(name) {
        tracing::warn!("a call refused: {refusal}");
        return failed(&refusal);
    }
    // Each request is read before the core's lock is taken, and its response written once,
    // inside the frame that carries it.
    let request = endpoint.read_json(args);
    if let Request::Sync(sync) = &request {
        if let Err(refusal) = grant.may_report(&sync.interface) {
            tracing::warn!("a sync refused: {refusal}");
            return (vec![respond(name, id, &sync::refused(refusal))], None);
        }
    }
    let (reply, revision) = node.handle(request);
    // An operator's call is answered once the streams show its change; a module's sync at once
    // (its answer carries what it needs), its change published soon.
    if endpoint == Endpoint::Sync {
        if revision.is_some() {
            node.publish_soon();
        }
        return (vec![respond(name, id, &reply)], None);
    }
    (vec![respond(name, id, &reply)], revision)
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

#[cfg(test)]
mod tests {
    use super::same_type;
    use crate::rosapi;

    #[test]
    fn a_type_is_named_in_ros_2_or_ros_1_form() {
        let factors = "autoware_adapi_v1_msgs/msg/VelocityFactorArray";
        assert!(same_type(factors, factors));
        assert!(same_type(
            "autoware_adapi_v1_msgs/VelocityFactorArray",
            factors
        ));
        assert!(!same_type(
            "autoware_adapi_v1_msgs/SteeringFactorArray",
            factors
        ));
        assert!(!same_type("", factors));
        let topic_type = rosapi::ros_type("/rosapi/topic_type");
        assert_eq!(topic_type, "rosapi_msgs/srv/TopicType");
        // rosapi's services were in the package `rosapi` in ROS 1, as roslibjs still names them.
        for given in [
            "rosapi_msgs/srv/TopicType",
            "rosapi_msgs/TopicType",
            "rosapi/TopicType",
        ] {
            assert!(same_type(given, &topic_type), "{given}");
        }
        assert!(!same_type("rosapi/Topics", &topic_type));
        assert!(!same_type("rosapi/TopicType", factors));
    }
}
