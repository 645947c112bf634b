//! Who may reach the node from a browser (`docs/server.md`, *Who may connect*): a request must
//! name a host the node answers to, a WebSocket from a web page must come from the node's own
//! page or an allowed origin, and no page may frame the panel. Raw HTTP over loopback, so that
//! every header is the test's choice.

use crate::common::{serve, WAIT};
use cooperation_server::{Access, Options};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

/// The status code and the headers (lower-cased) of the node's answer to a GET of `/` with
/// `headers`, and whether it upgraded.
async fn get(address: &str, headers: &[(&str, &str)]) -> (u16, String) {
    let mut stream = TcpStream::connect(address).await.expect("connected");
    let mut request = String::from("GET / HTTP/1.1\r\n");
    for (name, value) in headers {
        request += &format!("{name}: {value}\r\n");
    }
    request += "\r\n";
    stream
        .write_all(request.as_bytes())
        .await
        .expect("request sent");
    let mut answer = Vec::new();
    let mut buffer = [0; 4096];
    // Read the status line and headers; the connection may stay open (an upgrade, keep-alive).
    while !answer.windows(4).any(|w| w == b"\r\n\r\n") {
        let read = tokio::time::timeout(WAIT, stream.read(&mut buffer))
            .await
            .expect("an answer in time")
            .expect("read");
        assert!(read > 0, "the node closed without answering");
        answer.extend_from_slice(buffer.get(..read).expect("within the buffer"));
    }
    let text = String::from_utf8_lossy(&answer).to_lowercase();
    let status = text
        .split(' ')
        .nth(1)
        .and_then(|code| code.parse().ok())
        .expect("a status code");
    (status, text)
}

/// The headers of a WebSocket upgrade from a page of `origin` (none: not a browser).
fn upgrade<'a>(host: &'a str, origin: Option<&'a str>) -> Vec<(&'a str, &'a str)> {
    let mut headers = vec![
        ("Host", host),
        ("Connection", "Upgrade"),
        ("Upgrade", "websocket"),
        ("Sec-WebSocket-Version", "13"),
        ("Sec-WebSocket-Key", "dGhlIHNhbXBsZSBub25jZQ=="),
    ];
    headers.extend(origin.map(|origin| ("Origin", origin)));
    headers
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_websocket_from_another_origin_is_refused() {
    let served = serve(Options {
        access: Access {
            origins: vec!["https://ops.example".into()],
            ..Access::default()
        },
        ..Options::default()
    })
    .await;
    let address = served.url.trim_start_matches("ws://").trim_end_matches('/');
    let own = format!("http://{address}");
    let port = address.rsplit(':').next().expect("a port");
    let (status, _) = get(address, &upgrade(address, None)).await;
    assert_eq!(status, 101, "a client that is not a browser");
    let (status, _) = get(address, &upgrade(address, Some(&own))).await;
    assert_eq!(status, 101, "the node's own panel");
    let (status, _) = get(address, &upgrade(address, Some("https://ops.example"))).await;
    assert_eq!(status, 101, "an allowed origin");
    let other_port = format!(
        "http://127.0.0.1:{}",
        port.parse::<u16>().expect("a port") ^ 1
    );
    let localhost = format!("http://localhost:{port}");
    for origin in [
        "http://evil.example",
        "null",
        other_port.as_str(),
        localhost.as_str(),
    ] {
        let (status, text) = get(address, &upgrade(address, Some(origin))).await;
        assert_eq!(status, 403, "{origin}: {text}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_request_naming_another_host_is_refused() {
    let served = serve(Options {
        access: Access {
            hosts: vec!["node.example".into()],
            ..Access::default()
        },
        ..Options::default()
    })
    .await;
    let address = served.url.trim_start_matches("ws://").trim_end_matches('/');
    let port = address.rsplit(':').next().expect("a port");
    for host in [
        address.to_owned(),
        format!("localhost:{port}"),
        format!("node.example:{port}"),
    ] {
        let (status, text) = get(address, &[("Host", &host)]).await;
        assert_eq!(status, 200, "{host}: {text}");
    }
    // A name that resolves to the node only because a page made it so (DNS rebinding): the
    // panel and the WebSocket alike.
    let rebound = format!("evil.example:{port}");
    let (status, _) = get(address, &[("Host", &rebound)]).await;
    assert_eq!(status, 403);
    let own = format!("http://{rebound}");
    let (status, _) = get(address, &upgrade(&rebound, Some(&own))).await;
    assert_eq!(status, 403);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn no_page_may_frame_the_panel() {
    let served = serve(Options::default()).await;
    let address = served.url.trim_start_matches("ws://").trim_end_matches('/');
    let (status, text) = get(address, &[("Host", address)]).await;
    assert_eq!(status, 200);
    let policy = text
        .lines()
        .find_map(|line| line.strip_prefix("content-security-policy: "))
        .unwrap_or_else(|| panic!("no content-security-policy: {text}"));
    for directive in [
        "frame-ancestors 'none'",
        "script-src 'self'",
        "connect-src 'self'",
        "default-src 'none'",
    ] {
        assert!(policy.contains(directive), "{directive}: {policy}");
    }
    assert!(text.contains("x-frame-options: deny"), "{text}");
}
