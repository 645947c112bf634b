//! Subscriptions as rosbridge keeps them (`docs/server.md`, *The protocol*): per `id`, with
//! `throttle_rate` and `queue_length`, what the node does not support refused with a status,
//! each publication sent at most once per connection, and `rosapi`'s lookups.

use std::time::Duration;

use crate::common::{serve, Client};
use cooperation_server::Options;
use serde_json::{json, Value};

const VELOCITY: &str = "/api/planning/velocity_factors";

/// The publications `client` receives in `during`.
async fn publications(client: &mut Client, during: Duration) -> usize {
    let until = tokio::time::Instant::now() + during;
    let mut count = 0;
    while let Ok(frame) = tokio::time::timeout_at(until, client.next()).await {
        if frame.expect("the connection stays open")["op"] == "publish" {
            count += 1;
        }
    }
    count
}

fn every(ms: u64) -> Options {
    Options {
        publish_every: Duration::from_millis(ms),
        ..Options::default()
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_topic_is_sent_while_any_of_its_subscriptions_lasts() {
    let served = serve(every(20)).await;
    let mut client = Client::connect(&served.url).await;
    for id in ["a", "b"] {
        client
            .send(&json!({"op": "subscribe", "id": id, "topic": VELOCITY}))
            .await;
    }
    client
        .send(&json!({"op": "unsubscribe", "id": "a", "topic": VELOCITY}))
        .await;
    // `b` still holds the topic.
    assert!(publications(&mut client, Duration::from_millis(300)).await > 3);
    client
        .send(&json!({"op": "unsubscribe", "id": "b", "topic": VELOCITY}))
        .await;
    tokio::time::sleep(Duration::from_millis(100)).await;
    publications(&mut client, Duration::from_millis(50)).await;
    assert_eq!(
        publications(&mut client, Duration::from_millis(300)).await,
        0
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn throttle_rate_spaces_publications_and_the_smallest_one_holds() {
    let served = serve(every(20)).await;
    let mut client = Client::connect(&served.url).await;
    client
        .send(&json!({"op": "subscribe", "id": "slow", "topic": VELOCITY, "throttle_rate": 400}))
        .await;
    // 1.3 s at one publication per 400 ms at most: four, the first at once.
    let throttled = publications(&mut client, Duration::from_millis(1_300)).await;
    assert!((2..=4).contains(&throttled), "{throttled} publications");
    client
        .send(&json!({"op": "subscribe", "id": "fast", "topic": VELOCITY, "throttle_rate": 0}))
        .await;
    let unthrottled = publications(&mut client, Duration::from_millis(1_000)).await;
    assert!(unthrottled > 10, "{unthrottled} publications");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn what_the_node_does_not_do_is_refused_or_said() {
    let served = serve(every(20)).await;
    let mut client = Client::connect(&served.url).await;
    for (field, value, says) in [
        ("compression", json!("png"), "sends JSON text only"),
        ("compression", json!("cbor"), "sends JSON text only"),
        ("fragment_size", json!(1000), "sends every message whole"),
    ] {
        let mut frame = json!({"op": "subscribe", "id": field, "topic": VELOCITY});
        frame[field] = value;
        client.send(&frame).await;
        let status = client.next_op("status").await;
        assert_eq!(status["level"], "error", "{status}");
        assert!(
            status["msg"].as_str().is_some_and(|m| m.contains(says)),
            "{status}"
        );
    }
    // None of them subscribed.
    assert_eq!(
        publications(&mut client, Duration::from_millis(300)).await,
        0
    );
    // A service call asking for fragments is refused too, with its response.
    client
        .send(
            &json!({"op": "call_service", "id": "c", "fragment_size": 10,
                      "service": "/api/planning/cooperation/get_policies"}),
        )
        .await;
    let response = client.next_op("service_response").await;
    assert_eq!(response["result"], false, "{response}");
    // A queue longer than one is said to be one, and the subscription is made.
    client
        .send(
            &json!({"op": "subscribe", "id": "q", "topic": VELOCITY, "queue_length": 5,
                      "compression": "none"}),
        )
        .await;
    let status = client.next_op("status").await;
    assert_eq!(status["level"], "warning", "{status}");
    assert_eq!(status["id"], "q", "{status}");
    assert!(publications(&mut client, Duration::from_millis(300)).await > 0);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn subscribing_again_and_again_is_sent_each_publication_once() {
    let served = serve(every(3_600_000)).await;
    // The publishing task's first periodic publication is due at its start: let it pass.
    tokio::time::sleep(Duration::from_millis(300)).await;
    let mut client = Client::connect(&served.url).await;
    for n in 0..100 {
        let id = format!("s{n}");
        client
            .send(&json!({"op": "subscribe", "id": id, "topic": VELOCITY}))
            .await;
        client
            .send(&json!({"op": "unsubscribe", "id": id, "topic": VELOCITY}))
            .await;
    }
    client
        .send(&json!({"op": "subscribe", "topic": VELOCITY}))
        .await;
    // The newest publication once (the first subscription), and no other was made.
    assert_eq!(
        publications(&mut client, Duration::from_millis(500)).await,
        1
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn rosapi_lists_the_topics_and_services_with_their_types() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    let values = |response: Value| {
        assert_eq!(response["result"], true, "{response}");
        response["values"].clone()
    };
    let topics = values(client.call("/rosapi/topics", json!({})).await);
    assert_eq!(
        topics["topics"],
        json!([
            VELOCITY,
            "/api/planning/steering_factors",
            "/cooperation/scenes"
        ])
    );
    assert_eq!(
        topics["types"][0],
        "autoware_adapi_v1_msgs/msg/VelocityFactorArray"
    );
    let services = values(client.call("/rosapi/services", json!({})).await);
    let services = services["services"].as_array().expect("a list");
    for name in [
        "/api/planning/cooperation/set_commands",
        "/cooperation/rtc/sync",
        "/rosapi/topics",
    ] {
        assert!(services.contains(&json!(name)), "{services:?}");
    }
    let kind = values(
        client
            .call("/rosapi/topic_type", json!({"topic": VELOCITY}))
            .await,
    );
    assert_eq!(
        kind["type"],
        "autoware_adapi_v1_msgs/msg/VelocityFactorArray"
    );
    let kind = values(
        client
            .call(
                "/rosapi/service_type",
                json!({"service": "/cooperation/rtc/sync"}),
            )
            .await,
    );
    assert_eq!(kind["type"], "cooperation_server/srv/SyncCooperateStatus");
    let nodes = values(client.call("/rosapi/nodes", json!({})).await);
    assert_eq!(nodes["nodes"], json!(["/cooperation_server"]));
    let refused = client.call("/rosapi/get_param", json!({})).await;
    assert_eq!(refused["result"], false, "{refused}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_connection_holds_a_bounded_number_of_subscriptions() {
    let served = serve(every(3_600_000)).await;
    let mut client = Client::connect(&served.url).await;
    let most = cooperation_server::connection::MAX_SUBSCRIPTIONS;
    for n in 0..most {
        let id = format!("s{n}");
        client
            .send(&json!({"op": "subscribe", "id": id, "topic": VELOCITY}))
            .await;
    }
    client
        .send(&json!({"op": "subscribe", "id": "over", "topic": VELOCITY}))
        .await;
    let status = client.next_op("status").await;
    assert_eq!(status["id"], "over", "{status}");
    assert!(
        status["msg"]
            .as_str()
            .is_some_and(|m| m.contains("subscriptions")),
        "{status}"
    );
    // Subscribing again under an id it holds is no new subscription; after an unsubscribe
    // there is room again.
    client
        .send(&json!({"op": "subscribe", "id": "s0", "topic": VELOCITY}))
        .await;
    client
        .send(&json!({"op": "unsubscribe", "id": "s1", "topic": VELOCITY}))
        .await;
    client
        .send(&json!({"op": "subscribe", "id": "again", "topic": VELOCITY}))
        .await;
    let nothing = tokio::time::timeout(Duration::from_millis(300), client.next_op("status")).await;
    assert!(nothing.is_err(), "refused: {nothing:?}");
}
