//! A node served in-process on a free loopback port, and a rosbridge client for it.

#![allow(dead_code, unreachable_pub)]

use std::sync::Arc;
use std::time::Duration;

use cooperation_server::{Node, Options};
use futures_util::{SinkExt, StreamExt};
use serde_json::{json, Value};
use tokio::net::TcpStream;
use tokio::sync::oneshot;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream};

/// The longest any one step of a test waits.
pub const WAIT: Duration = Duration::from_secs(10);

/// The default settings file.
pub const SETTINGS: &str = include_str!("../../../config/cooperation.param.yaml");

/// A served node; stops when dropped.
pub struct Served {
    pub node: Arc<Node>,
    pub url: String,
    stop: Option<oneshot::Sender<()>>,
}

impl Drop for Served {
    fn drop(&mut self) {
        if let Some(stop) = self.stop.take() {
            let _ = stop.send(());
        }
    }
}

/// Serves a node with the default settings and these options.
pub async fn serve(options: Options) -> Served {
    serve_quota(options, cooperation_server::node::SCENE_QUOTA).await
}

/// Serves a node with the default settings, each RTC interface holding at most `quota` live
/// scenes.
pub async fn serve_quota(options: Options, quota: usize) -> Served {
    let config =
        cooperation_adapters::settings::parse(SETTINGS).expect("the default settings read");
    serve_config(config, options, quota).await
}

/// Serves a node with `config`, each RTC interface holding at most `quota` live scenes.
pub async fn serve_config(config: cooperation::Config, options: Options, quota: usize) -> Served {
    let node =
        Arc::new(Node::with_scene_quota(config, quota).expect("the settings are a configuration"));
    serve_node(node, options).await
}

/// Serves `node` with `options` on a loopback port.
pub async fn serve_node(node: Arc<Node>, options: Options) -> Served {
    serve_reloading(node, options, futures_util::stream::pending()).await
}

/// Serves `node` with `options` on a loopback port, reloading the credentials `reloads` yields.
pub async fn serve_reloading(
    node: Arc<Node>,
    options: Options,
    reloads: impl futures_util::Stream<Item = cooperation_server::Credentials> + Send + 'static,
) -> Served {
    let listener = cooperation_server::bind("127.0.0.1:0".parse().expect("an address"))
        .await
        .expect("a loopback port");
    let url = format!("ws://{}/", listener.local_addr().expect("its address"));
    let (stop, stopped) = oneshot::channel::<()>();
    tokio::spawn(cooperation_server::serve_reloading(
        listener,
        Arc::clone(&node),
        options,
        reloads,
        async move {
            let _ = stopped.await;
        },
    ));
    Served {
        node,
        url,
        stop: Some(stop),
    }
}

/// A rosbridge client.
pub struct Client {
    pub ws: WebSocketStream<MaybeTlsStream<TcpStream>>,
    next_id: u64,
}

/// A scene's 16 bytes from a number.
pub fn uuid(n: u128) -> Value {
    json!({ "uuid": n.to_be_bytes().to_vec() })
}

/// A `tier4_rtc_msgs/CooperateStatus` reported by a module.
pub fn status(n: u128, safe: bool, distance: f32) -> Value {
    json!({
        "stamp": {"sec": 0, "nanosec": 0},
        "uuid": uuid(n),
        "module": {"type": 0},
        "safe": safe,
        "command_status": {"type": 0},
        "state": {"type": 0},
        "auto_mode": false,
        "start_distance": distance,
        "finish_distance": distance + 30.0,
    })
}

/// A TCP connection to the node at `url` from the local address `source` (`127.0.0.2`).
pub async fn tcp_from(url: &str, source: &str) -> TcpStream {
    let target: std::net::SocketAddr = url
        .trim_start_matches("ws://")
        .trim_end_matches('/')
        .parse()
        .expect("the node's address");
    let socket = tokio::net::TcpSocket::new_v4().expect("a socket");
    socket
        .bind(format!("{source}:0").parse().expect("an address"))
        .expect("bound to the source address");
    tokio::time::timeout(WAIT, socket.connect(target))
        .await
        .expect("connected in time")
        .expect("connected")
}

impl Client {
    pub async fn connect(url: &str) -> Self {
        let (ws, _) = tokio::time::timeout(WAIT, tokio_tungstenite::connect_async(url))
            .await
            .expect("connected in time")
            .expect("connected");
        Self { ws, next_id: 0 }
    }

    /// Connects presenting `bearer` in an `Authorization` header: the client, or the HTTP
    /// status it was refused with.
    pub async fn connect_as(url: &str, bearer: Option<&str>) -> Result<Self, u16> {
        use tokio_tungstenite::tungstenite::client::IntoClientRequest;
        let mut request = url.into_client_request().expect("a request");
        if let Some(token) = bearer {
            request.headers_mut().insert(
                "authorization",
                format!("Bearer {token}").parse().expect("a header"),
            );
        }
        Self::settle(
            url,
            tokio::time::timeout(WAIT, tokio_tungstenite::connect_async(request))
                .await
                .expect("answered in time"),
        )
    }

    /// Connects from the local address `source` (`127.0.0.2`), without a credential: the
    /// client, or the HTTP status it was refused with.
    pub async fn connect_from(url: &str, source: &str) -> Result<Self, u16> {
        let stream = tcp_from(url, source).await;
        Self::settle(
            url,
            tokio::time::timeout(
                WAIT,
                tokio_tungstenite::client_async(url, MaybeTlsStream::Plain(stream)),
            )
            .await
            .expect("answered in time"),
        )
    }

    /// The client of a handshake's result, or the HTTP status it was refused with.
    fn settle<R>(
        url: &str,
        result: Result<
            (WebSocketStream<MaybeTlsStream<TcpStream>>, R),
            tokio_tungstenite::tungstenite::Error,
        >,
    ) -> Result<Self, u16> {
        match result {
            Ok((ws, _)) => Ok(Self { ws, next_id: 0 }),
            Err(tokio_tungstenite::tungstenite::Error::Http(response)) => {
                Err(response.status().as_u16())
            }
            Err(other) => panic!("{url}: {other}"),
        }
    }

    pub async fn send(&mut self, frame: &Value) {
        self.send_text(&frame.to_string()).await;
    }

    pub async fn send_text(&mut self, text: &str) {
        tokio::time::timeout(WAIT, self.ws.send(Message::text(text)))
            .await
            .expect("sent in time")
            .expect("sent");
    }

    /// The next text frame, as JSON; `None` when the connection ends.
    pub async fn next(&mut self) -> Option<Value> {
        loop {
            let message = tokio::time::timeout(WAIT, self.ws.next())
                .await
                .expect("a frame in time")?;
            match message {
                Ok(Message::Text(text)) => {
                    return Some(serde_json::from_str(text.as_str()).expect("JSON from the node"))
                }
                Ok(Message::Close(_)) | Err(_) => return None,
                Ok(_) => {}
            }
        }
    }

    /// The next frame whose `op` is `op`, skipping publications and other frames.
    /// Panics if none comes within [`WAIT`], however many other frames come meanwhile.
    pub async fn next_op(&mut self, op: &str) -> Value {
        let deadline = tokio::time::Instant::now() + WAIT;
        loop {
            let frame = tokio::time::timeout_at(deadline, self.next())
                .await
                .unwrap_or_else(|_| panic!("no {op:?} frame within {WAIT:?}"))
                .expect("the connection stays open");
            if frame["op"] == op {
                return frame;
            }
        }
    }

    /// Sends a `call_service` and returns its `service_response`.
    pub async fn call(&mut self, service: &str, args: Value) -> Value {
        self.next_id += 1;
        let id = format!("call:{}", self.next_id);
        self.send(&json!({"op": "call_service", "id": id, "service": service, "args": args}))
            .await;
        loop {
            let frame = self.next_op("service_response").await;
            if frame["id"] == id.as_str() {
                return frame;
            }
        }
    }

    pub async fn set_commands(&mut self, commands: &[(u128, u8)]) -> Value {
        let commands: Vec<Value> = commands
            .iter()
            .map(|&(n, decision)| json!({"uuid": uuid(n), "cooperator": {"decision": decision}}))
            .collect();
        self.call(
            "/api/planning/cooperation/set_commands",
            json!({ "commands": commands }),
        )
        .await
    }

    /// A module's sync of these statuses through `interface`; returns the response's values.
    pub async fn sync(&mut self, interface: &str, statuses: Vec<Value>) -> Value {
        let response = self
            .call(
                "/cooperation/rtc/sync",
                json!({"interface": interface, "statuses": statuses}),
            )
            .await;
        assert_eq!(response["result"], true, "{response}");
        response["values"].clone()
    }

    pub async fn subscribe(&mut self, topic: &str) {
        self.send(&json!({"op": "subscribe", "topic": topic})).await;
    }
}

/// The operator decision a publication shows for scene `n`, if it lists the scene.
pub fn operator_decision(publication: &Value, n: u128) -> Option<u64> {
    let uuid = uuid(n);
    publication["msg"]["factors"]
        .as_array()?
        .iter()
        .flat_map(|factor| {
            factor["cooperation"]
                .as_array()
                .cloned()
                .unwrap_or_default()
        })
        .find(|status| status["uuid"] == uuid)
        .and_then(|status| status["cooperator"]["decision"].as_u64())
}
