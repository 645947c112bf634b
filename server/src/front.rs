//! The node's front door: every TCP connection, from its accept until its request is answered
//! or it becomes a WebSocket.
//!
//! A connection that has not yet become a WebSocket holds a file descriptor and a task, and
//! tells the node nothing about who it is, so its life is bounded before anything else:
//!
//! - **At most [`Admission::pending`] at once**, all peers together. When they are all taken, a
//!   new connection takes the place of the oldest waiting connection of the address prefix
//!   (an IPv4 address, an IPv6 /64) that has the most waiting, if that is more than its own
//!   prefix has; otherwise it is closed at once. Either is logged. So a peer whose prefix has
//!   fewer connections waiting than another's always gets a place, however many connections
//!   others hold or however fast they come back.
//! - **At most [`Admission::per_peer`] from one IP address**, counting its connections not yet
//!   upgraded and its WebSockets that hold no credential (an authenticated WebSocket counts
//!   against its credential's places instead, [`crate::auth`]).
//! - **Its request's headers within [`Admission::header_timeout`]** of the accept, or it is
//!   closed and logged.
//! - **Its requests answered, or its WebSocket upgraded, within
//!   [`Admission::request_timeout`] of the accept**, or the connection is closed and logged:
//!   a connection kept alive between requests ends then too.
//!
//! A connection refused here gets no answer: it is closed.

use std::collections::HashMap;
use std::net::{IpAddr, SocketAddr};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use axum::body::Body;
use axum::Router;
use hyper::body::Incoming;
use hyper_util::rt::{TokioIo, TokioTimer};
use tokio::net::TcpListener;
use tokio::sync::Semaphore;

use crate::fair::Fair;
use crate::refusals::Refusals;
use tower::ServiceExt;

/// The limits on connections before they become WebSockets.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Admission {
    /// Connections not yet upgraded, all peers together.
    pub pending: usize,
    /// Connections from one IP address: those not yet upgraded and its WebSockets without a
    /// credential.
    pub per_peer: usize,
    /// The longest from the accept, or from the end of the last response, to the end of a
    /// request's headers.
    pub header_timeout: Duration,
    /// The longest a connection stays open without becoming a WebSocket.
    pub request_timeout: Duration,
    /// Refused clients and requests are logged one a period, the others summed up in one line
    /// at its end.
    pub refusal_log_every: Duration,
}

impl Default for Admission {
    fn default() -> Self {
        Self {
            pending: 256,
            per_peer: 128,
            header_timeout: Duration::from_secs(5),
            request_timeout: Duration::from_secs(30),
            refusal_log_every: cooperation_adapters::refusals::PERIOD,
        }
    }
}

impl Admission {
    /// Why these limits cannot run a node, if they cannot.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        if self.pending == 0 || self.pending > Semaphore::MAX_PERMITS {
            return Some(format!("{} pending connections", self.pending));
        }
        if self.per_peer == 0 {
            return Some("no connection per peer".to_owned());
        }
        if self.header_timeout.is_zero() || self.request_timeout.is_zero() {
            return Some("a zero request timeout".to_owned());
        }
        if self.refusal_log_every.is_zero() {
            return Some("a zero period for the log of refusals".to_owned());
        }
        None
    }
}

/// The connections of each IP address that count against [`Admission::per_peer`].
#[derive(Debug, Default)]
struct Peers {
    open: Mutex<HashMap<IpAddr, usize>>,
}

impl Peers {
    /// A seat for one more connection from `ip`, unless it has `most` already.
    fn seat(self: &Arc<Self>, ip: IpAddr, most: usize) -> Option<Seat> {
        let mut open = self.open.lock().unwrap_or_else(PoisonError::into_inner);
        let count = open.entry(ip).or_insert(0);
        if *count >= most {
            return None;
        }
        *count += 1;
        Some(Seat {
            peers: Arc::clone(self),
            ip,
        })
    }
}

/// One connection's place among its address's; freed when dropped.
#[derive(Debug)]
pub struct Seat {
    peers: Arc<Peers>,
    ip: IpAddr,
}

impl Drop for Seat {
    fn drop(&mut self) {
        let mut open = self
            .peers
            .open
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        if let Some(count) = open.get_mut(&self.ip) {
            *count = count.saturating_sub(1);
            if *count == 0 {
                open.remove(&self.ip);
            }
        }
    }
}

/// Who sent a request: put in every request's extensions. A WebSocket that counts against its
/// address keeps the seat (a clone of the `Arc`) for as long as it is open.
#[derive(Clone, Debug)]
pub struct Peer {
    /// The peer's address.
    pub address: SocketAddr,
    /// Its place among its address's connections.
    pub seat: Arc<Seat>,
}

/// Accepts connections on `listener` and serves each with `router`, within `admission`'s
/// limits, until `shutdown` completes.
pub(crate) async fn accept(
    listener: TcpListener,
    router: Router,
    admission: Admission,
    refusals: Arc<Refusals>,
    shutdown: impl std::future::Future<Output = ()> + Send,
) {
    let waiting = Fair::new(admission.pending);
    let peers = Arc::new(Peers::default());
    let mut shutdown = std::pin::pin!(shutdown);
    loop {
        let accepted = tokio::select! {
            accepted = listener.accept() => accepted,
            () = &mut shutdown => return,
        };
        let (stream, address) = match accepted {
            Ok(accepted) => accepted,
            Err(error) => {
                // Out of file descriptors, or a connection reset before it was accepted: wait
                // a moment rather than spin.
                tracing::warn!(%error, "a connection could not be accepted");
                tokio::time::sleep(Duration::from_millis(50)).await;
                continue;
            }
        };
        let Some(seat) = peers.seat(address.ip(), admission.per_peer) else {
            refusals.log(
                &address.to_string(),
                &format!(
                    "a connection closed: its address has {} open, the most one address may have",
                    admission.per_peer
                ),
            );
            continue;
        };
        let Ok((place, evicted, took)) = waiting.place(address.ip()) else {
            refusals.log(
                &address.to_string(),
                &format!(
                    "a connection closed: {} connections are waiting to send their request, the \
                     most the node keeps, and its address has as many of them as any",
                    admission.pending
                ),
            );
            continue;
        };
        if took {
            refusals.log(
                &address.to_string(),
                &format!(
                    "a connection let in in place of the oldest waiting one of the address \
                     with the most of the {} waiting",
                    admission.pending
                ),
            );
        }
        let peer = Peer {
            address,
            seat: Arc::new(seat),
        };
        let router = router.clone();
        let refusals = Arc::clone(&refusals);
        tokio::spawn(async move {
            tokio::select! {
                () = serve_connection(stream, peer, router, admission, &refusals) => {}
                Ok(()) = evicted => refusals.log(
                    &address.to_string(),
                    "a connection closed: a connection from an address with fewer waiting took \
                     its place",
                ),
            }
            drop(place);
        });
    }
}

/// One connection's request, within the header and request timeouts.
async fn serve_connection(
    stream: tokio::net::TcpStream,
    peer: Peer,
    router: Router,
    admission: Admission,
    refusals: &Refusals,
) {
    let address = peer.address;
    let service = hyper::service::service_fn(move |mut request: hyper::Request<Incoming>| {
        request.extensions_mut().insert(peer.clone());
        router.clone().oneshot(request.map(Body::new))
    });
    let mut builder = hyper::server::conn::http1::Builder::new();
    builder
        .timer(TokioTimer::new())
        .header_read_timeout(admission.header_timeout);
    let connection = builder
        .serve_connection(TokioIo::new(stream), service)
        .with_upgrades();
    match tokio::time::timeout(admission.request_timeout, connection).await {
        Ok(Ok(())) => {}
        Ok(Err(error)) if error.is_timeout() => refusals.log(
            &address.to_string(),
            &format!(
                "a connection closed: no complete request headers within {:?}",
                admission.header_timeout
            ),
        ),
        Ok(Err(error)) => tracing::debug!(peer = %address, %error, "a connection failed"),
        Err(_) => refusals.log(
            &address.to_string(),
            &format!(
                "a connection closed: its request was not done within {:?}",
                admission.request_timeout
            ),
        ),
    }
}
