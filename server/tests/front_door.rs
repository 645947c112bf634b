//! The front door under a flood (`docs/server.md`, *Limits and faults*): clients that present
//! no credential, from two addresses, hold every waiting place and come back at once when
//! closed; an operator from a third address gets in every time.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;

use crate::common::serve;
use crate::guesses::connect_from;
use cooperation_server::{Admission, Credentials, Options};
use tokio::net::TcpSocket;

const OPERATOR: &str = "operator-token-0123456789abcdef";
const FILE: &str = "operator panel operator-token-0123456789abcdef\n";
const PENDING: usize = 16;

/// Keeps opening connections from `source` that send nothing, at most `hold` open at once
/// (the oldest let go), as fast as they are accepted, until `stop`; counts them.
fn flood(
    at: std::net::SocketAddr,
    source: &'static str,
    hold: usize,
    stop: Arc<AtomicBool>,
    opened: Arc<AtomicUsize>,
) -> tokio::task::JoinHandle<()> {
    tokio::spawn(async move {
        let mut held = VecDeque::new();
        while !stop.load(Ordering::Relaxed) {
            let socket = TcpSocket::new_v4().expect("a socket");
            socket
                .bind(format!("{source}:0").parse().expect("an address"))
                .expect("bound");
            if let Ok(stream) = socket.connect(at).await {
                opened.fetch_add(1, Ordering::Relaxed);
                held.push_back(stream);
                if held.len() > hold {
                    held.pop_front();
                }
            }
            tokio::task::yield_now().await;
        }
    })
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_operator_gets_in_however_many_tokenless_connections_wait() {
    for credentials in [true, false] {
        let served = serve(Options {
            credentials: credentials
                .then(|| Credentials::parse(FILE, &[], 4).expect("the credentials read")),
            admission: Admission {
                pending: PENDING,
                ..Admission::default()
            },
            ..Options::default()
        })
        .await;
        let at: std::net::SocketAddr = served
            .url
            .trim_start_matches("ws://")
            .trim_end_matches('/')
            .parse()
            .expect("the node's address");
        let stop = Arc::new(AtomicBool::new(false));
        let opened = Arc::new(AtomicUsize::new(0));
        let floods = [
            flood(
                at,
                "127.0.0.1",
                PENDING,
                Arc::clone(&stop),
                Arc::clone(&opened),
            ),
            flood(
                at,
                "127.0.0.2",
                PENDING,
                Arc::clone(&stop),
                Arc::clone(&opened),
            ),
        ];
        // Let the flood take every waiting place.
        while opened.load(Ordering::Relaxed) < 4 * PENDING {
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
        let token = credentials.then_some(OPERATOR);
        for attempt in 0..20 {
            assert_eq!(
                connect_from(&served.url, "127.0.0.3", token).await,
                Ok(()),
                "attempt {attempt}, credentials: {credentials}"
            );
        }
        stop.store(true, Ordering::Relaxed);
        for flood in floods {
            flood.await.expect("the flood ran");
        }
        assert!(opened.load(Ordering::Relaxed) > 4 * PENDING);
    }
}

/// A node without credentials: subscribers from two addresses hold every client's place, and
/// stay, as subscribers are not idle; a client from a third address
/// still gets in, in the place of the oldest of one of them, while one more from either
/// of the two is refused.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn subscribers_without_a_credential_keep_no_other_address_out() {
    use crate::common::Client;
    // The default places, each address allowed them all: what refuses is the sharing.
    let clients = Options::default().max_clients;
    let per_peer = clients / 2;
    let served = serve(Options {
        admission: Admission {
            per_peer: clients,
            ..Admission::default()
        },
        ..Options::default()
    })
    .await;
    let url = served.url.as_str();
    let mut held = Vec::new();
    for source in ["127.0.0.1", "127.0.0.2"] {
        for _ in 0..per_peer {
            let mut client = Client::connect_from(url, source).await.expect("in");
            client.subscribe("/api/planning/velocity_factors").await;
            held.push(client);
        }
    }
    // Full: one more from either address is refused.
    for source in ["127.0.0.1", "127.0.0.2"] {
        assert_eq!(Client::connect_from(url, source).await.err(), Some(503));
    }
    // A third address gets in, and is served ...
    let mut operator = Client::connect_from(url, "127.0.0.3").await.expect("in");
    let read = operator
        .call(
            "/api/planning/cooperation/get_policies",
            serde_json::json!({}),
        )
        .await;
    assert_eq!(read["values"]["status"]["success"], true, "{read}");
    // ... in the place of the oldest subscriber of one of the two, which is closed.
    let oldest = [0, per_peer];
    let mut closed = 0;
    for index in oldest {
        let client = held.get_mut(index).expect("a client");
        let ended = tokio::time::timeout(Duration::from_secs(2), async {
            while client.next().await.is_some() {}
        })
        .await;
        closed += usize::from(ended.is_ok());
    }
    assert_eq!(closed, 1, "one oldest subscriber gave its place");
}
