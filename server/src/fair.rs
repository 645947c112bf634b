//! Places shared fairly among address prefixes ([`Prefix`]): when all are taken, a newcomer
//! takes the place of the oldest holder of the prefix that holds the most, if that prefix holds
//! more than the newcomer's own; otherwise it gets none. So a peer whose prefix holds fewer
//! places than another's always gets one, however many others hold or however fast they come
//! back. The front door's waiting connections ([`crate::front`]) and a node without
//! credentials' WebSockets ([`crate::Options::max_clients`]) are held so.

use std::collections::{HashMap, VecDeque};
use std::net::IpAddr;
use std::sync::{Arc, Mutex, PoisonError};

use tokio::sync::oneshot;

use crate::prefix::Prefix;

/// Places shared fairly by address prefix: each prefix's holders, oldest first.
#[derive(Debug)]
pub(crate) struct Fair {
    most: usize,
    state: Mutex<FairState>,
}

#[derive(Debug, Default)]
struct FairState {
    next: u64,
    total: usize,
    by_prefix: HashMap<Prefix, VecDeque<(u64, oneshot::Sender<()>)>>,
}

/// A holder's place; freed when dropped. Its receiver fires when a newcomer takes it.
#[derive(Debug)]
pub(crate) struct Place {
    fair: Arc<Fair>,
    prefix: Prefix,
    id: u64,
}

/// Why a newcomer got no place: all are taken, and its prefix holds as many as any.
pub(crate) struct Full;

impl Fair {
    /// `most` places.
    pub(crate) fn new(most: usize) -> Arc<Self> {
        Arc::new(Self {
            most,
            state: Mutex::new(FairState::default()),
        })
    }

    /// The places held now.
    pub(crate) fn held(&self) -> usize {
        self.state
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .total
    }

    /// A place for a holder from `ip`, and what tells it that it was evicted; whether it took
    /// another's. When all are taken, it takes the place of the oldest holder of the prefix
    /// that holds the most, if that is more than its own prefix holds.
    pub(crate) fn place(
        self: &Arc<Self>,
        ip: IpAddr,
    ) -> Result<(Place, oneshot::Receiver<()>, bool), Full> {
        let prefix = Prefix::of(ip);
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let mut evicted = false;
        if state.total >= self.most {
            let own = state.by_prefix.get(&prefix).map_or(0, |queue| queue.len());
            let fullest = state
                .by_prefix
                .iter()
                .max_by_key(|(_, queue)| queue.len())
                .filter(|(_, queue)| queue.len() > own)
                .map(|(prefix, _)| *prefix);
            let oldest = fullest
                .and_then(|fullest| state.by_prefix.get_mut(&fullest))
                .and_then(VecDeque::pop_front);
            let Some((_, evict)) = oldest else {
                return Err(Full);
            };
            // The evicted holder's task ends when told; if it already ended, nothing waits.
            let _ = evict.send(());
            state.total -= 1;
            state.by_prefix.retain(|_, queue| !queue.is_empty());
            evicted = true;
        }
        let id = state.next;
        state.next += 1;
        let (tell, told) = oneshot::channel();
        state
            .by_prefix
            .entry(prefix)
            .or_default()
            .push_back((id, tell));
        state.total += 1;
        Ok((
            Place {
                fair: Arc::clone(self),
                prefix,
                id,
            },
            told,
            evicted,
        ))
    }
}

impl Drop for Place {
    fn drop(&mut self) {
        let mut state = self
            .fair
            .state
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let Some(queue) = state.by_prefix.get_mut(&self.prefix) else {
            return;
        };
        let before = queue.len();
        queue.retain(|(id, _)| *id != self.id);
        let removed = before - queue.len();
        if queue.is_empty() {
            state.by_prefix.remove(&self.prefix);
        }
        state.total -= removed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(text: &str) -> IpAddr {
        text.parse().expect("an address")
    }

    #[test]
    fn a_newcomer_takes_a_place_only_from_a_prefix_that_holds_more() {
        let waiting = Fair::new(3);
        let (a1, mut a1_told, _) = waiting.place(ip("10.0.0.1")).ok().expect("a place");
        let (a2, _a2_told, _) = waiting.place(ip("10.0.0.1")).ok().expect("a place");
        let (b1, _b1_told, took) = waiting.place(ip("10.0.0.2")).ok().expect("a place");
        assert!(!took);
        // Full: one more from the fullest prefix gets nothing ...
        assert!(waiting.place(ip("10.0.0.1")).is_err());
        // ... but 10.0.0.2, with 1 waiting against 10.0.0.1's 2, takes 10.0.0.1's oldest.
        let (b2, _b2_told, took) = waiting.place(ip("10.0.0.2")).ok().expect("a place");
        assert!(took);
        assert_eq!(a1_told.try_recv(), Ok(()));
        drop(a1);
        // Now 10.0.0.1 and 10.0.0.2 hold 1 and 2: a third prefix takes 10.0.0.2's oldest.
        let (_c1, _c1_told, took) = waiting.place(ip("10.0.0.3")).ok().expect("a place");
        assert!(took);
        // Each prefix holds one: a prefix with none takes a place, one with one does not.
        assert!(waiting.place(ip("10.0.0.1")).is_err());
        let (_d1, _d1_told, took) = waiting.place(ip("10.0.0.4")).ok().expect("a place");
        assert!(took);
        drop((a2, b1, b2));
        let state = waiting.state.lock().expect("the lock");
        assert_eq!(
            state.total,
            state.by_prefix.values().map(|q| q.len()).sum::<usize>()
        );
        assert!(state.total <= 3);
    }

    #[test]
    fn an_ipv6_host_is_one_prefix_however_many_addresses_it_uses() {
        let fair = Fair::new(2);
        let (_a, _a_told, _) = fair.place(ip("2001:db8::1")).ok().expect("a place");
        let (_b, _b_told, _) = fair.place(ip("2001:db8::2")).ok().expect("a place");
        // Full, both held by one /64: another address of that /64 takes nothing ...
        assert!(fair.place(ip("2001:db8::ffff:3")).is_err());
        // ... while another /64 takes its oldest place.
        let (_c, _c_told, took) = fair.place(ip("2001:db8:0:1::1")).ok().expect("a place");
        assert!(took);
        assert_eq!(fair.held(), 2);
    }
}
