//! Token guesses (`docs/server.md`, *Who may connect*): a credential the node does not have,
//! presented again and again from one address, locks that address out for a while; a client
//! from another address, and a client that presents no credential, are not held up by it.

use std::time::Duration;

use crate::common::{serve, tcp_from, Client, WAIT};
use cooperation_server::{Credentials, GuessLimits, Options};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;

const OPERATOR: &str = "operator-token-0123456789abcdef";
const WRONG: &str = "operator-token-0123456789abcdeX";
const FILE: &str = "operator panel operator-token-0123456789abcdef\n";
const LOCKOUT: Duration = Duration::from_millis(400);

/// A WebSocket upgrade from `source` presenting `bearer`: let in, or refused with the HTTP
/// status and its `Retry-After`.
pub(crate) async fn connect_from(
    url: &str,
    source: &str,
    bearer: Option<&str>,
) -> Result<(), (u16, Option<String>)> {
    let mut request = url.into_client_request().expect("a request");
    if let Some(token) = bearer {
        request.headers_mut().insert(
            "authorization",
            format!("Bearer {token}").parse().expect("a header"),
        );
    }
    let stream = tcp_from(url, source).await;
    match tokio::time::timeout(WAIT, tokio_tungstenite::client_async(request, stream))
        .await
        .expect("answered in time")
    {
        Ok(_) => Ok(()),
        Err(tokio_tungstenite::tungstenite::Error::Http(response)) => Err((
            response.status().as_u16(),
            response
                .headers()
                .get("retry-after")
                .and_then(|value| value.to_str().ok())
                .map(str::to_owned),
        )),
        Err(other) => panic!("{url}: {other}"),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn guessed_credentials_lock_out_their_address_and_no_other() {
    let served = serve(Options {
        credentials: Some(Credentials::parse(FILE, &[], 4).expect("the credentials read")),
        guesses: GuessLimits {
            allowed: 3,
            lockout: LOCKOUT,
            ..GuessLimits::default()
        },
        ..Options::default()
    })
    .await;
    let url = served.url.as_str();
    // Clients that present no credential make no guess, however many.
    for _ in 0..10 {
        assert_eq!(connect_from(url, "127.0.0.1", None).await, Err((401, None)));
    }
    // Three wrong credentials from one address ...
    for _ in 0..3 {
        assert_eq!(
            connect_from(url, "127.0.0.1", Some(WRONG)).await,
            Err((401, None))
        );
    }
    // ... lock it out: even the right one is refused, unread, saying when to come back ...
    assert_eq!(
        connect_from(url, "127.0.0.1", Some(OPERATOR)).await,
        Err((429, Some("1".to_owned())))
    );
    assert_eq!(
        connect_from(url, "127.0.0.1", Some(WRONG)).await,
        Err((429, Some("1".to_owned())))
    );
    // ... while the operator from another address gets in at once.
    assert_eq!(connect_from(url, "127.0.0.2", Some(OPERATOR)).await, Ok(()));
    // After the lockout, the right credential is let in, and its address's guesses are
    // forgotten: the next lockout takes three guesses again, and lasts the first's time.
    tokio::time::sleep(LOCKOUT + Duration::from_millis(100)).await;
    assert_eq!(connect_from(url, "127.0.0.1", Some(OPERATOR)).await, Ok(()));
    for _ in 0..2 {
        assert_eq!(
            connect_from(url, "127.0.0.1", Some(WRONG)).await,
            Err((401, None))
        );
    }
    assert_eq!(connect_from(url, "127.0.0.1", Some(OPERATOR)).await, Ok(()));
    // A node without credentials has nothing to guess.
    let open = serve(Options::default()).await;
    for _ in 0..5 {
        assert!(Client::connect_as(&open.url, Some(WRONG)).await.is_ok());
    }
}

/// A second lockout in a row lasts twice the first.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_lockout_in_a_row_lasts_twice_the_last() {
    let served = serve(Options {
        credentials: Some(Credentials::parse(FILE, &[], 4).expect("the credentials read")),
        guesses: GuessLimits {
            allowed: 1,
            lockout: Duration::from_secs(1),
            ..GuessLimits::default()
        },
        ..Options::default()
    })
    .await;
    let url = served.url.as_str();
    assert_eq!(
        connect_from(url, "127.0.0.3", Some(WRONG)).await,
        Err((401, None))
    );
    assert_eq!(
        connect_from(url, "127.0.0.3", Some(OPERATOR)).await,
        Err((429, Some("1".to_owned())))
    );
    tokio::time::sleep(Duration::from_millis(1100)).await;
    assert_eq!(
        connect_from(url, "127.0.0.3", Some(WRONG)).await,
        Err((401, None))
    );
    assert_eq!(
        connect_from(url, "127.0.0.3", Some(OPERATOR)).await,
        Err((429, Some("2".to_owned())))
    );
}
