//! The log of what a node refuses from its peers: the first refusal of each period is logged
//! whole, the others counted and summed up in one line when the period ends, so that a peer that
//! repeats a refused request, message or status thousands of times a second cannot fill the
//! log, and nothing refused goes uncounted.
//!
//! The hosts keep one each (`cooperation-server` for its clients' addresses, `cooperation-dds`
//! for its services, topics and modules) and write the lines it answers; the log itself reads
//! no clock: a host ends a period by its own timer ([`Refusals::end_period`]) or by telling the
//! time ([`Refusals::poll`]).
//!
//! ```
//! use cooperation_adapters::refusals::Refusals;
//! use std::time::Duration;
//!
//! let log = Refusals::new("service", "services", Duration::from_secs(10));
//! assert!(log.refused("set_commands", "a malformed request refused"), "the first: logged whole");
//! assert!(!log.refused("set_commands", "a malformed request refused"), "counted");
//! assert!(!log.refused("get_policies", "a malformed request refused"), "counted");
//! assert_eq!(log.poll(0), None, "the period starts when first told the time");
//! assert_eq!(
//!     log.poll(10_000_000_000).as_deref(),
//!     Some("2 more refused since the last refusal logged, from 2 services, get_policies, \
//!           set_commands; the last: a malformed request refused")
//! );
//! assert!(log.refused("set_commands", "a malformed request refused"), "a new period's first");
//! ```

use std::collections::BTreeSet;
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

/// The most sources a summary counts one by one; beyond it the summary says "at least".
pub const MAX_SOURCES: usize = 4096;

/// The period a host without a setting of its own uses: ten seconds.
pub const PERIOD: Duration = Duration::from_secs(10);

/// Refusals since the period began.
#[derive(Debug, Default)]
struct Period {
    /// When it began, as the host's clock read (nanoseconds), once [`Refusals::poll`] was told.
    began_ns: Option<i64>,
    /// Whether this period's first refusal was logged.
    logged: bool,
    /// Refusals after the first, not logged one by one.
    counted: u64,
    /// Their sources (at most [`MAX_SOURCES`]).
    sources: BTreeSet<String>,
    /// The last counted refusal's line.
    last: String,
}

/// Refusals, logged at most twice a period: the first whole, then one summary.
#[derive(Debug)]
pub struct Refusals {
    /// What a source is, once and many times: `address`, `addresses`.
    one: &'static str,
    many: &'static str,
    /// The period [`poll`](Self::poll) ends.
    every: Duration,
    period: Mutex<Period>,
}

impl Refusals {
    /// A log whose sources are called `one` (and `many`), ended by [`poll`](Self::poll) every
    /// `every` (a host with a timer of its own may ignore it and call
    /// [`end_period`](Self::end_period)).
    #[must_use]
    pub fn new(one: &'static str, many: &'static str, every: Duration) -> Self {
        Self {
            one,
            many,
            every,
            period: Mutex::new(Period::default()),
        }
    }

    /// A refusal from `source`, said by `line`: `true` if it is to be logged whole (the
    /// period's first), `false` if it is counted for the period's summary.
    pub fn refused(&self, source: &str, line: &str) -> bool {
        let mut period = self.period.lock().unwrap_or_else(PoisonError::into_inner);
        if period.logged {
            period.counted = period.counted.saturating_add(1);
            if period.sources.len() < MAX_SOURCES && !period.sources.contains(source) {
                period.sources.insert(source.to_owned());
            }
            line.clone_into(&mut period.last);
            false
        } else {
            period.logged = true;
            true
        }
    }

    /// Ends the period: the line that sums up the refusals counted in it, if there were any.
    pub fn end_period(&self) -> Option<String> {
        let mut period = self.period.lock().unwrap_or_else(PoisonError::into_inner);
        let began_ns = period.began_ns;
        let ended = std::mem::take(&mut *period);
        period.began_ns = began_ns;
        drop(period);
        (ended.counted > 0).then(|| self.summary(&ended))
    }

    /// The time, as the host's clock reads it (nanoseconds, any origin): ends the period, with
    /// [`end_period`](Self::end_period)'s answer, if `every` has passed since it began. The
    /// first reading begins the first period; a reading earlier than the period's beginning (a
    /// clock that went back) begins it again.
    pub fn poll(&self, reading_ns: i64) -> Option<String> {
        let every = i64::try_from(self.every.as_nanos()).unwrap_or(i64::MAX);
        {
            let mut period = self.period.lock().unwrap_or_else(PoisonError::into_inner);
            match period.began_ns {
                Some(began) if began <= reading_ns && reading_ns - began < every => return None,
                Some(began) if began <= reading_ns => period.began_ns = Some(reading_ns),
                _ => {
                    period.began_ns = Some(reading_ns);
                    return None;
                }
            }
        }
        self.end_period()
    }

    /// The summary of a period with refusals counted.
    fn summary(&self, period: &Period) -> String {
        let sources = period.sources.len();
        let which = if sources >= MAX_SOURCES {
            format!("at least {sources} {}", self.many)
        } else if sources <= 3 {
            let list: Vec<&str> = period.sources.iter().map(String::as_str).collect();
            let noun = if sources == 1 { self.one } else { self.many };
            format!("{sources} {noun}, {}", list.join(", "))
        } else {
            format!("{sources} {}", self.many)
        };
        format!(
            "{} more refused since the last refusal logged, from {which}; the last: {}",
            period.counted, period.last
        )
    }
}

#[cfg(test)]
mod tests {
    use super::{Refusals, MAX_SOURCES, PERIOD};

    #[test]
    fn one_line_a_period_and_one_summary() {
        let refusals = Refusals::new("address", "addresses", PERIOD);
        assert_eq!(refusals.end_period(), None, "nothing refused, nothing said");
        assert!(refusals.refused("10.0.0.1", "a client refused: no credential presented"));
        for n in 0..999 {
            let source = format!("10.0.{}.{}", n / 256, n % 256);
            assert!(!refusals.refused(&source, "a client refused: an unknown credential"));
        }
        assert_eq!(
            refusals.end_period().as_deref(),
            Some(
                "999 more refused since the last refusal logged, from 999 addresses; the last: a \
                 client refused: an unknown credential"
            )
        );
        // A new period logs its first refusal whole again.
        assert!(refusals.refused("10.0.0.1", "a client refused: no credential presented"));
        for _ in 2..12 {
            assert!(!refusals.refused("10.0.0.1", "a client refused: no credential presented"));
        }
        assert!(refusals.end_period().is_some_and(|line| line.starts_with(
            "10 more refused since the last refusal logged, from 1 address, 10.0.0.1;"
        )));
        assert_eq!(refusals.end_period(), None);
    }

    /// Beyond [`MAX_SOURCES`] the summary counts no more sources, and says so.
    #[test]
    fn sources_are_counted_up_to_a_limit() {
        let refusals = Refusals::new("service", "services", PERIOD);
        assert!(refusals.refused("first", "refused"));
        for n in 0..MAX_SOURCES + 10 {
            assert!(!refusals.refused(&n.to_string(), "refused"));
        }
        assert_eq!(
            refusals.end_period().as_deref(),
            Some(
                "4106 more refused since the last refusal logged, from at least 4096 services; \
                 the last: refused"
            )
        );
    }

    /// The period ends when `every` has passed since it began, and only then; a clock that
    /// went back begins it again.
    #[test]
    fn the_period_ends_by_the_time_told() {
        let second = 1_000_000_000;
        let refusals = Refusals::new("topic", "topics", PERIOD);
        assert!(refusals.refused("a", "refused"));
        assert!(!refusals.refused("b", "refused"));
        assert_eq!(
            refusals.poll(5 * second),
            None,
            "the first reading begins the period"
        );
        assert_eq!(refusals.poll(14 * second), None, "9 s");
        assert!(refusals.poll(15 * second).is_some(), "10 s");
        assert!(refusals.refused("a", "refused"));
        assert!(!refusals.refused("a", "refused"));
        assert_eq!(refusals.poll(3 * second), None, "back: begins again at 3 s");
        assert_eq!(refusals.poll(12 * second), None, "9 s after 3 s");
        assert!(refusals
            .poll(13 * second)
            .is_some_and(|line| line.starts_with("1 more refused")));
        assert_eq!(
            refusals.poll(40 * second),
            None,
            "nothing counted, nothing said"
        );
    }
}
