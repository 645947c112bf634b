//! Which requests a browser may make of the node: the host a request names, and the origin of
//! the page that opens a WebSocket.
//!
//! A web page the operator has open in the same browser can open a WebSocket to any address,
//! and the browser lets it (WebSockets are not bound by the same-origin policy); what it cannot
//! hide is its `Origin` header. So an upgrade that carries an `Origin` is accepted only from
//! the node's own page (the origin `http://` plus the `Host` it asked for) or an origin the
//! node was told to allow (`--allow-origin`); any other, `null` included (a `file://` page, a
//! sandboxed frame), gets HTTP 403. A client that is not a browser sends no `Origin` and is not
//! refused here.
//!
//! A page can also make a name it controls resolve to the node's address (DNS rebinding), and
//! then the node's own origin is that name. So every request, the panel's included, must name a
//! host the node answers to: an IP address (a rebinding needs a name), `localhost`, or a name
//! it was told to allow (`--allow-host`); any other gets HTTP 403.
//!
//! Every page the node serves says it may not be framed by another page
//! (`Content-Security-Policy: frame-ancestors 'none'`, `X-Frame-Options: DENY`), and that it runs
//! only the node's own scripts and connects only to the node.

use std::net::IpAddr;

use axum::http::{header, HeaderMap, HeaderValue, StatusCode};

/// The origins and host names a node accepts besides its own.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Access {
    /// Origins (`scheme://host[:port]`, as a browser writes them) whose pages may open a
    /// WebSocket, besides the node's own.
    pub origins: Vec<String>,
    /// Host names requests may name, besides IP addresses and `localhost`.
    pub hosts: Vec<String>,
}

/// Why a request was refused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// The request names no host, or one the node does not answer to.
    Host(String),
    /// A WebSocket upgrade from a page of another origin.
    Origin(String),
}

impl core::fmt::Display for Refusal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Host(host) => write!(
                f,
                "host {host:?} is not one this node answers to (an IP address, localhost, or \
                 --allow-host)"
            ),
            Self::Origin(origin) => write!(
                f,
                "a WebSocket from a page of origin {origin:?}, which is neither this node's \
                 nor allowed (--allow-origin)"
            ),
        }
    }
}

impl Refusal {
    /// The HTTP status a refused request gets.
    #[must_use]
    pub const fn status(&self) -> StatusCode {
        StatusCode::FORBIDDEN
    }
}

impl Access {
    /// Whether a request with these headers may be served: its host, and, for a WebSocket
    /// upgrade that carries one, its origin.
    ///
    /// # Errors
    /// The [`Refusal`], naming the host or origin refused.
    pub fn check(&self, headers: &HeaderMap) -> Result<(), Refusal> {
        let host = text(headers.get(header::HOST)).unwrap_or_default();
        if !self.answers_to(host) {
            return Err(Refusal::Host(host.to_owned()));
        }
        let upgrade = text(headers.get(header::UPGRADE))
            .is_some_and(|value| value.eq_ignore_ascii_case("websocket"));
        if let (true, Some(origin)) = (upgrade, headers.get(header::ORIGIN)) {
            let origin = text(Some(origin)).unwrap_or("(not text)");
            if origin != format!("http://{host}") && !self.origins.iter().any(|o| o == origin) {
                return Err(Refusal::Origin(origin.to_owned()));
            }
        }
        Ok(())
    }

    /// Whether `host` (as a `Host` header writes it, with or without a port) is an IP address,
    /// `localhost` or an allowed name.
    fn answers_to(&self, host: &str) -> bool {
        let name = without_port(host);
        !name.is_empty()
            && (name.eq_ignore_ascii_case("localhost")
                || name
                    .strip_prefix('[')
                    .and_then(|v6| v6.strip_suffix(']'))
                    .unwrap_or(name)
                    .parse::<IpAddr>()
                    .is_ok()
                || self.hosts.iter().any(|h| h.eq_ignore_ascii_case(name)))
    }
}

/// A header's value as text, if it is.
fn text(value: Option<&HeaderValue>) -> Option<&str> {
    value.and_then(|value| value.to_str().ok())
}

/// `host` without its port: `[::1]:9090` → `[::1]`, `localhost:9090` → `localhost`.
fn without_port(host: &str) -> &str {
    if host.starts_with('[') {
        return host
            .find(']')
            .and_then(|end| host.get(..=end))
            .unwrap_or(host);
    }
    host.rsplit_once(':').map_or(host, |(name, _)| name)
}

/// The headers every page carries: no other page may frame it, and a page runs only the node's
/// own scripts and connects only back to the node (a script injected into it could neither
/// load nor call out).
pub(crate) const FRAMING: [(header::HeaderName, &str); 2] = [
    (
        header::CONTENT_SECURITY_POLICY,
        "default-src 'none'; script-src 'self'; style-src 'unsafe-inline'; img-src data:; \
         connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'",
    ),
    (header::X_FRAME_OPTIONS, "DENY"),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(pairs: &[(header::HeaderName, &str)]) -> HeaderMap {
        let mut map = HeaderMap::new();
        for (name, value) in pairs {
            map.insert(
                name.clone(),
                HeaderValue::from_str(value).expect("a header value"),
            );
        }
        map
    }

    #[test]
    fn hosts_are_addresses_localhost_or_allowed_names() {
        let access = Access {
            hosts: vec!["node.example".into()],
            ..Access::default()
        };
        for host in [
            "127.0.0.1:9090",
            "127.0.0.1",
            "[::1]:9090",
            "[::1]",
            "10.0.0.7:9090",
            "localhost:9090",
            "LOCALHOST",
            "node.example:9090",
        ] {
            assert_eq!(
                access.check(&headers(&[(header::HOST, host)])),
                Ok(()),
                "{host}"
            );
        }
        for host in [
            "evil.example:9090",
            "node.example.evil:9090",
            "",
            ":9090",
            "[::1",
        ] {
            assert_eq!(
                access.check(&headers(&[(header::HOST, host)])),
                Err(Refusal::Host(host.into())),
                "{host}"
            );
        }
        assert_eq!(
            access.check(&HeaderMap::new()),
            Err(Refusal::Host(String::new()))
        );
    }

    #[test]
    fn an_upgrade_from_another_origin_is_refused() {
        let access = Access {
            origins: vec!["https://ops.example".into()],
            ..Access::default()
        };
        let upgrade = |origin: Option<&str>| {
            let mut pairs = vec![
                (header::HOST, "127.0.0.1:9090"),
                (header::UPGRADE, "websocket"),
            ];
            pairs.extend(origin.map(|o| (header::ORIGIN, o)));
            access.check(&headers(&pairs))
        };
        assert_eq!(upgrade(None), Ok(()));
        assert_eq!(upgrade(Some("http://127.0.0.1:9090")), Ok(()));
        assert_eq!(upgrade(Some("https://ops.example")), Ok(()));
        for origin in [
            "http://evil.example",
            "null",
            "http://127.0.0.1:8000",
            "http://localhost:9090",
            "https://127.0.0.1:9090",
        ] {
            assert_eq!(
                upgrade(Some(origin)),
                Err(Refusal::Origin(origin.into())),
                "{origin}"
            );
        }
        // A request that is not an upgrade (the panel's page) is not refused for its origin.
        let page = headers(&[
            (header::HOST, "127.0.0.1:9090"),
            (header::ORIGIN, "http://evil.example"),
        ]);
        assert_eq!(access.check(&page), Ok(()));
    }
}
