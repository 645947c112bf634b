//! The stack mode's node ([`Node::relayed`]): a door onto a core another thread owns (in
//! `cooperation-server --stack`, `cooperation-dds`'s stack node and its relay; here an engine
//! on a thread of the test). Every call goes to that thread and its reply comes back; what the
//! thread shows is what the streams publish; a call it does not answer within the node's wait,
//! or can no longer take, is refused, saying so.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use crate::common::*;
use cooperation_adapters::clock::Clock;
use cooperation_adapters::engine::{Engine, Reply, Request};
use cooperation_server::{Node, Options};
use serde_json::json;

type Calls = mpsc::Receiver<(Request, mpsc::Sender<Reply>)>;

/// A relayed node waiting `wait` for each reply, the receiver of its calls, and how many times
/// it woke the owner.
fn relayed(wait: Duration) -> (Arc<Node>, Calls, Arc<AtomicUsize>) {
    let (calls, incoming) = mpsc::channel();
    let woken = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&woken);
    let wake = move || {
        counter.fetch_add(1, Ordering::SeqCst);
    };
    let interfaces = cooperation_adapters::rtc::Binding::standard()
        .into_iter()
        .map(|binding| binding.name)
        .collect();
    (
        Arc::new(Node::relayed(calls, Box::new(wake), wait, interfaces)),
        incoming,
        woken,
    )
}

/// The owner: an engine with the default settings answering `calls`, showing `node` each
/// publication before the reply that made it.
fn own(node: &Arc<Node>, calls: Calls) {
    let node = Arc::clone(node);
    std::thread::spawn(move || {
        let mut engine = Engine::from_settings(None, Default::default()).expect("the settings");
        let clock = Clock::start();
        node.show(&engine.publication(clock.stamp()));
        while let Ok((request, reply)) = calls.recv() {
            let handled = engine.handle(request, clock.now());
            if let Some(publication) = engine.poll_publication(clock.now()) {
                node.show(&publication);
            }
            let _ = reply.send(handled.reply);
        }
    });
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn calls_reach_the_owner_and_what_it_shows_is_published() {
    let (node, calls, woken) = relayed(WAIT);
    own(&node, calls);
    let served = serve_node(node, Options::default()).await;
    let mut module = Client::connect(&served.url).await;
    let mut operator = Client::connect(&served.url).await;
    operator.subscribe("/api/planning/velocity_factors").await;
    let values = module
        .sync("intersection", vec![status(1, false, 20.0)])
        .await;
    assert_eq!(values["success"], json!(true), "{values}");
    // The owner showed the scene before it answered: it is in the operator's stream.
    let shown = tokio::time::timeout(WAIT, async {
        loop {
            let frame = operator.next_op("publish").await;
            if operator_decision(&frame, 1).is_some() {
                return frame;
            }
        }
    })
    .await
    .expect("the scene is published");
    assert_eq!(operator_decision(&shown, 1), Some(4), "{shown}");
    let response = operator.set_commands(&[(1, 2)]).await;
    assert_eq!(
        response["values"]["status"]["success"],
        json!(true),
        "{response}"
    );
    let response = operator.set_commands(&[(9, 2)]).await;
    let status = &response["values"]["status"];
    assert_eq!(status["success"], json!(false), "{response}");
    assert!(
        status["message"]
            .as_str()
            .is_some_and(|m| m.contains("unknown")),
        "the owner's refusal comes back as it made it: {response}"
    );
    assert!(
        woken.load(Ordering::SeqCst) >= 3,
        "each call woke the owner"
    );
}

/// The panel learns from `/whoami` which decisions it may offer: in the stack mode, those an
/// upstream RTC interface can take, activate and deactivate.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn whoami_offers_only_the_decisions_a_module_can_take() {
    let (node, calls, _) = relayed(WAIT);
    own(&node, calls);
    let served = serve_node(node, Options::default()).await;
    let (status, _, body) = crate::whoami::ask(&served.url, "/whoami", None).await;
    assert_eq!(status, 200, "{body}");
    assert_eq!(
        crate::whoami::json(&body)["decisions"],
        json!([1, 2]),
        "{body}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_call_the_owner_does_not_answer_in_time_is_refused_saying_so() {
    let (node, calls, _) = relayed(Duration::from_millis(300));
    // The owner takes the calls and never answers them.
    let kept = std::thread::spawn(move || calls.iter().collect::<Vec<_>>());
    let served = serve_node(node, Options::default()).await;
    let mut operator = Client::connect(&served.url).await;
    let response = operator
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    let status = &response["values"]["status"];
    assert_eq!(status["success"], json!(false), "{response}");
    assert_eq!(
        status["message"],
        json!("the stack mode's relay did not answer within 300 ms"),
        "{response}"
    );
    drop(served);
    drop(kept);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_call_after_the_owner_stopped_is_refused_saying_so() {
    let (node, calls, _) = relayed(WAIT);
    drop(calls);
    let served = serve_node(node, Options::default()).await;
    let mut operator = Client::connect(&served.url).await;
    let response = operator.set_commands(&[(1, 2)]).await;
    let status = &response["values"]["status"];
    assert_eq!(status["success"], json!(false), "{response}");
    assert_eq!(
        status["message"],
        json!("the stack mode's relay has stopped"),
        "{response}"
    );
}

/// A subscription made before the relay first showed anything is sent nothing until it does,
/// then that publication: never an empty frame.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_subscription_before_the_first_publication_waits_for_it() {
    let (node, calls, _) = relayed(WAIT);
    let served = serve_node(Arc::clone(&node), Options::default()).await;
    let mut operator = Client::connect(&served.url).await;
    operator.subscribe("/api/planning/velocity_factors").await;
    // A call's round trip: the subscription is taken before the owner starts.
    operator.call("/rosapi/topics", json!({})).await;
    own(&node, calls);
    let frame = operator.next_op("publish").await;
    assert_eq!(
        frame["topic"],
        json!("/api/planning/velocity_factors"),
        "{frame}"
    );
    assert!(frame["msg"]["factors"].is_array(), "{frame}");
}

/// `rosapi` lists the services the stack mode answers: the AD API's, not the module sync,
/// which the modules' own RTC topics replace there.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn rosapi_lists_no_module_sync_in_the_stack_mode() {
    let (node, calls, _) = relayed(WAIT);
    own(&node, calls);
    let served = serve_node(node, Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    let response = client.call("/rosapi/services", json!({})).await;
    let services: Vec<&str> = response["values"]["services"]
        .as_array()
        .expect("a list")
        .iter()
        .filter_map(serde_json::Value::as_str)
        .filter(|name| !name.starts_with("/rosapi/"))
        .collect();
    assert_eq!(
        services,
        [
            "/api/planning/cooperation/set_commands",
            "/api/planning/cooperation/set_policies",
            "/api/planning/cooperation/get_policies",
        ],
        "{response}"
    );
    let response = client
        .call(
            "/rosapi/service_type",
            json!({"service": "/cooperation/rtc/sync"}),
        )
        .await;
    assert_eq!(response["values"]["type"], json!(""), "{response}");
}

/// `docs/server.md`: a call the relay does not answer "within `--deadline-ms` plus 2 s" is
/// refused. The stack mode's door waits [`answer_wait_ms`] of the deadline, the relay's own
/// limit.
///
/// [`answer_wait_ms`]: cooperation_adapters::relay::answer_wait_ms
#[test]
fn the_stack_door_waits_the_deadline_and_the_slack_the_docs_state() {
    use cooperation_adapters::relay::{answer_wait_ms, ANSWER_SLACK_MS, DEADLINE_MS};
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/server.md"))
        .expect("docs/server.md");
    let stated = format!(
        "within `--deadline-ms` plus {} s is answered with a refusal",
        ANSWER_SLACK_MS / 1_000
    );
    assert!(docs.contains(&stated), "docs/server.md states: {stated}");
    assert_eq!(answer_wait_ms(DEADLINE_MS), DEADLINE_MS + 2_000);
    assert_eq!(answer_wait_ms(250), 2_250);
    assert_eq!(answer_wait_ms(u64::MAX), u64::MAX, "no overflow");
}

/// At most `MAX_WAITING_CALLS` calls wait for the relay at once, all connections together (each
/// holds a thread of the blocking pool): one more is refused at once, saying so, and the place
/// frees as soon as a waiting call has its reply.
#[test]
fn calls_waiting_for_the_relay_are_bounded() {
    use cooperation_adapters::wire;
    use cooperation_server::MAX_WAITING_CALLS;
    let (node, calls, _) = relayed(Duration::from_secs(60));
    let ask = |node: &Arc<Node>| {
        let node = Arc::clone(node);
        std::thread::spawn(move || {
            let request = Request::Ad(wire::Request::GetPolicies(Default::default()));
            node.handle(request).0
        })
    };
    let mut waiting: Vec<_> = (0..MAX_WAITING_CALLS).map(|_| ask(&node)).collect();
    let held: Vec<_> = (0..MAX_WAITING_CALLS)
        .map(|_| {
            calls
                .recv_timeout(WAIT)
                .expect("each call reaches the owner")
        })
        .collect();

    let started = std::time::Instant::now();
    let refused = ask(&node).join().expect("answered");
    assert!(
        started.elapsed() < Duration::from_secs(10),
        "refused at once"
    );
    let Reply::Ad(response) = &refused else {
        panic!("{refused:?}")
    };
    assert!(!response.status().success);
    assert_eq!(
        response.status().message,
        format!(
            "the stack mode's relay has {MAX_WAITING_CALLS} calls waiting, the most the node \
             holds: call again"
        )
    );
    assert!(
        calls.try_recv().is_err(),
        "the refused call never reached the owner"
    );
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/server.md"))
        .expect("docs/server.md");
    let stated = format!(
        "At most {MAX_WAITING_CALLS} calls wait for the relay at once, all connections together"
    );
    assert!(docs.contains(&stated), "docs/server.md states: {stated}");

    // One reply frees one place: the next call reaches the owner and waits.
    let mut held = held.into_iter();
    let (request, reply) = held.next().expect("one");
    reply
        .send(Reply::refusal(request.endpoint(), "answered".to_owned()))
        .expect("the caller waits");
    // The call that had it returns (whichever of the threads made it).
    let deadline = std::time::Instant::now() + WAIT;
    let answered = loop {
        if let Some(done) = waiting
            .iter()
            .position(std::thread::JoinHandle::is_finished)
        {
            break waiting.swap_remove(done);
        }
        assert!(
            std::time::Instant::now() < deadline,
            "the answered call returns"
        );
        std::thread::sleep(Duration::from_millis(1));
    };
    assert!(
        !answered.join().expect("answered").success(),
        "its reply came back"
    );
    let next = ask(&node);
    let (request, reply) = calls.recv_timeout(WAIT).expect("a place was free");
    reply
        .send(Reply::refusal(request.endpoint(), "answered".to_owned()))
        .expect("the caller waits");
    assert!(!next.join().expect("answered").success());
    drop(held);
}
