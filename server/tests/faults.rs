//! Faults the node serves through (`docs/server.md`, *Limits and faults*): clients that leave
//! mid-call, subscribers too slow for the stream, and the promise that the publication after
//! an accepted command shows it.

use crate::common;

use std::time::{Duration, Instant};

use crate::common::{operator_decision, serve, status, Client, WAIT};
use cooperation_server::{Limits, Options};
use serde_json::json;

/// Scenes 1 to 500, a hundred on each of five velocity interfaces (each under the default
/// quota), registered by a module that then leaves (they live for the settings' 10 s).
async fn five_hundred_scenes(url: &str) {
    let mut module = Client::connect(url).await;
    let interfaces = [
        "intersection",
        "crosswalk",
        "traffic_light",
        "detection_area",
        "no_stopping_area",
    ];
    for (batch, interface) in (0..5_u128).zip(interfaces) {
        let scenes: Vec<_> = (0..100)
            .map(|n| status(batch * 100 + n + 1, true, 5.0))
            .collect();
        assert_eq!(module.sync(interface, scenes).await["success"], true);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_publication_after_an_accepted_command_shows_it() {
    // The publication that shows a change may also reach the client before the answer; the
    // one after the answer must show it too. A fast rate keeps the wait for it short.
    let served = serve(Options {
        publish_every: Duration::from_millis(20),
        ..Options::default()
    })
    .await;
    let mut module = Client::connect(&served.url).await;
    let synced = module
        .sync("intersection", vec![status(3, true, 12.0)])
        .await;
    assert_eq!(synced["success"], true, "{synced}");
    let mut operator = Client::connect(&served.url).await;
    operator.subscribe("/api/planning/velocity_factors").await;
    for round in 0..60_u8 {
        // Deactivate, activate, autonomous, in turn.
        let decision = 1 + round % 3;
        let response = operator.set_commands(&[(3, decision)]).await;
        assert_eq!(response["values"]["status"]["success"], true, "{response}");
        let publication = operator.next_op("publish").await;
        assert_eq!(
            operator_decision(&publication, 3),
            Some(u64::from(decision)),
            "round {round}: the first publication after the response: {publication}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_leaving_mid_call_loses_nothing_and_stops_nothing() {
    let served = serve(Options::default()).await;
    let mut module = Client::connect(&served.url).await;
    let scenes: Vec<_> = (1..=20).map(|n| status(n, true, 10.0 + n as f32)).collect();
    module.sync("crosswalk", scenes).await;
    for round in 0..20_u128 {
        let mut leaving = Client::connect(&served.url).await;
        let commands: Vec<_> = (1..=20)
            .map(|n| json!({"uuid": common::uuid(n), "cooperator": {"decision": 2}}))
            .collect();
        let frame = json!({"op": "call_service", "id": "gone", "service": "/api/planning/cooperation/set_commands", "args": {"commands": commands}});
        leaving.send(&frame).await;
        if round % 2 == 0 {
            // Gone without a close handshake.
            drop(leaving);
        } else {
            let _ = leaving.ws.close(None).await;
        }
    }
    // Every batch applied whole or not at all: every scene has the same operator decision,
    // and the node answers the next client.
    let mut operator = Client::connect(&served.url).await;
    operator.subscribe("/api/planning/velocity_factors").await;
    let publication = operator.next_op("publish").await;
    let decisions: Vec<_> = (1..=20)
        .map(|n| operator_decision(&publication, n))
        .collect();
    // The frame was in the node's socket before the client left, so every batch applied.
    assert!(decisions.iter().all(|d| *d == Some(2)), "{decisions:?}");
    let response = operator.set_commands(&[(5, 1)]).await;
    assert_eq!(response["values"]["status"]["success"], true, "{response}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stalled_subscriber_is_disconnected_and_others_are_served_meanwhile() {
    let limits = Limits {
        write_timeout: Duration::from_millis(500),
        ..Limits::default()
    };
    let served = serve(Options {
        publish_every: Duration::from_millis(10),
        limits,
        ..Options::default()
    })
    .await;
    // Big publications, to fill the stalled client's socket buffers quickly.
    five_hundred_scenes(&served.url).await;
    let mut stalled = Client::connect(&served.url).await;
    stalled.subscribe("/api/planning/velocity_factors").await;
    // While it reads nothing, another client's commands are answered and published to it.
    let mut operator = Client::connect(&served.url).await;
    operator.subscribe("/api/planning/velocity_factors").await;
    let started = Instant::now();
    let mut round = 0_u8;
    while started.elapsed() < Duration::from_secs(3) {
        let decision = 1 + round % 2;
        round = round.wrapping_add(1);
        let call = tokio::time::timeout(Duration::from_secs(1), async {
            let call = operator.set_commands(&[(7, decision)]).await;
            (call, operator.next_op("publish").await)
        })
        .await
        .expect("answered and published within a second while another client stalls");
        assert_eq!(call.0["values"]["status"]["success"], true);
        assert_eq!(operator_decision(&call.1, 7), Some(u64::from(decision)));
    }
    // The stalled client gets what was buffered before the node gave up on it, and then the
    // end of the connection: far fewer publications than were sent in those 3 s (300).
    let mut received = 0;
    let deadline = Instant::now() + WAIT;
    while let Some(frame) = stalled.next().await {
        assert!(
            Instant::now() < deadline,
            "the stalled client was not disconnected"
        );
        if frame["op"] == "publish" {
            received += 1;
        }
    }
    assert!(
        received < 300,
        "{received} publications reached a client that read nothing"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_slow_subscriber_skips_publications_and_each_is_whole_and_current() {
    let served = serve(Options {
        publish_every: Duration::from_millis(5),
        ..Options::default()
    })
    .await;
    // 500 scenes: publications of about 90 KB, 200 a second.
    five_hundred_scenes(&served.url).await;
    // The publication made before the last sync (400 scenes) may still be the latest for a
    // moment: wait until one shows all 500, so that every publication from here on should.
    let mut watcher = Client::connect(&served.url).await;
    watcher.subscribe("/api/planning/velocity_factors").await;
    let mut seen = 0;
    while watcher.next_op("publish").await["msg"]["factors"]
        .as_array()
        .map(Vec::len)
        != Some(500)
    {
        seen += 1;
        assert!(seen < 100, "no publication shows the 500 scenes synced");
    }
    drop(watcher);
    let mut slow = Client::connect(&served.url).await;
    slow.subscribe("/api/planning/velocity_factors").await;
    // It reads nothing for 2 s (about 400 publications, 36 MB), during which an operator
    // decides a scene.
    tokio::time::sleep(Duration::from_secs(1)).await;
    let mut operator = Client::connect(&served.url).await;
    let response = operator.set_commands(&[(250, 1)]).await;
    assert_eq!(response["values"]["status"]["success"], true);
    tokio::time::sleep(Duration::from_secs(1)).await;
    // Then it gets what its socket buffered and, soon after, the current state: not the
    // hundreds of publications a queue would have kept for it.
    let mut stamps = Vec::new();
    loop {
        let publication = slow.next_op("publish").await;
        let stamp = &publication["msg"]["header"]["stamp"];
        stamps.push((stamp["sec"].as_i64(), stamp["nanosec"].as_i64()));
        assert_eq!(
            publication["msg"]["factors"].as_array().map(Vec::len),
            Some(500),
            "whole"
        );
        if operator_decision(&publication, 250) == Some(1) {
            break;
        }
        assert!(
            stamps.len() < 200,
            "{} stale publications kept for a slow subscriber",
            stamps.len()
        );
    }
    assert!(
        stamps.windows(2).all(|pair| pair[0] < pair[1]),
        "{stamps:?}"
    );
}
