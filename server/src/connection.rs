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

use std::sync::Arc;
use std::time::Duration;

use axum::extract::ws::{CloseFrame, Message, Utf8Bytes, WebSocket};
use futures_util::{SinkExt, StreamExt};
use tokio::sync::{mpsc, watch};

use crate::node::{Node, Publication, Topic};
use crate::rosbridge::{self, Action};

/// How much one connection may hold and take.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Limits {
    /// Frames above this many bytes are refused with a `status` frame and the connection
    /// goes on.
    pub frame: usize,
    /// Frames above this many bytes close the connection: it is not read any further.
    pub hard_frame: usize,
    /// Answers waiting to be sent, per connection.
    pub queue: usize,
    /// The longest a frame may take to be handed to the client's connection (its socket
    /// buffers full) before the client is disconnected.
    pub write_timeout: Duration,
    /// The node pings the client this often; a client from which nothing (not even the pong)
    /// arrives for three times as long is disconnected.
    pub keepalive: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            frame: 2 << 20,
            hard_frame: 16 << 20,
            queue: 64,
            write_timeout: Duration::from_secs(10),
            keepalive: Duration::from_secs(20),
        }
    }
}

enum Out {
    Frame(Utf8Bytes),
    Subscribe(Topic),
    Unsubscribe(Topic),
}

/// Serves one client until it leaves, stalls, or sends a frame over the hard limit.
pub async fn serve(socket: WebSocket, node: Arc<Node>, limits: Limits) {
    let (sink, mut stream) = socket.split();
    let (out, queue) = mpsc::channel(limits.queue.max(1));
    let mut writer = tokio::spawn(write(sink, queue, Arc::clone(&node), limits));
    let mut writer_done = false;
    loop {
        // When the writer gives up on the client (it stalled), the reading stops too, so
        // the connection closes.
        let received = tokio::select! {
            received = tokio::time::timeout(limits.keepalive.saturating_mul(3), stream.next()) => {
                received.unwrap_or_else(|_| {
                    tracing::info!("a client sent nothing, not even a pong, for too long; disconnected");
                    None
                })
            }
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
            Ok(Message::Text(text)) => handle(&node, text, limits.frame).await,
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
            let out_item = match action {
                Action::Send(frame) => Out::Frame(Utf8Bytes::from(frame)),
                Action::Subscribe(topic) => Out::Subscribe(topic),
                Action::Unsubscribe(topic) => Out::Unsubscribe(topic),
            };
            if out.send(out_item).await.is_err() {
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
async fn handle(node: &Arc<Node>, text: Utf8Bytes, max: usize) -> Vec<Action> {
    let worker = Arc::clone(node);
    let work = move || {
        if text.len() > max {
            let msg = format!(
                "a frame of {} bytes, more than the {max} this node reads",
                text.len()
            );
            (rosbridge::refuse(text.as_str(), &msg), None)
        } else {
            rosbridge::handle(&worker, text.as_str())
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

async fn write<S>(mut sink: S, mut queue: mpsc::Receiver<Out>, node: Arc<Node>, limits: Limits)
where
    S: futures_util::Sink<Message> + Unpin,
    S::Error: std::fmt::Display,
{
    let mut velocity = node.subscribe(Topic::Velocity);
    let mut steering = node.subscribe(Topic::Steering);
    let (mut to_velocity, mut to_steering) = (false, false);
    let mut keepalive = tokio::time::interval(limits.keepalive);
    keepalive.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    keepalive.reset();
    loop {
        let message = tokio::select! {
            biased;
            item = queue.recv() => match item {
                Some(Out::Frame(frame)) => Message::Text(frame),
                Some(Out::Subscribe(topic)) => {
                    subscription(topic, true, &mut to_velocity, &mut to_steering, &mut velocity, &mut steering);
                    continue;
                }
                Some(Out::Unsubscribe(topic)) => {
                    subscription(topic, false, &mut to_velocity, &mut to_steering, &mut velocity, &mut steering);
                    continue;
                }
                None => break,
            },
            changed = velocity.changed(), if to_velocity => match changed {
                Ok(()) => Message::Text(velocity.borrow_and_update().frame.clone()),
                Err(_) => break,
            },
            changed = steering.changed(), if to_steering => match changed {
                Ok(()) => Message::Text(steering.borrow_and_update().frame.clone()),
                Err(_) => break,
            },
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

/// Starts or stops a topic; a new subscriber is sent the newest publication at once.
fn subscription(
    topic: Topic,
    on: bool,
    to_velocity: &mut bool,
    to_steering: &mut bool,
    velocity: &mut watch::Receiver<Publication>,
    steering: &mut watch::Receiver<Publication>,
) {
    let (flag, receiver) = match topic {
        Topic::Velocity => (to_velocity, velocity),
        Topic::Steering => (to_steering, steering),
    };
    if on && !*flag {
        receiver.mark_changed();
    }
    *flag = on;
}
