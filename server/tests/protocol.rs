//! The rosbridge protocol as `docs/server.md` states it: the services, the topics, and a
//! `status` error naming the problem for every bad request, after which the connection goes on.

use crate::common;

use crate::common::{serve, status, Client};
use cooperation_server::{Limits, Options};
use futures_util::SinkExt;
use serde_json::{json, Value};
use tokio_tungstenite::tungstenite::Message;

/// Sends `frame`, expects a `status` error whose message contains `names`, then checks the
/// connection still answers.
async fn refused(client: &mut Client, frame: &str, names: &str) -> Value {
    client.send_text(frame).await;
    let status = client.next_op("status").await;
    assert_eq!(status["level"], "error", "{status}");
    let msg = status["msg"].as_str().expect("a message");
    assert!(msg.contains(names), "{msg:?} does not name {names:?}");
    let answer = client
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(answer["values"]["status"]["success"], true, "{answer}");
    status
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_requests_are_answered_with_a_status_naming_the_problem() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    refused(&mut client, "{not json", "not JSON").await;
    refused(&mut client, "[1, 2]", "not a rosbridge frame").await;
    let status = refused(&mut client, r#"{"id": "x"}"#, "not a rosbridge frame").await;
    assert_eq!(
        status["id"], "x",
        "the id of a frame that is not rosbridge's is echoed"
    );
    let status = refused(
        &mut client,
        r#"{"op": "fly", "id": "f1"}"#,
        "unknown op \"fly\"",
    )
    .await;
    assert_eq!(status["id"], "f1", "the status echoes the request's id");
    refused(
        &mut client,
        r#"{"op": "subscribe"}"#,
        "subscribe without a topic",
    )
    .await;
    refused(
        &mut client,
        r#"{"op": "subscribe", "topic": "/api/planning/nothing"}"#,
        "no topic \"/api/planning/nothing\"",
    )
    .await;
    refused(
        &mut client,
        r#"{"op": "subscribe", "topic": "/api/planning/velocity_factors", "type": "std_msgs/msg/String"}"#,
        "not \"std_msgs/msg/String\"",
    )
    .await;
    refused(
        &mut client,
        r#"{"op": "publish", "topic": "/api/planning/velocity_factors", "msg": {}}"#,
        "takes no publications",
    )
    .await;
    refused(
        &mut client,
        r#"{"op": "call_service", "id": "s1", "service": "/api/nothing", "args": {}}"#,
        "no service \"/api/nothing\"",
    )
    .await;
    refused(
        &mut client,
        r#"{"op": "call_service", "id": "s2", "service": "/api/planning/cooperation/get_policies", "type": "std_srvs/srv/Empty"}"#,
        "not \"std_srvs/srv/Empty\"",
    )
    .await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_failed_call_is_also_answered_with_a_failed_service_response() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    let response = client.call("/api/nothing", json!({})).await;
    assert_eq!(response["result"], false, "{response}");
    assert!(
        response["values"]
            .as_str()
            .is_some_and(|msg| msg.contains("no service")),
        "{response}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_call_that_does_not_read_is_answered_too() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    client
        .send_text(r#"{"op": "call_service", "id": "n5", "service": 5}"#)
        .await;
    let status = client.next_op("status").await;
    assert_eq!(status["id"], "n5", "{status}");
    let response = client.next_op("service_response").await;
    assert_eq!(response["id"], "n5", "{response}");
    assert_eq!(response["result"], false, "{response}");
    assert!(
        response["values"]
            .as_str()
            .is_some_and(|msg| msg.starts_with("not a rosbridge frame")),
        "{response}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn types_may_be_named_in_ros_1_or_ros_2_form() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    for type_name in [
        "autoware_adapi_v1_msgs/srv/GetCooperationPolicies",
        "autoware_adapi_v1_msgs/GetCooperationPolicies",
    ] {
        client
            .send(
                &json!({"op": "call_service", "id": type_name, "type": type_name,
                "service": "/api/planning/cooperation/get_policies"}),
            )
            .await;
        let response = client.next_op("service_response").await;
        assert_eq!(response["result"], true, "{type_name}: {response}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_malformed_request_is_a_parameter_error_naming_the_field() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    let response = client.set_commands(&[(1, 9)]).await;
    let status = &response["values"]["status"];
    assert_eq!(status["success"], false, "{response}");
    assert_eq!(
        status["message"],
        "commands[0].cooperator.decision: 9 is not a CooperationDecision constant"
    );
    let response = client
        .call(
            "/cooperation/rtc/sync",
            json!({"interface": "lane_change_left", "statuses": [{"safe": 3}]}),
        )
        .await;
    assert_eq!(response["values"]["success"], false, "{response}");
    let message = response["values"]["message"].as_str().expect("a message");
    assert!(message.starts_with("statuses[0]"), "{message}");
    let response = client
        .call(
            "/cooperation/rtc/sync",
            json!({"interface": "lane_change_up", "statuses": []}),
        )
        .await;
    assert_eq!(response["values"]["success"], false, "{response}");
    assert!(
        response["values"]["message"]
            .as_str()
            .is_some_and(|m| m.contains("lane_change_up")),
        "{response}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn binary_and_oversized_frames_are_refused_and_the_connection_goes_on() {
    let limits = Limits {
        frame: 4096,
        hard_frame: 65536,
        ..Limits::default()
    };
    let served = serve(Options {
        limits,
        ..Options::default()
    })
    .await;
    let mut client = Client::connect(&served.url).await;
    client
        .ws
        .send(Message::binary(vec![0xa1, 0x62, 0x6f, 0x70]))
        .await
        .expect("sent");
    let status = client.next_op("status").await;
    assert!(
        status["msg"]
            .as_str()
            .is_some_and(|m| m.contains("binary frame")),
        "{status}"
    );
    let big = format!(
        r#"{{"op": "call_service", "id": "big", "service": "{}", "args": {{"pad": "{}"}}}}"#,
        "/api/planning/cooperation/get_policies",
        "x".repeat(5000)
    );
    let status = refused(&mut client, &big, "more than the 4096 this node reads").await;
    assert!(
        status["msg"]
            .as_str()
            .is_some_and(|m| m.contains("a frame of 5")),
        "{status}"
    );
    assert_eq!(status["id"], "big", "{status}");
    // The call is answered as failed, so a client waiting for it is not left waiting.
    client.send_text(&big).await;
    let response = client.next_op("service_response").await;
    assert_eq!(
        (&response["id"], &response["result"]),
        (&json!("big"), &json!(false))
    );

    // Over the hard limit the connection ends; the node serves others on.
    let huge = "x".repeat(100_000);
    let _ = client.ws.send(Message::text(huge)).await;
    // `next` fails the test unless the connection ends within its bounded wait.
    while let Some(frame) = client.next().await {
        assert_ne!(frame["op"], "service_response", "{frame}");
    }
    let mut other = Client::connect(&served.url).await;
    let answer = other
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(answer["values"]["status"]["success"], true);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_module_scene_reaches_the_operator_and_takes_the_operator_command() {
    let served = serve(Options::default()).await;
    let mut module = Client::connect(&served.url).await;
    let mut operator = Client::connect(&served.url).await;
    operator.subscribe("/api/planning/steering_factors").await;
    let synced = module
        .sync("lane_change_left", vec![status(7, true, 20.0)])
        .await;
    assert_eq!(synced["success"], true, "{synced}");
    assert_eq!(synced["activations"][0]["activated"], true, "{synced}");
    assert_eq!(
        synced["statuses"]["statuses"][0]["auto_mode"], true,
        "{synced}"
    );
    // The operator sees the scene, undecided.
    loop {
        let publication = operator.next_op("publish").await;
        if let Some(decision) = common::operator_decision(&publication, 7) {
            assert_eq!(decision, 4, "undecided: {publication}");
            let factor = &publication["msg"]["factors"][0];
            assert_eq!(factor["behavior"], "lane-change");
            assert_eq!(factor["distance"], json!([20.0, 50.0]));
            break;
        }
    }
    // It deactivates the scene; the module learns it in its next sync.
    let response = operator.set_commands(&[(7, 1)]).await;
    assert_eq!(response["values"]["status"]["success"], true, "{response}");
    let synced = module
        .sync("lane_change_left", vec![status(7, true, 18.0)])
        .await;
    let activation = &synced["activations"][0];
    assert_eq!(activation["activated"], false, "{synced}");
    // Force-deactivated is for a running scene only; this one is waiting.
    assert_eq!(activation["force_deactivated"], false, "{synced}");
    let reported = &synced["statuses"]["statuses"][0];
    assert_eq!(reported["command_status"]["type"], 0, "{synced}");
    assert_eq!(
        reported["auto_mode"], false,
        "an operator decided: {synced}"
    );
    // The module removes it; it leaves the stream.
    let response = module
        .call(
            "/cooperation/rtc/sync",
            json!({"interface": "lane_change_left", "removed": [common::uuid(7)]}),
        )
        .await;
    assert_eq!(
        response["values"]["results"][0]["success"], true,
        "{response}"
    );
    loop {
        let publication = operator.next_op("publish").await;
        if common::operator_decision(&publication, 7).is_none() {
            break;
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_over_the_limit_is_answered_503_and_the_others_are_served() {
    let served = serve(Options {
        max_clients: 2,
        ..Options::default()
    })
    .await;
    let mut first = Client::connect(&served.url).await;
    let _second = Client::connect(&served.url).await;
    let refused = tokio_tungstenite::connect_async(served.url.as_str()).await;
    match refused {
        Err(tokio_tungstenite::tungstenite::Error::Http(response)) => {
            assert_eq!(response.status(), 503);
        }
        other => panic!(
            "a third client was not refused: {:?}",
            other.map(|(_, r)| r)
        ),
    }
    let answer = first
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(answer["values"]["status"]["success"], true);
    // A place frees when a client leaves.
    drop(first);
    let mut third = None;
    for _ in 0..100 {
        if let Ok((ws, _)) = tokio_tungstenite::connect_async(served.url.as_str()).await {
            third = Some(ws);
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(20)).await;
    }
    assert!(
        third.is_some(),
        "the place of a client that left was not freed"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_sending_faster_than_it_reads_loses_no_answer() {
    let served = serve(Options {
        limits: Limits {
            queue: 4,
            ..Limits::default()
        },
        ..Options::default()
    })
    .await;
    let mut client = Client::connect(&served.url).await;
    // About 3.5 MB of answers: more than the sockets buffer, so the queue of 4 fills and the
    // node stops reading the client for a while.
    for n in 0..5_000 {
        client
            .send(&json!({"op": "call_service", "id": n, "service": "/api/planning/cooperation/get_policies"}))
            .await;
    }
    for n in 0..5_000 {
        let response = client.next_op("service_response").await;
        assert_eq!(response["id"], n, "answers in order, none dropped");
        assert_eq!(response["result"], true);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_silent_client_is_disconnected_and_a_listening_one_is_not() {
    let served = serve(Options {
        limits: Limits {
            keepalive: std::time::Duration::from_millis(100),
            ..Limits::default()
        },
        ..Options::default()
    })
    .await;
    let mut silent = Client::connect(&served.url).await;
    let mut listening = Client::connect(&served.url).await;
    // Reading answers the node's pings; not reading leaves them unanswered.
    let quiet = tokio::time::timeout(std::time::Duration::from_secs(1), listening.next()).await;
    assert!(
        quiet.is_err(),
        "no frame but pings for a client that asks nothing: {quiet:?}"
    );
    let answer = listening
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(
        answer["result"], true,
        "the listening client is still served"
    );
    // `next` fails the test unless the silent client's connection has ended.
    let frame = silent.next().await;
    assert_eq!(frame, None, "a frame for a silent client");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn options_that_cannot_run_a_node_are_refused() {
    let zero = std::time::Duration::ZERO;
    for options in [
        Options {
            publish_every: zero,
            ..Options::default()
        },
        Options {
            max_clients: 0,
            ..Options::default()
        },
        Options {
            limits: Limits {
                keepalive: zero,
                ..Limits::default()
            },
            ..Options::default()
        },
        Options {
            limits: Limits {
                write_timeout: zero,
                ..Limits::default()
            },
            ..Options::default()
        },
    ] {
        let problem = options.problem().expect("a problem");
        let config = cooperation_adapters::settings::parse(common::SETTINGS).expect("settings");
        let node = std::sync::Arc::new(cooperation_server::Node::new(config).expect("a node"));
        let listener = cooperation_server::bind("127.0.0.1:0".parse().expect("an address"))
            .await
            .expect("a port");
        let error = cooperation_server::serve(listener, node, options, async {})
            .await
            .expect_err("refused");
        assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
        assert_eq!(error.to_string(), problem);
    }
    assert_eq!(Options::default().problem(), None);
}
