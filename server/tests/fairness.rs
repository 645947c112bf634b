//! One client's heavy requests beside another's (`docs/server.md`, *Limits and faults*): a
//! connection's requests are worked out one after the other, so a client that sends many of
//! the heaviest requests at once delays another client by about the one under way, not by
//! its queue. Asserted by the order of the answers, not by a time.

use std::sync::{Arc, Mutex};

use crate::common::{serve, status, Client};
use cooperation_server::Options;
use serde_json::json;

/// Heavy requests sent at once, each the most statuses a sync may carry (`max_batch`).
const QUEUED: usize = 32;
const ENTRIES: u128 = 1_024;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_waits_for_one_of_anothers_heavy_requests_not_for_its_queue() {
    let served = serve(Options::default()).await;
    let mut heavy = Client::connect(&served.url).await;
    let mut light = Client::connect(&served.url).await;
    let statuses: Vec<_> = (1..=ENTRIES).map(|n| status(n, true, 20.0)).collect();
    for request in 0..QUEUED {
        heavy
            .send(&json!({
                "op": "call_service",
                "id": format!("heavy:{request}"),
                "service": "/cooperation/rtc/sync",
                "args": {"interface": "intersection", "statuses": statuses},
            }))
            .await;
    }
    // The answers of both clients, in the order they arrive.
    let arrivals = Arc::new(Mutex::new(Vec::new()));
    let heavy_answers = {
        let arrivals = Arc::clone(&arrivals);
        tokio::spawn(async move {
            for _ in 0..QUEUED {
                let answer = heavy.next_op("service_response").await;
                assert_eq!(answer["result"], true, "{answer}");
                arrivals.lock().expect("the list").push("heavy");
            }
        })
    };
    // Once the first heavy request is answered, the others are read and waiting.
    while arrivals.lock().expect("the list").is_empty() {
        tokio::time::sleep(std::time::Duration::from_millis(1)).await;
    }
    let read = light
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    arrivals.lock().expect("the list").push("light");
    assert_eq!(read["values"]["status"]["success"], true, "{read}");
    heavy_answers.await.expect("the heavy client's answers");
    let arrivals = arrivals.lock().expect("the list").clone();
    let before = arrivals.iter().take_while(|who| **who == "heavy").count();
    // The first, then about the one under way (a few, if the heavy client's next request
    // takes the lock first), not the queue: a queue of them would be about 30.
    assert!(
        before <= 4,
        "the light client was answered after {before} of the {QUEUED} heavy requests sent before \
         it: {arrivals:?}"
    );
}
