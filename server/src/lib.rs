//! `cooperation-server`: the cooperation AD API served over the rosbridge v2 protocol, with an
//! operator panel in a browser.
//!
//! One port serves a WebSocket for rosbridge clients (operators and planning modules) and,
//! over plain HTTP, the operator panel. The service engine ([`cooperation_adapters::engine`]) sits
//! behind one lock ([`cooperation_adapters::Shared`]) in a [`Node`]; the node's clock
//! ([`cooperation_adapters::clock`]) is the only place time is read. `docs/server.md` describes the
//! protocol, the planning modules' service and the limits.

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

pub mod access;
pub mod auth;
pub mod connection;
mod fair;
pub mod front;
pub mod guesses;
mod keyring;
pub mod node;
mod panel;
mod prefix;
mod refusals;
pub mod rosapi;
pub mod rosbridge;
pub use cooperation_adapters::engine::scenes;
pub mod sync;
mod who;

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::ws::WebSocketUpgrade;
use axum::extract::{Request, State as Extracted};
use axum::http::{HeaderMap, HeaderValue, StatusCode, Uri};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use tokio::net::TcpListener;
use tokio::sync::Semaphore;

pub use access::Access;
pub use auth::{Credentials, Grant};
pub use connection::Limits;
pub use front::Admission;
pub use guesses::GuessLimits;
pub use keyring::Reloaded;
pub use node::{Node, Topic, MAX_WAITING_CALLS};

/// How the node runs.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Options {
    /// The interval between periodic publications of the factors: the engine's
    /// ([`cooperation_adapters::engine::Options::publish_every_ms`]), set when the node is served.
    pub publish_every: Duration,
    /// At most this many clients without a credential at once (a node with no credentials).
    /// When all are taken, one more takes the place of the oldest client of the address prefix
    /// that has the most, if that is more than its own prefix has; otherwise it is
    /// answered HTTP 503.
    pub max_clients: usize,
    /// The credentials clients must present, each with places of its own; `None`: any client
    /// may do anything ([`auth`]).
    pub credentials: Option<Credentials>,
    /// The limits on connections before they become WebSockets ([`front`]).
    pub admission: Admission,
    /// The limits on token guesses ([`guesses`]).
    pub guesses: GuessLimits,
    /// Each connection's limits.
    pub limits: Limits,
    /// The origins and host names accepted besides the node's own ([`access`]).
    pub access: Access,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            publish_every: Duration::from_millis(cooperation_adapters::engine::PUBLISH_EVERY_MS),
            max_clients: 256,
            credentials: None,
            admission: Admission::default(),
            guesses: GuessLimits::default(),
            limits: Limits::default(),
            access: Access::default(),
        }
    }
}

#[derive(Clone)]
struct App {
    node: Arc<Node>,
    /// The places of the clients of a node without credentials.
    clients: Arc<fair::Fair>,
    /// How many.
    max_clients: usize,
    /// The credentials in force, with their places; `None`: a node without credentials.
    keyring: Option<Arc<keyring::Keyring>>,
    limits: Limits,
    access: Arc<Access>,
    refusals: Arc<refusals::Refusals>,
    guesses: Arc<guesses::Guesses>,
}

impl Options {
    /// Why these options cannot run a node, if they cannot: a zero interval or time limit, no
    /// client, or more clients than the runtime can count.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        let intervals = [
            ("the publication interval", self.publish_every),
            ("the write timeout", self.limits.write_timeout),
            ("the keepalive interval", self.limits.keepalive),
            ("the idle timeout", self.limits.idle),
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
        if let Some(credentials) = &self.credentials {
            if credentials.places == 0 || credentials.places > Semaphore::MAX_PERMITS {
                return Some(format!(
                    "{} connections per credential: give from 1 to {}",
                    credentials.places,
                    Semaphore::MAX_PERMITS
                ));
            }
        }
        if self.limits.hard_frame < self.limits.frame {
            return Some("the hard frame limit is below the frame limit".to_owned());
        }
        self.admission.problem().or_else(|| self.guesses.problem())
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
    serve_reloading(
        listener,
        node,
        options,
        futures_util::stream::pending(),
        shutdown,
    )
    .await
}

/// [`serve`], putting in force each set of credentials `reloads` yields: a credential that is
/// unchanged keeps its places and connections, every other one of the old set is revoked (its
/// connections closed, its token refused from then on), and a new one gets places of its own.
/// Each reload is logged with what it kept, revoked and added. A node without credentials
/// ignores them, saying so in its log.
///
/// # Errors
/// As [`serve`].
pub async fn serve_reloading(
    listener: TcpListener,
    node: Arc<Node>,
    options: Options,
    reloads: impl futures_util::Stream<Item = Credentials> + Send + 'static,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> std::io::Result<()> {
    if let Some(problem) = options.problem() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            problem,
        ));
    }
    // In the stack mode the relay's thread publishes, at the rate it was built with.
    if let Some(shared) = node.shared() {
        shared.update(|engine| engine.set_publish_every(options.publish_every));
    }
    let mut publisher = tokio::spawn(publish(Arc::clone(&node)));
    let mut ticker = tokio::spawn(tick(Arc::clone(&node)));
    let refusals = Arc::new(refusals::Refusals::new(options.admission.refusal_log_every));
    let summaries = tokio::spawn(sum_up(
        Arc::clone(&refusals),
        options.admission.refusal_log_every,
    ));
    let app = App {
        node,
        clients: fair::Fair::new(options.max_clients),
        max_clients: options.max_clients,
        keyring: options
            .credentials
            .map(|credentials| Arc::new(keyring::Keyring::new(credentials))),
        limits: options.limits,
        access: Arc::new(options.access),
        refusals: Arc::clone(&refusals),
        guesses: Arc::new(guesses::Guesses::new(options.guesses)),
    };
    let reloader = tokio::spawn(reload(app.keyring.clone(), reloads));
    let router = Router::new()
        .route("/", get(root))
        .route("/whoami", get(who::whoami))
        .merge(panel::routes())
        .layer(axum::middleware::from_fn_with_state(app.clone(), guard))
        .with_state(app);
    let served = front::accept(listener, router, options.admission, refusals, shutdown);
    let served = tokio::select! {
        () = served => Ok(()),
        stopped = &mut publisher => Err(std::io::Error::other(format!(
            "the publishing task stopped: {stopped:?}"
        ))),
        stopped = &mut ticker => Err(std::io::Error::other(format!(
            "the clock's task stopped: {stopped:?}"
        ))),
    };
    publisher.abort();
    ticker.abort();
    summaries.abort();
    reloader.abort();
    served
}

/// Puts each set of credentials `reloads` yields in force.
async fn reload(
    keyring: Option<Arc<keyring::Keyring>>,
    reloads: impl futures_util::Stream<Item = Credentials> + Send,
) {
    use futures_util::StreamExt;
    let mut reloads = std::pin::pin!(reloads);
    while let Some(credentials) = reloads.next().await {
        let Some(keyring) = &keyring else {
            tracing::warn!(
                "credentials to reload, but this node serves without credentials: ignored"
            );
            continue;
        };
        let Reloaded {
            kept,
            revoked,
            added,
        } = keyring.reload(credentials);
        tracing::warn!(
            kept = %kept.join(", "),
            revoked = %revoked.join(", "),
            added = %added.join(", "),
            "credentials reloaded"
        );
    }
}

/// Ends a period of the log of refusals every `every`.
async fn sum_up(refusals: Arc<refusals::Refusals>, every: Duration) {
    let mut interval = tokio::time::interval(every);
    interval.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    interval.tick().await;
    loop {
        interval.tick().await;
        if let Some(summary) = refusals.end_period() {
            tracing::warn!("{summary}");
        }
    }
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
        let peer = request
            .extensions()
            .get::<front::Peer>()
            .map_or_else(|| "unknown".to_owned(), |peer| peer.address.to_string());
        app.refusals
            .log(&peer, &format!("a request refused: {refusal}"));
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

/// `/`: a WebSocket upgrade is a rosbridge client, let in with its credential's grant and
/// place ([`auth`]); anything else gets the panel.
async fn root(
    Extracted(app): Extracted<App>,
    peer: Option<axum::Extension<front::Peer>>,
    uri: Uri,
    headers: HeaderMap,
    upgrade: Result<WebSocketUpgrade, axum::extract::ws::rejection::WebSocketUpgradeRejection>,
) -> Response {
    let Ok(upgrade) = upgrade else {
        return panel::page().into_response();
    };
    let peer = peer.map(|axum::Extension(peer)| peer);
    let who = match who::identify(&app, peer.as_ref(), &headers, &uri) {
        Ok(who) => who,
        Err(refused) => return *refused,
    };
    let address = peer.as_ref().map(|peer| peer.address);
    let Some((held, stop)) = who::take_place(&app, &who, address) else {
        return who::refuse(
            &app,
            peer.as_ref(),
            StatusCode::SERVICE_UNAVAILABLE,
            who.full(),
        );
    };
    let grant = who.grant;
    if let (Grant::Credential(credential), Some(peer)) = (&grant, &peer) {
        tracing::info!(peer = %peer.address, credential = %credential.name, "a client authenticated");
    }
    // A WebSocket without a credential counts against its address for as long as it is open.
    let seat = matches!(grant, Grant::Anyone)
        .then(|| peer.map(|peer| peer.seat))
        .flatten();
    let limits = app.limits;
    upgrade
        .max_message_size(limits.hard_frame)
        .max_frame_size(limits.hard_frame)
        .on_upgrade(move |socket| async move {
            connection::serve(socket, app.node, limits, grant, stop).await;
            drop(held);
            drop(seat);
        })
}

/// Publishes both topics periodically, and soon after a change is announced.
async fn publish(node: Arc<Node>) {
    loop {
        let wait = node.until_publication();
        tokio::select! {
            () = tokio::time::sleep(wait) => {}
            () = node.publish_asked() => {}
        }
        blocking(&node, Node::publish).await;
    }
}

/// Tells the core the time from the node's monotonic clock whenever the engine asks, as every
/// host does ([`Node::until_timeout`]): a scene's time to live runs out, a publication is due,
/// or the step limit would otherwise leave time uncounted (`[COOP-ENGINE-STEP.1]`).
async fn tick(node: Arc<Node>) {
    loop {
        blocking(&node, Node::tick).await;
        tokio::time::sleep(node.until_timeout()).await;
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
