//! A copy of one interface's query answers that a query reads without the core's lock.
//!
//! A planning module asks the same few questions about each of its handful of scenes every
//! cycle (`isActivated`, `isRTCEnabled`, ...), and the core changes between cycles, not between
//! the questions. So each [`Handle`](crate::calls::Handle) keeps the answers for its interface's
//! live scenes, made under the core's lock by the adapter
//! ([`View::answers`](cooperation_adapters::rtc::View::answers): the queries' answers for every
//! scene, in one pass), with the core's change count they were made at
//! ([`Shared::changes`](cooperation_adapters::Shared::changes)). A query that finds the count
//! where it was answers from the copy, with no lock taken; any change of the core, from any
//! thread, moves the count, and the next query makes the copy again.
//!
//! The copy is a sequence lock over atomics: one writer at a time (it is written only under the
//! core's lock), readers that never wait and retry nothing (a reader that meets a write in
//! progress answers through the core instead). It holds up to [`CAPACITY`] scenes; an interface
//! with more is answered through the core, as before.

use std::sync::atomic::{fence, AtomicU64, Ordering};

use cooperation_adapters::rtc::{self, View};

/// The most live scenes of one interface the copy holds: more than a module has at once in
/// practice (each scene is one situation ahead on the route).
pub(crate) const CAPACITY: usize = 16;

/// The answers' bits.
const ACTIVATED: u64 = 1;
const FORCE_ACTIVATED: u64 = 1 << 1;
const FORCE_DEACTIVATED: u64 = 1 << 2;
const RTC_ENABLED: u64 = 1 << 3;

/// `Snapshot::scenes` when the interface had more live scenes than the copy holds.
const TOO_MANY: u64 = u64::MAX;

/// The answers of one live scene of the interface, as the adapter's queries gave them.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) struct Answers(u64);

impl Answers {
    /// Upstream `isActivated`.
    pub(crate) const fn activated(self) -> bool {
        self.0 & ACTIVATED != 0
    }

    /// Upstream `isForceActivated`.
    pub(crate) const fn force_activated(self) -> bool {
        self.0 & FORCE_ACTIVATED != 0
    }

    /// Upstream `isForceDeactivated`.
    pub(crate) const fn force_deactivated(self) -> bool {
        self.0 & FORCE_DEACTIVATED != 0
    }

    /// Upstream `isRTCEnabled`.
    pub(crate) const fn rtc_enabled(self) -> bool {
        self.0 & RTC_ENABLED != 0
    }
}

/// What the copy says of a scene.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Lookup {
    /// The copy is current: the scene is a live scene of the interface with these answers, or
    /// (`None`) it is not.
    Current(Option<Answers>),
    /// The copy cannot answer (the core changed since it was made, it is being made again, or
    /// the interface has more scenes than it holds): ask the core.
    Ask,
}

/// The two halves of an identifier's bytes, as the copy keeps it.
fn halves(uuid: &[u8; 16]) -> (u64, u64) {
    let whole = u128::from_be_bytes(*uuid);
    // The halves of a 128-bit number: both truncations are the point.
    #[allow(clippy::cast_possible_truncation)]
    ((whole >> 64) as u64, whole as u64)
}

/// One interface's answers, at one change count of its core.
#[derive(Debug)]
pub(crate) struct Snapshot {
    /// Odd while the copy is being written.
    sequence: AtomicU64,
    /// The change count the copy is of (`u64::MAX`, none yet: a count never reaches it).
    changes: AtomicU64,
    /// How many entries of `entries` hold a scene, or [`TOO_MANY`].
    scenes: AtomicU64,
    /// Per scene: the identifier's halves and its answers.
    entries: [[AtomicU64; 3]; CAPACITY],
}

impl Default for Snapshot {
    fn default() -> Self {
        Self {
            sequence: AtomicU64::new(0),
            changes: AtomicU64::new(u64::MAX),
            scenes: AtomicU64::new(0),
            entries: std::array::from_fn(|_| std::array::from_fn(|_| AtomicU64::new(0))),
        }
    }
}

impl Snapshot {
    /// What the copy says of `uuid`, if it was made at change count `changes` and no write is in
    /// progress. Never waits.
    pub(crate) fn lookup(&self, changes: u64, uuid: &[u8; 16]) -> Lookup {
        let before = self.sequence.load(Ordering::Acquire);
        if before & 1 == 1 || self.changes.load(Ordering::Relaxed) != changes {
            return Lookup::Ask;
        }
        let Some(entries) = usize::try_from(self.scenes.load(Ordering::Relaxed))
            .ok()
            .and_then(|scenes| self.entries.get(..scenes))
        else {
            return Lookup::Ask;
        };
        let (high, low) = halves(uuid);
        let answers = entries
            .iter()
            .find(|entry| {
                entry[1].load(Ordering::Relaxed) == low && entry[0].load(Ordering::Relaxed) == high
            })
            .map(|entry| Answers(entry[2].load(Ordering::Relaxed)));
        // Everything read above was read before the sequence is read again.
        fence(Ordering::Acquire);
        if self.sequence.load(Ordering::Relaxed) == before {
            Lookup::Current(answers)
        } else {
            Lookup::Ask
        }
    }

    /// Makes the copy again from `view`, the interface as the core is at change count
    /// `changes`, unless it is of that count already. Called only with the core's lock held,
    /// which makes the writers one at a time and the count fixed.
    pub(crate) fn make(&self, changes: u64, view: Option<&View<'_>>) {
        if self.changes.load(Ordering::Relaxed) == changes {
            return;
        }
        // The answers first, so that readers meet a write in progress for as short a time as
        // can be.
        let mut made = [[0; 3]; CAPACITY];
        let mut scenes = 0;
        // An interface that had too many scenes is counted first: it likely still has, and
        // then no answer is worth working out.
        let had_too_many = self.scenes.load(Ordering::Relaxed) == TOO_MANY;
        if let Some(view) = view {
            if had_too_many && view.scenes().nth(CAPACITY).is_some() {
                scenes = CAPACITY + 1;
            }
        }
        if let Some(view) = view.filter(|_| scenes == 0) {
            for (id, answers) in view.answers() {
                let Some(entry) = made.get_mut(scenes) else {
                    scenes = CAPACITY + 1;
                    break;
                };
                let (high, low) = halves(&rtc::Uuid::from(id).uuid);
                *entry = [high, low, Answers::from(answers).0];
                scenes += 1;
            }
        }
        let sequence = self.sequence.load(Ordering::Relaxed);
        self.sequence
            .store(sequence.wrapping_add(1), Ordering::Relaxed);
        // The sequence is odd before any entry changes.
        fence(Ordering::Release);
        if scenes > CAPACITY {
            self.scenes.store(TOO_MANY, Ordering::Relaxed);
        } else {
            for (entry, made) in self.entries.iter().zip(&made).take(scenes) {
                for (word, made) in entry.iter().zip(made) {
                    word.store(*made, Ordering::Relaxed);
                }
            }
            self.scenes.store(scenes as u64, Ordering::Relaxed);
        }
        self.changes.store(changes, Ordering::Relaxed);
        self.sequence
            .store(sequence.wrapping_add(2), Ordering::Release);
    }
}

impl From<rtc::Answers> for Answers {
    /// The adapter's answers for one live scene, as bits.
    fn from(answers: rtc::Answers) -> Self {
        let bit = |set: bool, bit: u64| if set { bit } else { 0 };
        Self(
            bit(answers.activated, ACTIVATED)
                | bit(answers.force_activated, FORCE_ACTIVATED)
                | bit(answers.force_deactivated, FORCE_DEACTIVATED)
                | bit(answers.rtc_enabled, RTC_ENABLED),
        )
    }
}
