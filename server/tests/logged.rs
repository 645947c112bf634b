//! Every limit is logged when it bites (`docs/server.md`, *Limits and faults*): each limit is
//! made to bite once, with the node's log captured, and the log must say so.

mod common;

use std::io::Write;
use std::sync::{Arc, Mutex, OnceLock, PoisonError};
use std::time::Duration;

use common::{serve, serve_quota, status, Client};
use cooperation_server::{Admission, Credentials, GuessLimits, Limits, Options};
use serde_json::json;
use tokio::io::AsyncReadExt;
use tokio::net::TcpStream;

/// The log of every node in this test binary.
fn log() -> &'static Arc<Mutex<Vec<u8>>> {
    static LOG: OnceLock<Arc<Mutex<Vec<u8>>>> = OnceLock::new();
    LOG.get_or_init(|| {
        let log = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&log);
        tracing_subscriber::fmt()
            .with_ansi(false)
            .with_env_filter("info")
            .with_writer(move || Captured(Arc::clone(&sink)))
            .init();
        log
    })
}

struct Captured(Arc<Mutex<Vec<u8>>>);

impl Write for Captured {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .extend_from_slice(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Waits until the log says `text`.
async fn logged(text: &str) {
    for _ in 0..200 {
        let said = String::from_utf8_lossy(&log().lock().unwrap_or_else(PoisonError::into_inner))
            .contains(text);
        if said {
            return;
        }
        tokio::time::sleep(Duration::from_millis(25)).await;
    }
    let all =
        String::from_utf8_lossy(&log().lock().unwrap_or_else(PoisonError::into_inner)).into_owned();
    panic!("the log never said {text:?}:\n{all}");
}

fn address(url: &str) -> String {
    url.trim_start_matches("ws://")
        .trim_end_matches('/')
        .to_owned()
}

/// Holds a TCP connection open until the node closes it.
async fn until_closed(mut stream: TcpStream) {
    let mut buffer = [0u8; 64];
    while let Ok(Ok(n)) =
        tokio::time::timeout(Duration::from_secs(5), stream.read(&mut buffer)).await
    {
        if n == 0 {
            return;
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_limit_is_logged_when_it_bites() {
    log();
    // Before the upgrade: headers too slow, too many waiting, too many from one address.
    let served = serve(Options {
        admission: Admission {
            header_timeout: Duration::from_millis(200),
            pending: 2,
            per_peer: 1,
            // Each refusal logged whole: a period ends between any two.
            refusal_log_every: Duration::from_millis(20),
            ..Admission::default()
        },
        ..Options::default()
    })
    .await;
    let at = address(&served.url);
    let first = TcpStream::connect(&at).await.expect("connects");
    let second = TcpStream::connect(&at).await.expect("connects");
    until_closed(second).await;
    logged("its address has 1 open, the most one address may have").await;
    until_closed(first).await;
    logged("no complete request headers within 200ms").await;
    drop(served);
    let served = serve(Options {
        admission: Admission {
            pending: 1,
            // Each refusal logged whole: a period ends between any two.
            refusal_log_every: Duration::from_millis(20),
            ..Admission::default()
        },
        ..Options::default()
    })
    .await;
    let at = address(&served.url);
    let _waiting = TcpStream::connect(&at).await.expect("connects");
    until_closed(TcpStream::connect(&at).await.expect("connects")).await;
    logged("1 connections are waiting to send their request").await;
    drop(served);

    // After: an idle client, an oversized frame, too many subscriptions, a scene over the
    // quota, too many clients.
    let served = serve_quota(
        Options {
            max_clients: 2,
            limits: Limits {
                idle: Duration::from_millis(200),
                frame: 1024,
                ..Limits::default()
            },
            ..Options::default()
        },
        1,
    )
    .await;
    let mut idle = Client::connect(&served.url).await;
    assert!(idle.next().await.is_none());
    logged("a client with no subscription sent no request for 200ms; disconnected").await;
    let mut client = Client::connect(&served.url).await;
    client.send_text(&" ".repeat(2048)).await;
    logged("a frame refused: a frame of 2048 bytes, more than the 1024").await;
    for n in 0..=cooperation_server::connection::MAX_SUBSCRIPTIONS {
        let topic = "/api/planning/velocity_factors";
        client
            .send(&json!({"op": "subscribe", "id": n, "topic": topic}))
            .await;
    }
    logged("a subscription refused: the connection holds 64").await;
    let statuses = vec![status(1, true, 10.0), status(2, true, 10.0)];
    client
        .send(
            &json!({"op": "call_service", "service": "/cooperation/rtc/sync",
                      "args": {"interface": "intersection", "statuses": statuses}}),
        )
        .await;
    logged("a scene refused: scene").await;
    let _second = Client::connect(&served.url).await;
    let refused = Client::connect_as(&served.url, None).await;
    assert_eq!(refused.err(), Some(503));
    logged("a client refused: this node serves as many clients as it may").await;
    drop(served);

    // With credentials: none presented, and a credential's places full.
    let credentials = Credentials::parse(
        "operator panel logged-operator-0123456789abcdef",
        &["intersection"],
        1,
    )
    .expect("credentials");
    // Refusals after a period's first are summed up at its end (here, every 200 ms): the
    // second refusal below is said in that summary.
    let served = serve(Options {
        credentials: Some(credentials),
        admission: Admission {
            refusal_log_every: Duration::from_millis(200),
            ..Admission::default()
        },
        ..Options::default()
    })
    .await;
    assert_eq!(Client::connect_as(&served.url, None).await.err(), Some(401));
    logged("a client refused: no credential presented").await;
    let token = "logged-operator-0123456789abcdef";
    let _operator = Client::connect_as(&served.url, Some(token))
        .await
        .expect("in");
    assert_eq!(
        Client::connect_as(&served.url, Some(token)).await.err(),
        Some(503)
    );
    logged("credential \"panel\" has 1 connections open, the most it may have").await;
}

/// The line of the log that says `text` (whole, or as the last of a period's summary).
fn line_saying(text: &str) -> String {
    let all =
        String::from_utf8_lossy(&log().lock().unwrap_or_else(PoisonError::into_inner)).into_owned();
    all.lines()
        .find(|line| line.contains(text))
        .unwrap_or_default()
        .to_owned()
}

/// On a node without credentials whose places are all taken, a client from an address with
/// fewer takes the place of the oldest client of the address with the most: the client let in
/// and the client closed are both logged, each with its address (`docs/server.md`, *Limits and
/// faults*).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_let_in_in_anothers_place_and_the_one_closed_are_both_logged() {
    log();
    let served = serve(Options {
        max_clients: 2,
        admission: Admission {
            // Each logged whole, or else as the last of a summary: a period ends between them.
            refusal_log_every: Duration::from_millis(20),
            ..Admission::default()
        },
        ..Options::default()
    })
    .await;
    let mut oldest = Client::connect_from(&served.url, "127.0.0.11")
        .await
        .expect("in");
    let _second = Client::connect_from(&served.url, "127.0.0.11")
        .await
        .expect("in");
    let _newcomer = Client::connect_from(&served.url, "127.0.0.12")
        .await
        .expect("in, in the place of 127.0.0.11's oldest");
    assert!(oldest.next().await.is_none(), "the oldest client is closed");
    let let_in =
        "a client let in in place of the oldest client of the address with the most of the 2 clients";
    logged(let_in).await;
    assert!(
        line_saying(let_in).contains("127.0.0.12"),
        "{}",
        line_saying(let_in)
    );
    let closed = "a client closed: a client from an address with fewer took its place";
    logged(closed).await;
    assert!(
        line_saying(closed).contains("127.0.0.11"),
        "{}",
        line_saying(closed)
    );
}

/// Asks for a WebSocket from `from` (a loopback address) with a token the node does not know;
/// the status line of the answer.
async fn knock(at: &str, from: &str) -> String {
    let socket = tokio::net::TcpSocket::new_v4().expect("a socket");
    socket
        .bind(format!("{from}:0").parse().expect("an address"))
        .expect("bound");
    let mut stream = socket
        .connect(at.parse().expect("an address"))
        .await
        .expect("connects");
    let request = format!(
        "GET /?token=not-a-token-of-this-node-0123456789 HTTP/1.1\r\nHost: {at}\r\n\
         Connection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Version: 13\r\n\
         Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n"
    );
    tokio::io::AsyncWriteExt::write_all(&mut stream, request.as_bytes())
        .await
        .expect("sent");
    let mut answer = vec![0; 512];
    let n = stream.read(&mut answer).await.expect("an answer");
    String::from_utf8_lossy(&answer[..n])
        .lines()
        .next()
        .unwrap_or_default()
        .to_owned()
}

/// A client guessing tokens does not fill the log: of a burst of 40 refused clients (5 wrong
/// tokens answered 401, then 35 upgrades refused while the address is locked out for them),
/// the first of each period is logged whole and the rest summed up in one line at the period's
/// end.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_burst_of_refused_clients_is_summed_up_not_logged_one_by_one() {
    log();
    let credentials = Credentials::parse(
        "operator panel burst-operator-0123456789abcdef",
        &["intersection"],
        1,
    )
    .expect("credentials");
    let served = serve(Options {
        credentials: Some(credentials),
        admission: Admission {
            refusal_log_every: Duration::from_secs(1),
            ..Admission::default()
        },
        guesses: GuessLimits {
            lockout: Duration::from_secs(60),
            ..GuessLimits::default()
        },
        ..Options::default()
    })
    .await;
    let at = address(&served.url);
    for _ in 0..5 {
        assert_eq!(knock(&at, "127.0.0.77").await, "HTTP/1.1 401 Unauthorized");
    }
    for _ in 0..35 {
        assert_eq!(
            knock(&at, "127.0.0.77").await,
            "HTTP/1.1 429 Too Many Requests"
        );
    }
    logged("refused since the last refusal logged, from 1 address, 127.0.0.77; the last: a client refused: too many credentials the node does not have from this address: try again in 60 s").await;
    let text =
        String::from_utf8_lossy(&log().lock().unwrap_or_else(PoisonError::into_inner)).into_owned();
    let whole = text
        .lines()
        .filter(|line| line.contains("peer=127.0.0.77:") && line.contains("a client refused"))
        .count();
    // 40 refusals within a second or two: one period, or two if they straddle its end.
    assert!(
        (1..=2).contains(&whole),
        "{whole} lines logged whole:\n{text}"
    );
}
