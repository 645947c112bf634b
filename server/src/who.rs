//! Who a request is: the grant its token gives, and the places it would take, checked the same
//! way for a WebSocket upgrade (`/`) and for `/whoami`, which answers it without taking a place.
//!
//! `/whoami` lets the operator panel tell apart what a browser's WebSocket cannot (its failed
//! upgrade's status is hidden from scripts): a token that is no credential's, an address locked
//! out for its guesses, a credential whose places are all taken, a module's token, and a node
//! that does not answer at all. It reads the token from the `Authorization: Bearer` header
//! only (never from the URL, so that no token is left in a log or a history), and counts a
//! wrong one as a guess, exactly as an upgrade does ([`crate::guesses`]).

use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::Arc;
use std::time::Instant;

use axum::extract::State as Extracted;
use axum::http::{header, HeaderMap, HeaderValue, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use serde::Serialize;

use crate::auth::{self, Grant, Role};
use crate::fair::Fair;
use crate::keyring::Entry;
use crate::{front, App};

/// A request's grant, and the places it takes a connection from.
pub(crate) struct Who {
    /// What the connection may do.
    pub(crate) grant: Grant,
    /// Where its connection's place comes from.
    places: Places,
    /// How many places there are.
    most: usize,
}

/// The places a connection takes one of.
enum Places {
    /// Its credential's own.
    Credential(Arc<Entry>),
    /// Those of a node without credentials, shared fairly by address prefix.
    Anyone(Arc<Fair>),
}

/// A connection's place, freed when dropped: one of its credential's, or of a node without
/// credentials'.
pub(crate) type Held = Box<dyn Send>;

/// What completes when a connection must close: another client took its place, or its
/// credential was revoked.
pub(crate) type Stop = Pin<Box<dyn Future<Output = ()> + Send>>;

/// A connection's place, and what completes when the connection must close ([`Stop`]); none
/// when every place is taken and none may be taken from another.
pub(crate) fn take_place(
    app: &App,
    who: &Who,
    address: Option<SocketAddr>,
) -> Option<(Held, Stop)> {
    match &who.places {
        Places::Credential(entry) => {
            let permit = Arc::clone(&entry.places).try_acquire_owned().ok()?;
            let revoked = entry.revoked();
            let refusals = Arc::clone(&app.refusals);
            let peer = address.map_or_else(|| "unknown".to_owned(), |address| address.to_string());
            let stop = async move {
                revoked.await;
                refusals.log(&peer, "a client closed: its credential was revoked");
            };
            Some((Box::new(permit), Box::pin(stop)))
        }
        Places::Anyone(fair) => {
            let address =
                address.unwrap_or_else(|| SocketAddr::from((std::net::Ipv4Addr::UNSPECIFIED, 0)));
            let (place, evicted, took) = fair.place(address.ip()).ok()?;
            let peer = address.to_string();
            if took {
                app.refusals.log(
                    &peer,
                    &format!(
                        "a client let in in place of the oldest client of the address with the \
                         most of the {} clients",
                        who.most
                    ),
                );
            }
            let refusals = Arc::clone(&app.refusals);
            let stop = async move {
                if evicted.await.is_ok() {
                    refusals.log(
                        &peer,
                        "a client closed: a client from an address with fewer took its place",
                    );
                } else {
                    std::future::pending::<()>().await;
                }
            };
            Some((Box::new(place), Box::pin(stop)))
        }
    }
}

impl Who {
    /// Why a connection gets no place: all are taken.
    pub(crate) fn full(&self) -> String {
        match &self.grant {
            Grant::Anyone => {
                "this node serves as many clients as it may; try again later".to_owned()
            }
            Grant::Credential(credential) => format!(
                "credential {:?} has {} connections open, the most it may have",
                credential.name, self.most
            ),
        }
    }
}

/// Who a request is, from its token; or the response that refuses it, logged: HTTP 429 with
/// `Retry-After` while its address is locked out (its token unread), HTTP 401 for no token or
/// one that is no credential's (a guess, which may lock the address out).
pub(crate) fn identify(
    app: &App,
    peer: Option<&front::Peer>,
    headers: &HeaderMap,
    uri: &Uri,
) -> Result<Who, Box<Response>> {
    let Some(keyring) = &app.keyring else {
        return Ok(Who {
            grant: Grant::Anyone,
            places: Places::Anyone(Arc::clone(&app.clients)),
            most: app.max_clients,
        });
    };
    let set = keyring.current();
    let credentials = &set.credentials;
    let ip = peer.map(|peer| peer.address.ip());
    let now = Instant::now();
    if let Some(left) = ip.and_then(|ip| app.guesses.locked(ip, now)) {
        let why = format!(
            "too many credentials the node does not have from this address: try again in {} s",
            whole_seconds(left)
        );
        let mut response = refuse(app, peer, StatusCode::TOO_MANY_REQUESTS, why);
        if let Ok(value) = HeaderValue::from_str(&whole_seconds(left).to_string()) {
            response.headers_mut().insert(header::RETRY_AFTER, value);
        }
        return Err(Box::new(response));
    }
    let index = match credentials.identify(headers, uri) {
        Ok(index) => index,
        Err(why) => {
            let lockout = (why == auth::Unidentified::Unknown)
                .then_some(ip)
                .flatten()
                .and_then(|ip| app.guesses.guessed(ip, now));
            let why = match lockout {
                Some(lockout) => format!(
                    "{}; too many from this address: locked out for {} s",
                    why.as_str(),
                    whole_seconds(lockout)
                ),
                None => why.as_str().to_owned(),
            };
            let mut response = refuse(app, peer, StatusCode::UNAUTHORIZED, why);
            response
                .headers_mut()
                .insert(header::WWW_AUTHENTICATE, HeaderValue::from_static("Bearer"));
            return Err(Box::new(response));
        }
    };
    let (Some(credential), Some(entry)) = (credentials.list().get(index), set.entries.get(index))
    else {
        return Err(Box::new(refuse(
            app,
            peer,
            StatusCode::INTERNAL_SERVER_ERROR,
            "no such credential".to_owned(),
        )));
    };
    if let Some(ip) = ip {
        app.guesses.identified(ip);
    }
    Ok(Who {
        grant: Grant::Credential(credential.clone()),
        places: Places::Credential(Arc::clone(entry)),
        most: credentials.places,
    })
}

/// A refusal with `status` and `why`, logged with the peer's address.
pub(crate) fn refuse(
    app: &App,
    peer: Option<&front::Peer>,
    status: StatusCode,
    why: String,
) -> Response {
    let address = peer.map_or_else(|| "unknown".to_owned(), |peer| peer.address.to_string());
    app.refusals
        .log(&address, &format!("a client refused: {why}"));
    (status, why).into_response()
}

/// `/whoami`'s answer.
#[derive(Serialize, Debug)]
struct Answer {
    /// `operator`, `module`, or `anyone` on a node without credentials.
    role: &'static str,
    /// The credential's name; none on a node without credentials.
    credential: Option<String>,
    /// The RTC interfaces a module may report for.
    interfaces: Vec<String>,
    /// The connections it may have open at once.
    places: usize,
    /// Those open now.
    open: usize,
    /// The operator decisions `set_commands` may set (the AD API's constants): all four, or
    /// in the stack mode activate and deactivate only.
    decisions: Vec<u8>,
}

/// `/whoami`: what the request's `Authorization: Bearer` token would let a WebSocket in as,
/// and how many of its places are taken, as JSON; or the refusal an upgrade would get for it
/// (HTTP 401 or 429), except that a full credential is an answer (`open` equal to `places`),
/// not a refusal. Takes no place.
pub(crate) async fn whoami(
    Extracted(app): Extracted<App>,
    peer: Option<axum::Extension<front::Peer>>,
    headers: HeaderMap,
) -> Response {
    let peer = peer.map(|axum::Extension(peer)| peer);
    // The header only: a token in this URL would be left in logs and histories.
    let who = match identify(&app, peer.as_ref(), &headers, &Uri::from_static("/whoami")) {
        Ok(who) => who,
        Err(refused) => return *refused,
    };
    let open = match &who.places {
        Places::Credential(entry) => who.most.saturating_sub(entry.places.available_permits()),
        Places::Anyone(fair) => fair.held(),
    };
    let answer = match who.grant {
        Grant::Anyone => Answer {
            role: "anyone",
            credential: None,
            interfaces: Vec::new(),
            places: who.most,
            open,
            decisions: app.node.decisions(),
        },
        Grant::Credential(credential) => Answer {
            role: match credential.role {
                Role::Operator => "operator",
                Role::Module => "module",
            },
            credential: Some(credential.name),
            interfaces: credential.interfaces.into_iter().collect(),
            places: who.most,
            open,
            decisions: app.node.decisions(),
        },
    };
    let Ok(body) = serde_json::to_string(&answer) else {
        return refuse(
            &app,
            peer.as_ref(),
            StatusCode::INTERNAL_SERVER_ERROR,
            "the answer did not serialize".to_owned(),
        );
    };
    (
        [
            (header::CONTENT_TYPE, "application/json"),
            (header::CACHE_CONTROL, "no-store"),
        ],
        body,
    )
        .into_response()
}

/// A lockout or the time left of one, in whole seconds, rounded up.
fn whole_seconds(time: std::time::Duration) -> u64 {
    time.as_secs() + u64::from(time.subsec_nanos() > 0)
}
