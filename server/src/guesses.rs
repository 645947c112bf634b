//! Token guesses: a WebSocket upgrade that presents a credential the node does not have,
//! counted per address prefix (an IPv4 address; the /64 of an IPv6 address, which one host
//! can choose its addresses from).
//!
//! After [`GuessLimits::allowed`] guesses, the prefix is locked out for
//! [`GuessLimits::lockout`], doubled for each lockout since its record was last forgotten, at
//! most [`GuessLimits::max_lockout`]: every upgrade from it is refused (429, with
//! `Retry-After`) without its credential being checked, so a guesser learns nothing while
//! locked out. A client that presents no credential makes no guess (the front door bounds those,
//! [`crate::front`]), and a valid credential from another prefix is never refused for these.
//! A credential let in forgets its prefix's guesses. The record of at most
//! [`GuessLimits::prefixes`] prefixes is kept: a full table forgets the one idle longest, or,
//! if every one is locked out, the one whose lockout ends first.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use crate::prefix::Prefix;

/// How token guesses are limited.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct GuessLimits {
    /// Wrong credentials a prefix may present before it is locked out.
    pub allowed: u32,
    /// The first lockout; each further one doubles it.
    pub lockout: Duration,
    /// The longest lockout, and how long a prefix's record outlives its last guess or lockout.
    pub max_lockout: Duration,
    /// The prefixes whose guesses are recorded at once.
    pub prefixes: usize,
}

impl Default for GuessLimits {
    fn default() -> Self {
        Self {
            allowed: 5,
            lockout: Duration::from_secs(1),
            max_lockout: Duration::from_secs(60),
            prefixes: 4096,
        }
    }
}

impl GuessLimits {
    /// Why these limits cannot run a node, if they cannot.
    #[must_use]
    pub fn problem(&self) -> Option<String> {
        if self.allowed == 0 {
            return Some("no wrong credential allowed before a lockout".to_owned());
        }
        if self.lockout.is_zero() || self.max_lockout < self.lockout {
            return Some("a zero lockout, or a longest lockout below the first".to_owned());
        }
        if self.prefixes == 0 {
            return Some("no address prefix recorded".to_owned());
        }
        None
    }
}

/// One prefix's record.
#[derive(Clone, Copy, Debug)]
struct Record {
    /// Wrong credentials since its last lockout (or since it was first recorded).
    guesses: u32,
    /// Lockouts since it was first recorded.
    lockouts: u32,
    /// The end of its lockout, if it has had one.
    locked_until: Option<Instant>,
    /// Its last guess.
    last: Instant,
}

impl Record {
    fn locked(&self, now: Instant) -> Option<Duration> {
        self.locked_until
            .filter(|until| *until > now)
            .map(|until| until - now)
    }

    /// Idle: not locked out, and neither a guess nor a lockout for `keep`.
    fn forgotten(&self, now: Instant, keep: Duration) -> bool {
        let latest = self
            .locked_until
            .map_or(self.last, |until| until.max(self.last));
        now.saturating_duration_since(latest) >= keep
    }
}

/// The guesses of every recorded prefix.
#[derive(Debug)]
pub(crate) struct Guesses {
    limits: GuessLimits,
    records: Mutex<HashMap<Prefix, Record>>,
}

impl Guesses {
    pub(crate) fn new(limits: GuessLimits) -> Self {
        Self {
            limits,
            records: Mutex::new(HashMap::new()),
        }
    }

    /// How long `ip`'s prefix stays locked out after `now`, if it is.
    pub(crate) fn locked(&self, ip: IpAddr, now: Instant) -> Option<Duration> {
        let records = self.records.lock().unwrap_or_else(PoisonError::into_inner);
        records.get(&Prefix::of(ip))?.locked(now)
    }

    /// A wrong credential from `ip` at `now`: counted; the lockout it starts, if it does.
    pub(crate) fn guessed(&self, ip: IpAddr, now: Instant) -> Option<Duration> {
        let prefix = Prefix::of(ip);
        let mut records = self.records.lock().unwrap_or_else(PoisonError::into_inner);
        if !records.contains_key(&prefix) && records.len() >= self.limits.prefixes {
            self.make_room(&mut records, now);
        }
        let limits = self.limits;
        let record = records.entry(prefix).or_insert(Record {
            guesses: 0,
            lockouts: 0,
            locked_until: None,
            last: now,
        });
        if record.forgotten(now, limits.max_lockout) {
            *record = Record {
                guesses: 0,
                lockouts: 0,
                locked_until: None,
                last: now,
            };
        }
        record.last = now;
        record.guesses = record.guesses.saturating_add(1);
        if record.guesses < limits.allowed {
            return None;
        }
        let lockout = limits
            .lockout
            .saturating_mul(1u32.checked_shl(record.lockouts).unwrap_or(u32::MAX))
            .min(limits.max_lockout);
        record.guesses = 0;
        record.lockouts = record.lockouts.saturating_add(1);
        record.locked_until = Some(now + lockout);
        Some(lockout)
    }

    /// A credential from `ip` let in: its prefix's record is forgotten.
    pub(crate) fn identified(&self, ip: IpAddr) {
        let mut records = self.records.lock().unwrap_or_else(PoisonError::into_inner);
        records.remove(&Prefix::of(ip));
    }

    /// Forgets every idle record, and if none was, the one idle longest or, all being locked
    /// out, the one whose lockout ends first.
    fn make_room(&self, records: &mut HashMap<Prefix, Record>, now: Instant) {
        let keep = self.limits.max_lockout;
        records.retain(|_, record| !record.forgotten(now, keep));
        if records.len() < self.limits.prefixes {
            return;
        }
        let oldest = records
            .iter()
            .min_by_key(|(_, record)| {
                (
                    record.locked(now).is_some(),
                    record.locked_until,
                    record.last,
                )
            })
            .map(|(prefix, _)| *prefix);
        if let Some(prefix) = oldest {
            records.remove(&prefix);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> GuessLimits {
        GuessLimits {
            allowed: 3,
            lockout: Duration::from_secs(1),
            max_lockout: Duration::from_secs(5),
            prefixes: 2,
        }
    }

    fn ip(text: &str) -> IpAddr {
        text.parse().expect("an address")
    }

    /// The limits docs/server.md states.
    #[test]
    fn the_defaults_are_the_documented_ones() {
        let limits = GuessLimits::default();
        assert_eq!(limits.allowed, 5);
        assert_eq!(limits.lockout, Duration::from_secs(1));
        assert_eq!(limits.max_lockout, Duration::from_secs(60));
        assert_eq!(limits.prefixes, 4096);
        assert!(limits.problem().is_none());
    }

    #[test]
    fn a_prefix_is_locked_out_after_its_allowed_guesses_each_lockout_twice_the_last() {
        let guesses = Guesses::new(limits());
        let start = Instant::now();
        let at = |s: u64| start + Duration::from_secs(s);
        assert_eq!(guesses.guessed(ip("10.0.0.1"), at(0)), None);
        assert_eq!(guesses.guessed(ip("10.0.0.1"), at(0)), None);
        assert_eq!(
            guesses.guessed(ip("10.0.0.1"), at(0)),
            Some(Duration::from_secs(1))
        );
        assert_eq!(
            guesses.locked(ip("10.0.0.1"), at(0)),
            Some(Duration::from_secs(1))
        );
        // Another address is another prefix.
        assert_eq!(guesses.locked(ip("10.0.0.2"), at(0)), None);
        assert_eq!(guesses.locked(ip("10.0.0.1"), at(1)), None);
        for _ in 0..2 {
            assert_eq!(guesses.guessed(ip("10.0.0.1"), at(1)), None);
        }
        assert_eq!(
            guesses.guessed(ip("10.0.0.1"), at(1)),
            Some(Duration::from_secs(2))
        );
        // Doubling stops at the longest lockout.
        let mut now = at(3);
        let mut last = None;
        for _ in 0..5 {
            for _ in 0..3 {
                last = guesses.guessed(ip("10.0.0.1"), now);
            }
            now += last.expect("locked out");
        }
        assert_eq!(last, Some(Duration::from_secs(5)));
        // An identified client forgets its prefix's record.
        guesses.identified(ip("10.0.0.1"));
        assert_eq!(guesses.locked(ip("10.0.0.1"), now), None);
    }

    #[test]
    fn an_ipv6_host_is_one_prefix_and_an_idle_record_is_forgotten() {
        let guesses = Guesses::new(limits());
        let start = Instant::now();
        for n in 1..=3 {
            guesses.guessed(ip(&format!("2001:db8::{n}")), start);
        }
        assert!(guesses.locked(ip("2001:db8::ffff:1"), start).is_some());
        assert!(guesses.locked(ip("2001:db8:0:1::1"), start).is_none());
        // A mapped IPv4 address is its IPv4 address.
        for _ in 0..3 {
            guesses.guessed(ip("::ffff:10.0.0.9"), start);
        }
        assert!(guesses.locked(ip("10.0.0.9"), start).is_some());
        // After the longest lockout with nothing new, a prefix starts again from its first.
        let later = start + Duration::from_secs(7);
        assert_eq!(guesses.guessed(ip("2001:db8::1"), later), None);
    }

    #[test]
    fn a_full_table_forgets_an_idle_record_or_the_lockout_that_ends_first() {
        let guesses = Guesses::new(limits());
        let start = Instant::now();
        for _ in 0..3 {
            guesses.guessed(ip("10.0.0.1"), start);
        }
        for _ in 0..3 {
            guesses.guessed(ip("10.0.0.2"), start + Duration::from_millis(10));
        }
        // Both locked out: a third prefix takes the place of the one whose lockout ends first.
        guesses.guessed(ip("10.0.0.3"), start + Duration::from_millis(20));
        let now = start + Duration::from_millis(20);
        assert!(guesses.locked(ip("10.0.0.1"), now).is_none());
        assert!(guesses.locked(ip("10.0.0.2"), now).is_some());
        assert!(limits().problem().is_none());
        assert!(GuessLimits {
            allowed: 0,
            ..limits()
        }
        .problem()
        .is_some());
    }
}
