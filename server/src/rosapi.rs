//! The parts of rosbridge's `rosapi` a client uses to find its way: which topics and services
//! the node has, and their types. `roslibpy`'s `get_topics`, `get_services`, `get_topic_type`,
//! `get_service_type`, `get_topics_for_type`, `get_services_for_type` and `get_nodes` call
//! these. Every other `rosapi` service is refused as a service the node does not have.

use cooperation_adapters::engine::Endpoint;
use serde::Deserialize;
use serde_json::{json, Value};

use crate::node::Topic;

/// The services of `rosapi` the node answers.
pub const SERVICES: [&str; 7] = [
    "/rosapi/topics",
    "/rosapi/topic_type",
    "/rosapi/topics_for_type",
    "/rosapi/services",
    "/rosapi/service_type",
    "/rosapi/services_for_type",
    "/rosapi/nodes",
];

/// The node's name in the ROS graph, as `rosapi/nodes` lists it.
pub const NODE: &str = "/cooperation_server";

/// The type of the `rosapi` service `service`, in ROS 2 form: `rosapi_msgs/srv/TopicType` for
/// `/rosapi/topic_type`.
#[must_use]
pub fn ros_type(service: &str) -> String {
    format!("rosapi_msgs/srv/{}", camel(service))
}

/// `TopicType` for `/rosapi/topic_type`.
fn camel(service: &str) -> String {
    service
        .trim_start_matches("/rosapi/")
        .split('_')
        .map(|word| {
            let mut chars = word.chars();
            chars.next().map_or_else(String::new, |first| {
                first.to_ascii_uppercase().to_string() + chars.as_str()
            })
        })
        .collect()
}

/// The node's topics and their types.
fn topics() -> Vec<(&'static str, &'static str)> {
    Topic::ALL
        .into_iter()
        .map(|topic| (topic.name(), topic.type_name()))
        .collect()
}

/// The node's services (`endpoints`, and `rosapi`'s) and their types.
fn services(endpoints: &[Endpoint]) -> Vec<(&'static str, String)> {
    endpoints
        .iter()
        .map(|endpoint| (endpoint.name(), endpoint.ros_type().to_owned()))
        .chain(SERVICES.iter().map(|name| (*name, ros_type(name))))
        .collect()
}

#[derive(Deserialize, Default)]
struct Args {
    #[serde(default)]
    topic: String,
    #[serde(default)]
    service: String,
    #[serde(default, rename = "type")]
    r#type: String,
}

/// The answer of `rosapi` service `name` to `args` for a node answering `endpoints`
/// ([`Node::endpoints`](crate::Node::endpoints)): the response's values, or why the request
/// does not read. `None` if the node does not answer `name`.
#[must_use]
pub fn answer(name: &str, args: &[u8], endpoints: &[Endpoint]) -> Option<Result<Value, String>> {
    if !SERVICES.contains(&name) {
        return None;
    }
    let args: Args = match serde_json::from_slice(args) {
        Ok(args) => args,
        Err(error) => return Some(Err(format!("{name}: {error}"))),
    };
    let type_of = |list: &[(&str, String)], wanted: &str| {
        list.iter()
            .find(|(n, _)| *n == wanted)
            .map_or_else(String::new, |(_, t)| t.clone())
    };
    let topics: Vec<(&str, String)> = topics()
        .into_iter()
        .map(|(n, t)| (n, t.to_owned()))
        .collect();
    let services = services(endpoints);
    let names = |list: &[(&str, String)], of: Option<&str>| -> Vec<String> {
        list.iter()
            .filter(|(_, t)| of.is_none_or(|of| crate::rosbridge::same_type(of, t)))
            .map(|(n, _)| (*n).to_owned())
            .collect()
    };
    let values = match name {
        "/rosapi/topics" => json!({
            "topics": names(&topics, None),
            "types": topics.iter().map(|(_, t)| t.clone()).collect::<Vec<_>>(),
        }),
        "/rosapi/topic_type" => json!({ "type": type_of(&topics, &args.topic) }),
        "/rosapi/topics_for_type" => json!({ "topics": names(&topics, Some(&args.r#type)) }),
        "/rosapi/services" => json!({ "services": names(&services, None) }),
        "/rosapi/service_type" => json!({ "type": type_of(&services, &args.service) }),
        "/rosapi/services_for_type" => {
            json!({ "services": names(&services, Some(&args.r#type)) })
        }
        _ => json!({ "nodes": [NODE] }),
    };
    Some(Ok(values))
}
