//! The log of refused clients and requests ([`cooperation_adapters::refusals`]), counted by
//! address: a client that guesses tokens, or knocks without one, thousands of times a second
//! cannot fill the log.

use cooperation_adapters::refusals;

/// Refusals, logged at most twice a period ([`crate::Admission::refusal_log_every`], ended by
/// the node's own timer).
#[derive(Debug)]
pub(crate) struct Refusals(refusals::Refusals);

impl Refusals {
    /// A log of periods of `every`.
    pub(crate) fn new(every: std::time::Duration) -> Self {
        Self(refusals::Refusals::new("address", "addresses", every))
    }

    /// Logs `line`, a refusal of a client at `peer`, if it is the period's first; counts it
    /// otherwise, by the peer's address without its port: one peer's connections count once.
    pub(crate) fn log(&self, peer: &str, line: &str) {
        let ip = peer
            .parse::<std::net::SocketAddr>()
            .map_or_else(|_| peer.to_owned(), |at| at.ip().to_string());
        if self.0.refused(&ip, line) {
            tracing::warn!(peer = %peer, "{line}");
        }
    }

    /// Ends the period: the line that sums up the refusals counted in it, if there were any.
    pub(crate) fn end_period(&self) -> Option<String> {
        self.0.end_period()
    }
}
