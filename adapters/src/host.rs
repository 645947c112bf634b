//! A process that hosts the core for others: the core with the bookkeeping its adapters keep
//! ([`Host`]), and the service engine over it behind one lock ([`Shared`]).

use std::sync::atomic::{AtomicI64, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use cooperation::{State, Transition};

use crate::engine::{self, Engine, Now, Publication};
use crate::rtc::{Interface, InterfaceId, Rtc, RtcError, View};
use crate::wire;

/// The core as a process serving it keeps it: the [`State`], the RTC interfaces' routing
/// ([`Rtc`]), and the core's time: how much time the core was told of.
///
/// One value, so that one lock ([`Shared`]) covers everything a call reads or writes: a node
/// serving operators and planning modules has no second lock and no lock order. Every change is
/// still an input to [`State::apply`] (or [`State::apply_all`]): through the AD API services
/// ([`answer`](Self::answer)), an RTC interface ([`interface`](Self::interface)) or time
/// ([`advance_to`](Self::advance_to)).
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Host {
    state: State,
    rtc: Rtc,
    /// The core's time, in milliseconds from the host's start: the time it was told of, summed.
    told_ms: u64,
}

impl Host {
    /// A host of `state`, whose planning modules report through `rtc`'s interfaces, with its
    /// clock at 0.
    #[must_use]
    pub const fn new(state: State, rtc: Rtc) -> Self {
        Self {
            state,
            rtc,
            told_ms: 0,
        }
    }

    /// The core, to query.
    #[must_use]
    pub const fn state(&self) -> &State {
        &self.state
    }

    /// The core, for a planner in the same process that speaks its inputs directly
    /// ([`State::apply`], [`State::apply_all`]). Time is better told through
    /// [`advance_to`](Self::advance_to), which keeps the host's clock and the RTC routes in step.
    pub fn state_mut(&mut self) -> &mut State {
        &mut self.state
    }

    /// The RTC interfaces, to query.
    #[must_use]
    pub const fn rtc(&self) -> &Rtc {
        &self.rtc
    }

    /// The RTC interfaces and the core, for the calls that take both (the external API's
    /// [`Rtc::cooperate_commands`], [`Rtc::auto_mode_with_module`]).
    pub fn rtc_and_state(&mut self) -> (&mut Rtc, &mut State) {
        (&mut self.rtc, &mut self.state)
    }

    /// An AD API service call, read by [`wire::Service::read`]: the typed response and whether
    /// the state changed.
    pub fn answer(&mut self, request: &wire::Request) -> wire::Answer<wire::Response> {
        request.answer(&mut self.state)
    }

    /// The RTC interface named `name`, to report through.
    ///
    /// # Errors
    /// As [`Rtc::interface`].
    pub fn interface(&mut self, name: &str) -> Result<Interface<'_>, RtcError> {
        self.rtc.interface(&mut self.state, name)
    }

    /// The RTC interface named `name`, to query.
    ///
    /// # Errors
    /// As [`Rtc::view`].
    pub fn view(&self, name: &str) -> Result<View<'_>, RtcError> {
        self.rtc.view(&self.state, name)
    }

    /// The RTC interface `id` ([`Rtc::find`]), to change the core through.
    ///
    /// # Errors
    /// As [`Rtc::interface_at`].
    pub fn interface_at(&mut self, id: InterfaceId) -> Result<Interface<'_>, RtcError> {
        self.rtc.interface_at(&mut self.state, id)
    }

    /// The RTC interface `id` ([`Rtc::find`]), to query.
    ///
    /// # Errors
    /// As [`Rtc::view_at`].
    pub fn view_at(&self, id: InterfaceId) -> Result<View<'_>, RtcError> {
        self.rtc.view_at(&self.state, id)
    }

    /// The core's time, in milliseconds from the host's start: the time it was told of, summed
    /// (the engine counts each step of its host's clock at most its step limit, so this is not
    /// the clock's reading, `[COOP-ENGINE-STEP.1]`).
    #[must_use]
    pub const fn told_ms(&self) -> u64 {
        self.told_ms
    }

    /// Tells the core that its time is `now_ms`: the core's `Tick` for the time since it was
    /// last told ([`Rtc::tick`], which also forgets the routes of forgotten scenes). `None` if
    /// no time passed; a time earlier than the last one is taken as no time passing, so that no
    /// scene ages twice.
    ///
    /// # Errors
    /// The core's rejection of the tick (a tick is never rejected today).
    pub fn advance_to(&mut self, now_ms: u64) -> Result<Option<Transition>, RtcError> {
        let elapsed_ms = now_ms.saturating_sub(self.told_ms);
        self.told_ms = self.told_ms.max(now_ms);
        if elapsed_ms == 0 {
            return Ok(None);
        }
        self.rtc.tick(&mut self.state, elapsed_ms).map(Some)
    }
}

/// An [`Engine`] behind one lock: `Send + Sync`, shareable through an `Arc` between a planning
/// cycle, service callbacks and a clock.
///
/// Every change goes through [`State::apply`] under the lock, so each call is applied whole or
/// (when refused) not at all, and calls from different threads are applied one after the other:
/// none is lost, none sees another half-done (`[COOP-DEV-RACE.1]`). Reads take the same lock
/// and so see the state between two calls, never during one.
///
/// ```
/// use std::sync::Arc;
/// use cooperation::*;
/// use cooperation_adapters::engine::{Engine, Options};
/// use cooperation_adapters::rtc::StatusReport;
/// use cooperation_adapters::Shared;
///
/// let config = cooperation_adapters::settings::load(None)?.config;
/// let shared = Arc::new(Shared::new(Engine::new(config, Options::default())?));
/// let id = SceneId::from_u128(7);
///
/// // The planning thread reports a scene through its RTC interface ...
/// let planner = Arc::clone(&shared);
/// std::thread::spawn(move || {
///     planner.update(|engine| {
///         let report = StatusReport::new(id, true, Phase::Waiting, 10.0, 30.0);
///         engine
///             .call(|host| host.interface("intersection")?.update_cooperate_status(&report).map(drop))
///             .0
///     })
/// })
/// .join()
/// .expect("the planning thread ran")?;
///
/// // ... and a service thread reads it: the built-in settings' optional policy, the module
/// // safe, no operator decision yet.
/// assert_eq!(shared.read(|engine| engine.state().merged_decision(id)), Some(Decision::Activate));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug)]
pub struct Shared {
    inner: Mutex<Inner>,
    /// How many times [`update`](Self::update) has taken the lock ([`changes`](Self::changes)).
    changes: AtomicU64,
    /// [`Engine::read_ms`] as the last [`update`](Self::update) left it, for
    /// [`told_in`](Self::told_in); [`UNKNOWN_MS`] while an update runs, and before the engine's
    /// first reading.
    read_ms: AtomicI64,
}

/// What [`Shared`]'s copy of the engine's last reading holds when it matches no reading.
const UNKNOWN_MS: i64 = i64::MIN;

/// What the lock guards: the engine, and its newest publication for every door that sends
/// one.
#[derive(Debug)]
struct Inner {
    engine: Engine,
    /// How many publications the engine has handed out, and the newest.
    published: u64,
    newest: Option<Arc<Publication>>,
}

impl Shared {
    /// A handle owning `engine`.
    #[must_use]
    pub const fn new(engine: Engine) -> Self {
        let read_ms = match engine.read_ms() {
            Some(read_ms) => read_ms,
            None => UNKNOWN_MS,
        };
        Self {
            inner: Mutex::new(Inner {
                engine,
                published: 0,
                newest: None,
            }),
            changes: AtomicU64::new(0),
            read_ms: AtomicI64::new(read_ms),
        }
    }

    /// The lock. A panic in another thread while it held the lock cannot have left the core
    /// half-changed: its only writers are `State::apply` and `State::apply_all`, which decide
    /// before they write and do not panic, and the engine's own bookkeeping is written after the
    /// core. So a poisoned lock is used as it is.
    fn lock(&self) -> MutexGuard<'_, Inner> {
        self.inner.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Runs `change` with the lock held: whatever it does is a sequence of inputs, each applied
    /// whole or not at all, and no other thread's input lands between them. Keep it short;
    /// every other caller waits for it.
    pub fn update<R>(&self, change: impl FnOnce(&mut Engine) -> R) -> R {
        let mut inner = self.lock();
        // Counted before the change, under the lock: a reader that sees the count move reads
        // again under the lock, so after the change; one that does not is before it.
        self.changes.fetch_add(1, Ordering::Release);
        // Unknown while `change` runs (and after, if it panics): `told_in` answers from the
        // lock's side only what the engine held between two updates.
        self.read_ms.store(UNKNOWN_MS, Ordering::Release);
        let answer = change(&mut inner.engine);
        self.read_ms.store(
            inner.engine.read_ms().unwrap_or(UNKNOWN_MS),
            Ordering::Release,
        );
        answer
    }

    /// Whether the engine was last told a reading in the millisecond of `now`'s, read without
    /// the lock. If so, [`Engine::advance`] at `now` would change nothing and expire nothing, so
    /// a host may answer it without the lock and without counting a change: as of the moment
    /// of this read, which is between two updates.
    #[must_use]
    pub fn told_in(&self, now: Now) -> bool {
        let read_ms = self.read_ms.load(Ordering::Acquire);
        read_ms != UNKNOWN_MS && read_ms == engine::reading_ms(now)
    }

    /// Runs `query` between two changes: everything it reads is from one moment. Keep it short;
    /// every other caller waits for it.
    pub fn read<R>(&self, query: impl FnOnce(&Engine) -> R) -> R {
        query(&self.lock().engine)
    }

    /// How many times [`update`](Self::update) has run (or begun), read without the lock: a
    /// count that moves before anything in the engine can change. A reader that keeps what it
    /// read with the count it read it at ([`read_counted`](Self::read_counted)) knows it is
    /// still current while the count has not moved, whatever other thread changes the engine.
    #[must_use]
    pub fn changes(&self) -> u64 {
        self.changes.load(Ordering::Acquire)
    }

    /// [`read`](Self::read), with the [`changes`](Self::changes) count the engine is at while
    /// `query` reads it (the count cannot move while the lock is held).
    pub fn read_counted<R>(&self, query: impl FnOnce(u64, &Engine) -> R) -> R {
        let inner = self.lock();
        query(self.changes.load(Ordering::Acquire), &inner.engine)
    }

    /// The newest publication for a door that has sent the first `sent` ones, with its number:
    /// the engine's, if one is due at `now` ([`Engine::poll_publication`]), or one another door
    /// polled since. Every door of a process sends every publication it sees, so that all the
    /// doors of one engine show the same thing, each at its own pace.
    pub fn publication(&self, now: Now, sent: u64) -> Option<(u64, Arc<Publication>)> {
        let mut inner = self.lock();
        if let Some(publication) = inner.engine.poll_publication(now) {
            inner.published += 1;
            inner.newest = Some(Arc::new(publication));
        }
        let number = inner.published;
        inner
            .newest
            .as_ref()
            .filter(|_| number > sent)
            .map(|newest| (number, Arc::clone(newest)))
    }

    /// The engine, when no other thread can reach the handle any more.
    #[must_use]
    pub fn into_inner(self) -> Engine {
        self.inner
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
            .engine
    }
}

impl From<Engine> for Shared {
    fn from(engine: Engine) -> Self {
        Self::new(engine)
    }
}
