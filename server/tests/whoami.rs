//! `/whoami` (`docs/server.md`, *Who may connect*): what a token lets a client in as and how
//! many of its places are taken, answered without taking one, refused as an upgrade would be,
//! and counted as a guess when wrong.

use std::time::Duration;

use serde_json::Value;
use tokio::io::{AsyncReadExt, AsyncWriteExt};

use crate::common::{serve, Client, WAIT};
use crate::guesses::connect_from;
use cooperation_server::{Credentials, GuessLimits, Options};

const OPERATOR: &str = "operator-token-0123456789abcdef";
const MODULE: &str = "module-token-0123456789abcdefgh";
const WRONG: &str = "operator-token-0123456789abcdeX";
const FILE: &str = "operator panel operator-token-0123456789abcdef\n\
    module lanes module-token-0123456789abcdefgh lane_change_left lane_change_right\n";

fn credentials(places: usize) -> Credentials {
    Credentials::parse(FILE, &["lane_change_left", "lane_change_right"], places)
        .expect("the credentials read")
}

/// The answer to `GET target` with `bearer` in the `Authorization` header: the status, the
/// `Retry-After` header and the body.
pub(crate) async fn ask(
    url: &str,
    target: &str,
    bearer: Option<&str>,
) -> (u16, Option<String>, String) {
    let address = url.trim_start_matches("ws://").trim_end_matches('/');
    let mut stream = tokio::time::timeout(WAIT, tokio::net::TcpStream::connect(address))
        .await
        .expect("connected in time")
        .expect("connected");
    let authorization = bearer
        .map(|token| format!("Authorization: Bearer {token}\r\n"))
        .unwrap_or_default();
    let request = format!(
        "GET {target} HTTP/1.1\r\nHost: {address}\r\n{authorization}Connection: close\r\n\r\n"
    );
    stream
        .write_all(request.as_bytes())
        .await
        .expect("the request sent");
    let mut answer = String::new();
    tokio::time::timeout(WAIT, stream.read_to_string(&mut answer))
        .await
        .expect("answered in time")
        .expect("an answer");
    let (head, body) = answer.split_once("\r\n\r\n").expect("a head and a body");
    let status = head
        .split(' ')
        .nth(1)
        .and_then(|code| code.parse().ok())
        .expect("a status");
    let retry = head.lines().find_map(|line| {
        let (name, value) = line.split_once(':')?;
        name.eq_ignore_ascii_case("retry-after")
            .then(|| value.trim().to_owned())
    });
    (status, retry, body.to_owned())
}

pub(crate) fn json(body: &str) -> Value {
    serde_json::from_str(body).unwrap_or_else(|error| panic!("{body:?}: {error}"))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn whoami_names_the_role_and_the_places_taken_and_takes_none() {
    let served = serve(Options {
        credentials: Some(credentials(2)),
        ..Options::default()
    })
    .await;
    let url = served.url.as_str();
    let (status, _, body) = ask(url, "/whoami", Some(OPERATOR)).await;
    assert_eq!(status, 200, "{body}");
    let answer = json(&body);
    assert_eq!(answer["role"], "operator", "{body}");
    assert_eq!(answer["credential"], "panel", "{body}");
    assert_eq!(answer["places"], 2, "{body}");
    assert_eq!(answer["open"], 0, "{body}");
    // Every operator decision: this node has its own core.
    assert_eq!(
        answer["decisions"],
        serde_json::json!([1, 2, 3, 4]),
        "{body}"
    );
    // A module's places fill: its answer says so, and names its interfaces.
    let _first = Client::connect_as(url, Some(MODULE)).await.expect("in");
    let (_, _, body) = ask(url, "/whoami", Some(MODULE)).await;
    assert_eq!(json(&body)["open"], 1, "{body}");
    let _second = Client::connect_as(url, Some(MODULE)).await.expect("in");
    let (status, _, body) = ask(url, "/whoami", Some(MODULE)).await;
    assert_eq!(
        status, 200,
        "a full credential is an answer, not a refusal: {body}"
    );
    let answer = json(&body);
    assert_eq!(answer["role"], "module", "{body}");
    assert_eq!(answer["open"], 2, "{body}");
    assert_eq!(
        answer["interfaces"],
        serde_json::json!(["lane_change_left", "lane_change_right"]),
        "{body}"
    );
    assert_eq!(Client::connect_as(url, Some(MODULE)).await.err(), Some(503));
    // Asking takes no place, however often: the operator's two are still free.
    for _ in 0..10 {
        assert_eq!(ask(url, "/whoami", Some(OPERATOR)).await.0, 200);
    }
    let _one = Client::connect_as(url, Some(OPERATOR)).await.expect("in");
    let _two = Client::connect_as(url, Some(OPERATOR)).await.expect("in");
    let (_, _, body) = ask(url, "/whoami", Some(OPERATOR)).await;
    assert_eq!(json(&body)["open"], 2, "{body}");
    drop(_one);
    drop(_two);
    // A node without credentials: anyone, with the places of the clients it serves.
    let open = serve(Options {
        max_clients: 3,
        ..Options::default()
    })
    .await;
    let _client = Client::connect_as(&open.url, None).await.expect("in");
    let (status, _, body) = ask(&open.url, "/whoami", None).await;
    assert_eq!(status, 200, "{body}");
    let answer = json(&body);
    assert_eq!(answer["role"], "anyone", "{body}");
    assert_eq!(answer["credential"], Value::Null, "{body}");
    assert_eq!(
        (answer["places"].clone(), answer["open"].clone()),
        (3.into(), 1.into())
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn whoami_refuses_as_an_upgrade_would_and_a_wrong_token_is_a_guess() {
    let served = serve(Options {
        credentials: Some(credentials(2)),
        guesses: GuessLimits {
            allowed: 3,
            lockout: Duration::from_secs(1),
            ..GuessLimits::default()
        },
        ..Options::default()
    })
    .await;
    let url = served.url.as_str();
    // No token, or one in the URL (read from the header only), is no guess.
    for _ in 0..5 {
        let (status, _, body) = ask(url, "/whoami", None).await;
        assert_eq!(status, 401, "{body}");
        assert!(body.contains("no credential presented"), "{body}");
        let (status, _, _) = ask(url, &format!("/whoami?token={OPERATOR}"), None).await;
        assert_eq!(status, 401);
    }
    // Three wrong tokens lock the address out, for the upgrade as well as for the question.
    for _ in 0..3 {
        let (status, _, body) = ask(url, "/whoami", Some(WRONG)).await;
        assert_eq!(status, 401, "{body}");
        assert!(
            body.contains("a credential the node does not have"),
            "{body}"
        );
    }
    let (status, retry, body) = ask(url, "/whoami", Some(OPERATOR)).await;
    assert_eq!((status, retry.as_deref()), (429, Some("1")), "{body}");
    assert!(body.contains("try again in 1 s"), "{body}");
    assert_eq!(
        connect_from(url, "127.0.0.1", Some(OPERATOR)).await,
        Err((429, Some("1".to_owned())))
    );
    // Another address is not held up.
    assert_eq!(connect_from(url, "127.0.0.2", Some(OPERATOR)).await, Ok(()));
}
