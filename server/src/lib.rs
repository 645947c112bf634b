//! `cooperation-server`: the cooperation AD API served over the rosbridge v2 protocol, with an
//! operator panel in a browser.
//!
//! One port serves a WebSocket for rosbridge clients (operators and planning modules) and,
//! over plain HTTP, the operator panel. The verified core and its RTC interfaces sit behind
//! one lock ([`cooperation_ros::Shared`]) in a [`Node`]; the node's clock ([`clock`]) is the
//! only place time is read. `docs/server.md` describes the protocol, the planning modules' service and the
//! limits.

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

pub mod access;
pub mod clock;
pub mod connection;
pub mod node;
mod panel;
pub mod rosbridge;
pub mod sync;

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::ws::WebSocketUpgrade;
use axum::extract::{Request, State as Extracted};
use axum::http::HeaderValue;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use tokio::net::TcpListener;
use tokio::sync::Semaphore;

pub use access::Access;
pub use connection::Limits;
pub use node::{Node, Topic};

/// How the node runs.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Options {
    /// The interval between periodic publications of the factors.
    pub publish_every: Duration,
    /// The interval between ticks of the core's clock.
    pub tick_every: Duration,
    /// At most this many clients at once; one more is answered HTTP 503.
    pub max_clients: usize,
    /// Each connection's limits.
    pub limits: Limits,
    /// The origins and host names accepted besides the node's own ([`access`]).
    pub access: Access,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            publish_every: Duration::from_millis(200),
            tick_every: Duration::from_millis(100),
            max_clients: 256,
            limits: Limits::default(),
            access: Access::default(),
        }
    }
}

#[derive(Clone)]
struct App {
    node: Arc<Node>,
    clients: Arc<Semaphore>,
    limits: Limits,
    access: Arc<Access>,
}

impl Options {
    /// Why these options cannot run a node, if they cannot: a zero interval or time limit, no
    /// client, or more clients than the runtime can count.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        let intervals = [
            ("the publication interval", self.publish_every),
            ("the tick interval", self.tick_every),
            ("the write timeout", self.limits.write_timeout),
            ("the keepalive interval", self.limits.keepalive),
        ];
        if let Some((name, _)) = intervals.iter().find(|(_, every)| every.is_zero()) {
            return Some(format!("{name} is zero"));
        }
        if self.max_clients == 0 || self.max_clients > Semaphore::MAX_PERMITS {
            return Some(format!(
                "{} clients: give from 1 to {}",
                self.max_clients,
                Semaphore::MAX_PERMITS
            ));
        }
        None
    }
}

/// Serves `node` on `listener` until `shutdown` completes: the WebSocket, the panel, the
/// periodic publications and the clock.
///
/// # Errors
/// [`std::io::ErrorKind::InvalidInput`] with [`Options::problem`]; the listener's failure; an
/// error if the publishing or the clock's task stops, which would leave the streams or the
/// expiry silently stopped.
pub async fn serve(
    listener: TcpListener,
    node: Arc<Node>,
    options: Options,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    if let Some(problem) = options.problem() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            problem,
        ));
    }
    let mut publisher = tokio::spawn(publish(Arc::clone(&node), options.publish_every));
    let mut ticker = tokio::spawn(tick(Arc::clone(&node), options.tick_every));
    let app = App {
        node,
        clients: Arc::new(Semaphore::new(options.max_clients)),
        limits: options.limits,
        access: Arc::new(options.access),
    };
    let router = Router::new()
        .route("/", get(root))
        .merge(panel::routes())
        .layer(axum::middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app);
    let served = axum::serve(listener, router).with_graceful_shutdown(shutdown);
    let served = tokio::select! {
        served = served => served,
        stopped = &mut publisher => Err(std::io::Error::other(format!(
            "the publishing task stopped: {stopped:?}"
        ))),
        stopped = &mut ticker => Err(std::io::Error::other(format!(
            "the clock's task stopped: {stopped:?}"
        ))),
    };
    publisher.abort();
    ticker.abort();
    served
}

/// Binds `address`.
///
/// # Errors
/// The bind's failure.
pub async fn bind(address: SocketAddr) -> std::io::Result<TcpListener> {
    TcpListener::bind(address).await
}

/// Every request: refused with 403 if its host or, for a WebSocket, its page's origin is not
/// accepted ([`access`]); else served, with the headers that forbid framing its page.
async fn guard(Extracted(app): Extracted<App>, request: Request, next: Next) -> Response {
    if let Err(refusal) = app.access.check(request.headers()) {
        tracing::warn!("a request refused: {refusal}");
        return (refusal.status(), refusal.to_string()).into_response();
    }
    let mut response = next.run(request).await;
    for (name, value) in access::FRAMING {
        response
            .headers_mut()
            .insert(name, HeaderValue::from_static(value));
    }
    response
}

/// `/`: a WebSocket upgrade is a rosbridge client; anything else gets the panel.
async fn root(
    Extracted(app): Extracted<App>,
    upgrade: Result<WebSocketUpgrade, axum::extract::ws::rejection::WebSocketUpgradeRejection>,
) -> Response {
    let Ok(upgrade) = upgrade else {
        return panel::page().into_response();
    };
    let Ok(permit) = Arc::clone(&app.clients).try_acquire_owned() else {
        tracing::warn!("a client refused: the node serves as many as it may");
        return (
            axum::http::StatusCode::SERVICE_UNAVAILABLE,
            "this node serves as many clients as it may; try again later",
        )
            .into_response();
    };
    let limits = app.limits;
    upgrade
        .max_message_size(limits.hard_frame)
        .max_frame_size(limits.hard_frame)
        .on_upgrade(move |socket| async move {
            connection::serve(socket, app.node, limits).await;
            drop(permit);
        })
}

/// Publishes both topics periodically, and soon after a change is announced.
async fn publish(node: Arc<Node>, every: Duration) {
    let mut interval = tokio::time::interval(every);
    interval.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        tokio::select! {
            _ = interval.tick() => {}
            () = node.publish_asked() => {}
        }
        blocking(&node, Node::publish).await;
    }
}

/// Ticks the core from the node's monotonic clock.
async fn tick(node: Arc<Node>, every: Duration) {
    let mut interval = tokio::time::interval(every);
    interval.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        interval.tick().await;
        blocking(&node, Node::tick).await;
    }
}

/// Runs `work` on the blocking pool: it takes the core's lock, which must not hold up the
/// tasks of the connections.
async fn blocking(node: &Arc<Node>, work: fn(&Node)) {
    let node = Arc::clone(node);
    if let Err(error) = tokio::task::spawn_blocking(move || work(&node)).await {
        tracing::error!(%error, "the node's periodic work failed");
    }
}
