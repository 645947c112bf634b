//! The log of refused clients and requests: the first refusal of each period is logged whole,
//! the others counted and summed up in one line when the period ends, so that a client that
//! guesses tokens, or knocks without one, thousands of times a second cannot fill the log.

use std::collections::BTreeSet;
use std::sync::{Mutex, PoisonError};

/// The most addresses a summary counts one by one; beyond it the summary says "at least".
const MAX_ADDRESSES: usize = 4096;

/// Refusals since the period began.
#[derive(Debug, Default)]
struct Period {
    /// Whether this period's first refusal was logged.
    logged: bool,
    /// Refusals after the first, not logged one by one.
    counted: u64,
    /// Their peers' addresses (at most [`MAX_ADDRESSES`]).
    addresses: BTreeSet<String>,
    /// The last counted refusal's reason.
    last: String,
}

/// Refusals, logged at most twice a period ([`crate::Admission::refusal_log_every`]).
#[derive(Debug, Default)]
pub(crate) struct Refusals {
    period: Mutex<Period>,
}

impl Refusals {
    /// A refusal of a client at `peer`, said by `line`: `true` if it is to be logged whole
    /// (the period's first), `false` if it is counted for the period's summary.
    pub(crate) fn refused(&self, peer: &str, line: &str) -> bool {
        let mut period = self.period.lock().unwrap_or_else(PoisonError::into_inner);
        if period.logged {
            period.counted = period.counted.saturating_add(1);
            if period.addresses.len() < MAX_ADDRESSES {
                // The address without its port: one peer's connections count once.
                let ip = peer
                    .parse::<std::net::SocketAddr>()
                    .map_or_else(|_| peer.to_owned(), |at| at.ip().to_string());
                period.addresses.insert(ip);
            }
            line.clone_into(&mut period.last);
            false
        } else {
            period.logged = true;
            true
        }
    }

    /// Logs `line`, a refusal of a client at `peer`, if it is the period's first; counts it
    /// otherwise ([`refused`](Self::refused)).
    pub(crate) fn log(&self, peer: &str, line: &str) {
        if self.refused(peer, line) {
            tracing::warn!(peer = %peer, "{line}");
        }
    }

    /// Ends the period: the line that sums up the refusals counted in it, if there were any.
    pub(crate) fn end_period(&self) -> Option<String> {
        let period =
            std::mem::take(&mut *self.period.lock().unwrap_or_else(PoisonError::into_inner));
        (period.counted > 0).then(|| {
            let addresses = period.addresses.len();
            let which = if addresses >= MAX_ADDRESSES {
                format!("at least {addresses} addresses")
            } else if addresses <= 3 {
                let list: Vec<&str> = period.addresses.iter().map(String::as_str).collect();
                format!("{addresses} address(es), {}", list.join(", "))
            } else {
                format!("{addresses} addresses")
            };
            format!(
                "{} more refused since the last refusal logged, from {which}; the last: {}",
                period.counted, period.last
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::Refusals;

    #[test]
    fn one_line_a_period_and_one_summary() {
        let refusals = Refusals::default();
        assert_eq!(refusals.end_period(), None, "nothing refused, nothing said");
        assert!(refusals.refused("10.0.0.1:1", "a client refused: no credential presented"));
        for n in 0..999 {
            let peer = format!("10.0.{}.{}:2", n / 256, n % 256);
            assert!(!refusals.refused(&peer, "a client refused: an unknown credential"));
        }
        assert_eq!(
            refusals.end_period().as_deref(),
            Some(
                "999 more refused since the last refusal logged, from 999 addresses; the last: a \
                 client refused: an unknown credential"
            )
        );
        // A new period logs its first refusal whole again.
        assert!(refusals.refused("10.0.0.1:1", "a client refused: no credential presented"));
        for port in 2..12 {
            let peer = format!("10.0.0.1:{port}");
            assert!(!refusals.refused(&peer, "a client refused: no credential presented"));
        }
        assert!(refusals.end_period().is_some_and(|line| line.starts_with(
            "10 more refused since the last refusal logged, from 1 address(es), 10.0.0.1;"
        )));
        assert_eq!(refusals.end_period(), None);
    }
}
