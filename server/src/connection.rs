//! One client's WebSocket: a reader that answers its frames and a writer that sends the
//! answers and its topics' publications.
//!
//! - **Answers** wait in a bounded queue ([`Limits::queue`]). When it is full the reader stops
//!   reading that client's frames until the writer catches up: a client that sends faster
//!   than it reads slows only itself, and no answer is dropped.
//! - **Publications** are not queued: each topic holds only its newest publication, and a
//!   subscriber that is still sending an older one skips the ones in between. A slow
//!   subscriber therefore gets fewer publications, each complete and current.
//! - **A stalled client** (one frame not handed to its connection within
//!   [`Limits::write_timeout`]) is disconnected, and so is a silent one: the node pings every
//!   [`Limits::keepalive`] and disconnects a client from which nothing, not even the pong,
//!   arrives for three times as long.
//! - **An idle client**, one that holds no subscription and has sent no request for
//!   [`Limits::idle`], is disconnected: it holds a place and does nothing with it.
//! - **Subscriptions** are kept per `id`, as rosbridge keeps them: a topic is sent while any
//!   of its subscriptions lasts, at most once per the smallest `throttle_rate` among them, and
//!   each publication at most once per connection (a new subscription gets the newest
//!   publication at once only if the connection was never sent it).

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::ws::{CloseFrame, Message, Utf8Bytes, WebSocket};
use futures_util::{SinkExt, StreamExt};
use tokio::sync::{mpsc, watch};
use tokio::time::Instant;

use crate::auth::Grant;
use crate::node::{Node, Publication, Topic};
use crate::rosbridge::{self, Action};

/// How much one connection may hold and take.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Limits {
    /// Frames above this many bytes are refused with a `status` frame and the connection
    /// goes on.
    pub frame: usize,
    /// Messages above this many bytes, whole or still arriving in fragments, close the
    /// connection when they pass it: the most a connection's unread message holds.
    pub hard_frame: usize,
    /// Answers waiting to be sent, per connection.
    pub queue: usize,
    /// The longest a frame may take to be handed to the client's connection (its socket
    /// buffers full) before the client is disconnected.
    pub write_timeout: Duration,
    /// The node pings the client this often; a client from which nothing (not even the pong)
    /// arrives for three times as long is disconnected.
    pub keepalive: Duration,
    /// A client that holds no subscription and has sent no request for this long is
    /// disconnected.
    pub idle: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            frame: 1 << 20,
            hard_frame: 2 << 20,
            queue: 64,
            write_timeout: Duration::from_secs(10),
            keepalive: Duration::from_secs(20),
            idle: Duration::from_secs(60),
        }
    }
}

enum Out {
    Frame(Utf8Bytes),
    /// The topic is to be sent at most once per this interval; `None`: not sent.
    Topic(Topic, Option<Duration>),
}

/// The most subscriptions one connection may hold, all topics together: more are refused, so a
/// client cannot grow the node's memory by subscribing under ever new `id`s.
pub const MAX_SUBSCRIPTIONS: usize = 64;

/// One connection's subscriptions: for each topic, each subscription's `id` (`None` for one
/// without) and its `throttle_rate`.
#[derive(Default)]
struct Subscriptions {
    topics: BTreeMap<(usize, Option<String>), Duration>,
}

impl Subscriptions {
    const fn key(topic: Topic) -> usize {
        topic.index()
    }

    /// The topic's interval after a change: the smallest throttle of its subscriptions, or
    /// `None` if it has none left.
    fn apply(&mut self, action: Action) -> Out {
        let (topic, key) = match action {
            Action::Send(frame) => return Out::Frame(Utf8Bytes::from(frame)),
            Action::Subscribe {
                topic,
                id,
                throttle,
            } => {
                let key = (Self::key(topic), id);
                if !self.topics.contains_key(&key) && self.topics.len() >= MAX_SUBSCRIPTIONS {
                    tracing::warn!(
                        "a subscription refused: the connection holds {MAX_SUBSCRIPTIONS}"
                    );
                    let msg = format!(
                        "a connection may hold {MAX_SUBSCRIPTIONS} subscriptions; unsubscribe one first"
                    );
                    let id = key
                        .1
                        .as_deref()
                        .and_then(|id| serde_json::from_str(id).ok());
                    return Out::Frame(Utf8Bytes::from(rosbridge::error_status(&msg, id)));
                }
                self.topics.insert(key, throttle);
                (topic, Self::key(topic))
            }
            Action::Unsubscribe {
                topic,
                id: Some(id),
            } => {
                self.topics.remove(&(Self::key(topic), Some(id)));
                (topic, Self::key(topic))
            }
            Action::Unsubscribe { topic, id: None } => {
                let key = Self::key(topic);
                self.topics.retain(|(of, _), _| *of != key);
                (topic, key)
            }
        };
        let every = self
            .topics
            .iter()
            .filter(|((of, _), _)| *of == key)
            .map(|(_, throttle)| *throttle)
            .min();
        Out::Topic(topic, every)
    }

    fn any(&self) -> bool {
        !self.topics.is_empty()
    }
}

/// Serves one client until it leaves, stalls, sends a frame over the hard limit, or `stop`
/// completes (another client took its place).
pub async fn serve(
    socket: WebSocket,
    node: Arc<Node>,
    limits: Limits,
    grant: Grant,
    stop: impl std::future::Future<Output = ()> + Send,
) {
    let mut stop = std::pin::pin!(stop);
    let (sink, mut stream) = socket.split();
    let (out, queue) = mpsc::channel(limits.queue.max(1));
    let mut writer = tokio::spawn(write(sink, queue, Arc::clone(&node), limits));
    let mut writer_done = false;
    let grant = Arc::new(grant);
    let mut subscriptions = Subscriptions::default();
    let mut last_request = Instant::now();
    let silent = limits.keepalive.saturating_mul(3);
    loop {
        let idle_at = (!subscriptions.any()).then(|| last_request + limits.idle);
        let wait_until = idle_at.map_or(Instant::now() + silent, |idle_at| {
            idle_at.min(Instant::now() + silent)
        });
        // When the writer gives up on the client (it stalled), the reading stops too, so
        // the connection closes.
        let received = tokio::select! {
            received = tokio::time::timeout_at(wait_until, stream.next()) => {
                received.unwrap_or_else(|_| {
                    if idle_at.is_some_and(|idle_at| Instant::now() >= idle_at) {
                        tracing::warn!(
                            "a client with no subscription sent no request for {:?}; disconnected",
                            limits.idle
                        );
                    } else {
                        tracing::info!("a client sent nothing, not even a pong, for too long; disconnected");
                    }
                    None
                })
            }
            () = &mut stop => None,
            done = &mut writer => {
                writer_done = true;
                if let Err(error) = done {
                    tracing::error!(%error, "a connection's writer failed");
                }
                None
            }
        };
        let Some(received) = received else { break };
        let actions = match received {
            Ok(Message::Text(text)) => {
                last_request = Instant::now();
                handle(&node, text, limits.frame, &grant).await
            }
            Ok(Message::Binary(_)) => vec![Action::Send(rosbridge::error_status(
                "a binary frame: this node reads rosbridge JSON in text frames (no CBOR or BSON)",
                None,
            ))],
            Ok(Message::Close(_)) => break,
            Ok(Message::Ping(_) | Message::Pong(_)) => Vec::new(),
            Err(error) => {
                tracing::info!(%error, "a client's connection failed");
                break;
            }
        };
        for action in actions {
            if out.send(subscriptions.apply(action)).await.is_err() {
                break;
            }
        }
    }
    drop(out);
    if !writer_done {
        if let Err(error) = writer.await {
            tracing::error!(%error, "a connection's writer failed");
        }
    }
}

/// A text frame's answer, worked out on the blocking pool (it reads the frame and takes the
/// core's lock, which must not hold up the tasks of other connections); an answer to a call
/// that changed the core waits for the publication that shows the change.
async fn handle(node: &Arc<Node>, text: Utf8Bytes, max: usize, grant: &Arc<Grant>) -> Vec<Action> {
    let worker = Arc::clone(node);
    let grant = Arc::clone(grant);
    let work = move || {
        if text.len() > max {
            let msg = format!(
                "a frame of {} bytes, more than the {max} this node reads",
                text.len()
            );
            tracing::warn!("a frame refused: {msg}");
            (rosbridge::refuse(text.as_str(), &msg), None)
        } else {
            rosbridge::handle(&worker, text.as_str(), &grant)
        }
    };
    let (actions, revision) = tokio::task::spawn_blocking(work)
        .await
        .unwrap_or_else(|error| {
            tracing::error!(%error, "a request's handling failed");
            let failed = rosbridge::error_status("the node failed to answer this request", None);
            (vec![Action::Send(failed)], None)
        });
    if let Some(revision) = revision {
        node.published(revision).await;
    }
    actions
}

/// One topic as the writer sends it.
struct Stream {
    receiver: watch::Receiver<Publication>,
    /// `None`: not subscribed; else at most one publication per this interval.
    every: Option<Duration>,
    /// When the next publication may be sent, when the interval holds one back.
    not_before: Option<Instant>,
    /// Whether this connection was ever sent the topic.
    sent: bool,
}

impl Stream {
    fn new(receiver: watch::Receiver<Publication>) -> Self {
        Self {
            receiver,
            every: None,
            not_before: None,
            sent: false,
        }
    }

    /// Starts, re-times or stops the topic. The first subscription of the connection gets
    /// the newest publication at once, if there is one yet (in the stack mode, none until the
    /// relay first shows one); a later one only publications it was not yet sent.
    fn set(&mut self, every: Option<Duration>) {
        let published = !self.receiver.borrow().frame.is_empty();
        if every.is_some() && self.every.is_none() && !self.sent && published {
            self.receiver.mark_changed();
        }
        self.every = every;
    }

    /// Whether a publication may be sent now.
    fn open(&self) -> bool {
        self.every.is_some() && self.not_before.is_none_or(|at| Instant::now() >= at)
    }

    /// The newest publication, marked as sent.
    fn take(&mut self) -> Message {
        self.sent = true;
        self.not_before = self
            .every
            .filter(|every| !every.is_zero())
            .map(|every| Instant::now() + every);
        Message::Text(self.receiver.borrow_and_update().frame.clone())
    }

    /// When a held-back publication may be sent (far off when none is held back).
    fn reopens(&self) -> Instant {
        match (self.every, self.not_before) {
            (Some(_), Some(at)) if at > Instant::now() => at,
            _ => Instant::now() + Duration::from_secs(3600),
        }
    }
}

async fn write<S>(mut sink: S, mut queue: mpsc::Receiver<Out>, node: Arc<Node>, limits: Limits)
where
    S: futures_util::Sink<Message> + Unpin,
    S::Error: std::fmt::Display,
{
    let [mut velocity, mut steering, mut scenes] =
        Topic::ALL.map(|topic| Stream::new(node.subscribe(topic)));
    let mut keepalive = tokio::time::interval(limits.keepalive);
    keepalive.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    keepalive.reset();
    loop {
        let (velocity_open, steering_open, scenes_open) =
            (velocity.open(), steering.open(), scenes.open());
        let reopens = velocity
            .reopens()
            .min(steering.reopens())
            .min(scenes.reopens());
        let message = tokio::select! {
            biased;
            item = queue.recv() => match item {
                Some(Out::Frame(frame)) => Message::Text(frame),
                Some(Out::Topic(topic, every)) => {
                    match topic {
                        Topic::Velocity => velocity.set(every),
                        Topic::Steering => steering.set(every),
                        Topic::Scenes => scenes.set(every),
                    }
                    continue;
                }
                None => break,
            },
            changed = velocity.receiver.changed(), if velocity_open => match changed {
                Ok(()) => velocity.take(),
                Err(_) => break,
            },
            changed = steering.receiver.changed(), if steering_open => match changed {
                Ok(()) => steering.take(),
                Err(_) => break,
            },
            changed = scenes.receiver.changed(), if scenes_open => match changed {
                Ok(()) => scenes.take(),
                Err(_) => break,
            },
            () = tokio::time::sleep_until(reopens) => continue,
            _ = keepalive.tick() => Message::Ping(axum::body::Bytes::new()),
        };
        match tokio::time::timeout(limits.write_timeout, sink.send(message)).await {
            Ok(Ok(())) => {}
            Ok(Err(error)) => {
                tracing::info!(%error, "a client's connection failed");
                break;
            }
            Err(_) => {
                tracing::warn!(
                    timeout = ?limits.write_timeout,
                    "a client took no frame for too long; disconnected"
                );
                break;
            }
        }
    }
    let close = Message::Close(Some(CloseFrame {
        code: 1000,
        reason: Utf8Bytes::default(),
    }));
    let _closed = tokio::time::timeout(Duration::from_secs(1), sink.send(close)).await;
}
