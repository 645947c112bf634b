//! The service engine: every door's request answered on one core, time first, and what the
//! streams publish decided in one place.
//!
//! A host (the rosbridge node, the DDS node, the C++ class's bridge) keeps its sockets, threads,
//! DDS entities, FFI and the clock it reads, and drives one [`Engine`] in the shape of a sans-IO
//! connection:
//!
//! - [`Engine::handle`] answers a request read from any door ([`Endpoint::read_json`],
//!   `dds::Endpoint::read`): first the core is told the time of the request ([`Now`]), so no
//!   command applies to a scene whose time to live had passed, then the request is answered. The
//!   answer says what it changed ([`Change`]).
//! - [`Engine::handle_timeout`] tells the core the time between requests (scenes age out); a
//!   host calls it at the latest after [`Engine::until_timeout_ms`].
//! - [`Engine::poll_publication`] hands out the streams' messages when a publication is due: at
//!   once after a change the streams show (`[COOP-ENGINE-PUBLISH.1]`), and every
//!   [`Options::publish_every_ms`] otherwise (so stamps and ages stay fresh).
//!
//! The core is built here, once, from a configuration and [`Options`] whose defaults every
//! host shares. Nothing here restates a rule of the core: every change is an input to
//! [`State::apply`] or [`State::apply_all`] through the adapters ([`wire`], [`sync`], [`rtc`](crate::rtc)).
//!
//! ```
//! use cooperation_adapters::engine::{Endpoint, Engine, Now, Options};
//! use cooperation_adapters::wire::Service;
//! use cooperation_adapters::Time;
//!
//! let mut engine = Engine::from_settings(None, Options::default())?;
//! let now = Now::new(0, Time::new(100, 0));
//! let request = Endpoint::Ad(Service::GetPolicies).read_json(b"{}");
//! let handled = engine.handle(request, now);
//! assert!(handled.reply.success() && handled.change.revision.is_none());
//! // The first publication is due at once.
//! let publication = engine.poll_publication(now).expect("due");
//! assert_eq!(publication.velocity.header.stamp, Time::new(100, 0));
//! assert!(engine.poll_publication(now).is_none());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod request;
pub mod scenes;
mod shown;

pub use error::EngineError;
pub use request::{Endpoint, Reply, Request};

use cooperation::{Config, State, Transition};

use crate::rtc::{Binding, Rtc, SCENE_QUOTA};
use crate::wire::{self, SteeringFactorArray, VelocityFactorArray};
use crate::{sync, Host, Time};
use scenes::SceneArray;

/// The interval of periodic publications unless a host says otherwise, in milliseconds.
pub const PUBLISH_EVERY_MS: u64 = 100;
/// The same interval as publications per second, as the nodes' `--rate` takes it.
pub const PUBLICATION_RATE_HZ: f64 = 1000.0 / PUBLISH_EVERY_MS as f64;
/// The most publications a second a host may ask for ([`publish_every`]).
pub const MAX_PUBLICATION_RATE_HZ: f64 = 1000.0;
/// The most one step of the host's clock counts unless a host says otherwise, in milliseconds
/// (`[COOP-ENGINE-STEP.1]`).
pub const MAX_STEP_MS: u64 = 1000;

/// How the engine runs: the same defaults for every host.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Options {
    /// The live scenes each RTC interface may hold (`[COOP-DEV-QUOTA.1]`); 0 for no quota. The
    /// quotas of all interfaces together must fit the core's table
    /// ([`EngineError::QuotaOverTable`]). The default, [`SCENE_QUOTA`], is lowered to the
    /// table shared by the interfaces (`max_scenes` ÷ interfaces) when that is less: settings
    /// that add interfaces, or shrink the table, then need no quota of their own.
    pub scene_quota: usize,
    /// The interval of periodic publications, in milliseconds (at least 1).
    pub publish_every_ms: u64,
    /// The most the core's time moves for one step of the host's clock, in milliseconds (at
    /// least 1; `[COOP-ENGINE-STEP.1]`): a longer step is a clock that jumped or a host that
    /// stalled, and counts this much. A host is told to tell the time at least this often
    /// ([`Engine::until_timeout_ms`]).
    pub max_step_ms: u64,
}

impl Options {
    /// These options, publishing every `every` (a host's [`publish_every`]): in whole
    /// milliseconds, at least 1.
    #[must_use]
    pub fn publishing_every(self, every: std::time::Duration) -> Self {
        Self {
            publish_every_ms: interval_ms(every),
            ..self
        }
    }
}

/// An interval in whole milliseconds, at least 1, as [`Options::publish_every_ms`] takes it.
fn interval_ms(every: std::time::Duration) -> u64 {
    u64::try_from(every.as_millis()).unwrap_or(u64::MAX).max(1)
}

impl Default for Options {
    fn default() -> Self {
        Self {
            scene_quota: SCENE_QUOTA,
            publish_every_ms: PUBLISH_EVERY_MS,
            max_step_ms: MAX_STEP_MS,
        }
    }
}

/// The time of a call, as the host's clock reads it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct Now {
    /// A reading in nanoseconds, from any origin (the engine takes its first reading as its time
    /// 0). A reading earlier than the last is a clock that went back: no time passes, and time
    /// counts on from it (`[COOP-ENGINE-STEP.1]`).
    pub reading_ns: i64,
    /// The stamp of the messages written now.
    pub stamp: Time,
}

impl Now {
    /// A reading and the stamp for it.
    #[must_use]
    pub const fn new(reading_ns: i64, stamp: Time) -> Self {
        Self { reading_ns, stamp }
    }

    /// A ROS clock's reading (`rclcpp::Clock::now()`): the stamp is the reading.
    #[must_use]
    pub fn of_stamp(stamp: Time) -> Self {
        Self {
            reading_ns: i64::from(stamp.sec) * 1_000_000_000 + i64::from(stamp.nanosec),
            stamp,
        }
    }
}

/// What a call did to the core, and whether a publication is due because of it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct Change {
    /// The core's revision after the call, if the call changed it (a report that only renews
    /// its scene's time to live changes the core too).
    pub revision: Option<u64>,
    /// The call changed what the streams show: a publication is due at once
    /// ([`Engine::publication_due`]); poll soon.
    pub publish: bool,
}

/// A request's reply and what it changed.
#[derive(Clone, PartialEq, Debug)]
pub struct Handled {
    /// The reply to write.
    pub reply: Reply,
    /// What the call (time first, then the request) changed.
    pub change: Change,
    /// What the request asked that was refused and is worth a line in the host's log
    /// ([`sync::Synced::refused`]); the reply says it to the caller either way.
    pub refused: Vec<String>,
}

/// One publication of every stream, as the core was when it was polled.
#[derive(Clone, PartialEq, Debug, Default)]
pub struct Publication {
    /// The revision of the state it shows: a stream never goes back to an older one.
    pub revision: u64,
    /// `/api/planning/velocity_factors`.
    pub velocity: VelocityFactorArray,
    /// `/api/planning/steering_factors`.
    pub steering: SteeringFactorArray,
    /// `/cooperation/scenes` ([`scenes`]).
    pub scenes: SceneArray,
}

/// The core, the RTC routes, the engine's clock, and whether a publication is due.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Engine {
    host: Host,
    options: Options,
    /// The first reading, the engine's time 0.
    origin_ns: Option<i64>,
    /// The reading the core was last told of, in milliseconds of the host's clock (`None` before
    /// the first): the core's own time ([`Host::told_ms`]) counts each step from it at most
    /// [`Options::max_step_ms`]. A reading, not the engine's time, so that a clock that went
    /// back before the first reading still counts on from where it went.
    read_ms: Option<i64>,
    /// Counts the changes made to the core.
    revision: u64,
    /// A change the streams show came since the last publication (or there was none yet).
    unpublished: bool,
    /// The reading of the last publication, in milliseconds of the host's clock (`None` before
    /// the first): the next periodic one is due an interval later, or at once if the clock
    /// goes back before it.
    published_ms: Option<i64>,
}

impl Engine {
    /// An engine over a new core with `config`, the standard RTC interfaces and `options`.
    ///
    /// # Errors
    /// The core's refusal of the configuration ([`EngineError::Config`]); a scene quota whose
    /// interfaces together could hold more scenes than the core's table
    /// ([`EngineError::QuotaOverTable`]).
    pub fn new(config: Config, options: Options) -> Result<Self, EngineError> {
        Self::from_state(State::new(config)?, options)
    }

    /// An engine over a new core configured by the settings file at `settings` (the built-in
    /// settings, [`settings::BUILT_IN`](crate::settings::BUILT_IN), for `None`), the standard
    /// RTC interfaces and those the file adds, and `options`: how every host builds its engine.
    ///
    /// # Errors
    /// A settings file that cannot be read or parsed ([`EngineError::Settings`], naming the
    /// file); otherwise as [`Engine::new`].
    pub fn from_settings(
        settings: Option<&std::path::Path>,
        options: Options,
    ) -> Result<Self, EngineError> {
        let settings = crate::settings::load(settings).map_err(EngineError::Settings)?;
        Self::with_interfaces(settings.config, settings.interfaces, options)
    }

    /// An engine over a new core with `config`, the standard RTC interfaces and `interfaces`
    /// besides, and `options`.
    ///
    /// # Errors
    /// As [`Engine::new`], and [`EngineError::Interfaces`] for an interface whose name another
    /// has, or that binds no sequence.
    pub fn with_interfaces(
        config: Config,
        interfaces: Vec<Binding>,
        options: Options,
    ) -> Result<Self, EngineError> {
        let rtc = Rtc::new(Binding::standard().into_iter().chain(interfaces))
            .map_err(EngineError::Interfaces)?;
        Self::over(State::new(config)?, rtc, options)
    }

    /// An engine over `state` (a core a planner built and fed itself), the standard RTC
    /// interfaces and `options`.
    ///
    /// # Errors
    /// [`EngineError::QuotaOverTable`], as for [`Engine::new`].
    pub fn from_state(state: State, options: Options) -> Result<Self, EngineError> {
        Self::over(state, Rtc::standard(), options)
    }

    /// An engine over `state`, the interfaces of `rtc` and `options`.
    fn over(state: State, mut rtc: Rtc, mut options: Options) -> Result<Self, EngineError> {
        let interfaces = rtc.bindings().len();
        let max_scenes = state.limits().max_scenes;
        if options.scene_quota == SCENE_QUOTA {
            // The default, the table shared by the standard interfaces, is the table shared
            // by these when that is less: settings that add interfaces or shrink the table.
            options.scene_quota = SCENE_QUOTA.min((max_scenes / interfaces.max(1)).max(1));
        }
        if options.scene_quota > 0 {
            if options.scene_quota.saturating_mul(interfaces) > max_scenes {
                return Err(EngineError::QuotaOverTable {
                    quota: options.scene_quota,
                    interfaces,
                    max_scenes,
                });
            }
            rtc = rtc.with_scene_quota(options.scene_quota);
        }
        Ok(Self {
            host: Host::new(state, rtc),
            options,
            origin_ns: None,
            read_ms: None,
            revision: 0,
            unpublished: true,
            published_ms: None,
        })
    }

    /// The core, to query.
    #[must_use]
    pub const fn state(&self) -> &State {
        self.host.state()
    }

    /// The core with its RTC routes, to query.
    #[must_use]
    pub const fn host(&self) -> &Host {
        &self.host
    }

    /// The engine's options.
    #[must_use]
    pub const fn options(&self) -> &Options {
        &self.options
    }

    /// Sets the interval of periodic publications ([`Options::publish_every_ms`]), from the next
    /// publication on: `every` in whole milliseconds, at least 1.
    pub fn set_publish_every(&mut self, every: std::time::Duration) {
        self.options.publish_every_ms = interval_ms(every);
    }

    /// How many changes the core has had.
    #[must_use]
    pub const fn revision(&self) -> u64 {
        self.revision
    }

    /// The reading the core was last told of, as a [`Now`] whose stamp is `stamp`: handling a
    /// request at this time tells the core no time.
    #[must_use]
    pub fn told(&self, stamp: Time) -> Now {
        let told_ns = self.read_ms.map_or(self.origin_ns.unwrap_or(0), |read_ms| {
            read_ms.saturating_mul(1_000_000)
        });
        Now::new(told_ns, stamp)
    }

    /// The millisecond of the reading the core was last told of (`None` before the first). A
    /// call at a reading in that millisecond tells the core no time and leaves the engine as it
    /// was, so [`advance`](Self::advance) at such a reading changes nothing.
    #[must_use]
    pub const fn read_ms(&self) -> Option<i64> {
        self.read_ms
    }

    /// Counts a change of the core, `shown` if it changed what the streams show.
    fn count_change(&mut self, shown: bool) -> Change {
        self.revision += 1;
        self.unpublished |= shown;
        Change {
            revision: Some(self.revision),
            publish: shown,
        }
    }

    /// Tells the core the time `now`: the core's `Tick` for the step from the reading it was
    /// last told of, at most [`Options::max_step_ms`] (`[COOP-ENGINE-STEP.1]`). A reading before
    /// that one is a clock that went back: no time passes, and the next step counts from it, so
    /// that a replayed stretch of time ages scenes as it runs. The transition if time passed.
    fn catch_up(&mut self, now: Now) -> Option<Transition> {
        self.origin_ns.get_or_insert(now.reading_ns);
        let now_ms = reading_ms(now);
        let step_ms = self
            .read_ms
            .map_or(0, |read_ms| now_ms.saturating_sub(read_ms));
        self.read_ms = Some(now_ms);
        let counted_ms = u64::try_from(step_ms)
            .unwrap_or(0)
            .min(self.options.max_step_ms.max(1));
        if counted_ms == 0 {
            // No time passes: nothing to tell the core (most calls of a cycle come here).
            return None;
        }
        match self
            .host
            .advance_to(self.host.told_ms().saturating_add(counted_ms))
        {
            Ok(transition) => transition,
            Err(error) => {
                tracing::error!(%error, "the core refused a tick");
                None
            }
        }
    }

    /// Answers `request`, made at `now`: the core is told the time first
    /// (`[COOP-ENGINE-TIME.1]`), then the request is answered by the adapters, so an operator's
    /// call gets the core's transition's answer at its time (`[COOP-ENGINE-ANSWER.1]`); the
    /// sync's statuses are stamped `now.stamp`.
    pub fn handle(&mut self, request: Request, now: Now) -> Handled {
        let ticked = self.catch_up(now);
        let mut shown = ticked.as_ref().is_some_and(|t| !t.retired.is_empty());
        let mut refused = Vec::new();
        let (reply, changed) = match request {
            Request::Ad(request) => {
                // An AD API call changed the core exactly when an operator decision or a policy
                // is now other than it was, each of which the streams show.
                let answer = self.host.answer(&request);
                shown |= answer.changed;
                (Reply::Ad(answer.response), answer.changed)
            }
            Request::Sync(request) => {
                let named = shown::named(&request);
                let before = shown::of_scenes(self.host.state(), &named);
                let synced = sync::answer(&mut self.host, &request, now.stamp);
                shown |= synced.changed && before != shown::of_scenes(self.host.state(), &named);
                refused = synced.refused;
                (Reply::Sync(synced.response), synced.changed)
            }
            Request::Malformed(endpoint, message) => (Reply::refusal(endpoint, message), false),
        };
        let change = if changed || ticked.is_some() {
            self.count_change(shown)
        } else {
            Change::default()
        };
        Handled {
            reply,
            change,
            refused,
        }
    }

    /// Tells the core the time between requests: scenes whose time to live ran out retire.
    pub fn handle_timeout(&mut self, now: Now) -> Change {
        self.advance(now).0
    }

    /// As [`handle_timeout`](Self::handle_timeout), with the core's transition if time passed
    /// (its `retired` are the scenes that aged out).
    pub fn advance(&mut self, now: Now) -> (Change, Option<Transition>) {
        match self.catch_up(now) {
            Some(transition) => (
                self.count_change(!transition.retired.is_empty()),
                Some(transition),
            ),
            None => (Change::default(), None),
        }
    }

    /// A call by a planner in the same process (the C++ class's RTC interfaces, a Rust planner's
    /// own core inputs), made at the time the core was last told: `call` gets the core with its
    /// routes, and its `Ok` counts as a change.
    pub fn call<T, E>(
        &mut self,
        call: impl FnOnce(&mut Host) -> Result<T, E>,
    ) -> (Result<T, E>, Change) {
        let result = call(&mut self.host);
        let change = if result.is_ok() {
            self.count_change(true)
        } else {
            Change::default()
        };
        (result, change)
    }

    /// A call by a planner in the same process made at `now`: the core is told the time first
    /// (`[COOP-ENGINE-TIME.1]`), as [`advance`](Self::advance) tells it, then `call` gets the
    /// core with its routes, all in one step of the engine. The call's result, the change the
    /// two made (one revision), and the transition if time passed (its `retired` are the scenes
    /// that aged out before the call).
    pub fn call_at<T, E>(
        &mut self,
        now: Now,
        call: impl FnOnce(&mut Host) -> Result<T, E>,
    ) -> (Result<T, E>, Change, Option<Transition>) {
        let ticked = self.catch_up(now);
        let result = call(&mut self.host);
        let aged = ticked.as_ref().is_some_and(|t| !t.retired.is_empty());
        let change = if result.is_ok() || ticked.is_some() {
            self.count_change(result.is_ok() || aged)
        } else {
            Change::default()
        };
        (result, change, ticked)
    }

    /// Whether a publication is due at `now` (`[COOP-ENGINE-PUBLISH.1]`): a change the streams
    /// show came since the last publication, or the periodic interval has run.
    #[must_use]
    pub fn publication_due(&self, now: Now) -> bool {
        self.unpublished || self.until_publication_ms(now) == 0
    }

    /// The streams' messages at `now`, if a publication is due ([`publication_due`](Self::publication_due)).
    pub fn poll_publication(&mut self, now: Now) -> Option<Publication> {
        if !self.publication_due(now) {
            return None;
        }
        self.origin_ns.get_or_insert(now.reading_ns);
        self.unpublished = false;
        self.published_ms = Some(reading_ms(now));
        Some(self.publication(now.stamp))
    }

    /// The streams' messages for the core as it is, stamped `stamp`, whether or not a
    /// publication is due: what [`poll_publication`](Self::poll_publication) hands out.
    #[must_use]
    pub fn publication(&self, stamp: Time) -> Publication {
        let state = self.host.state();
        Publication {
            revision: self.revision,
            velocity: wire::velocity_factors(state, stamp),
            steering: wire::steering_factors(state, stamp),
            scenes: scenes::scene_array(state, stamp),
        }
    }

    /// The reading of the last publication, in whole milliseconds of the host's clock (`None`
    /// before the first): with the interval, what decides when the next periodic one is due.
    #[must_use]
    pub const fn last_publication_ms(&self) -> Option<i64> {
        self.published_ms
    }

    /// Milliseconds from `now` until the next periodic publication is due (0 if it is): the
    /// publication interval after the last publication's reading; at once before the first, and
    /// when `now` reads earlier than the last (a clock that went back: its stamps would go back
    /// too).
    #[must_use]
    pub fn until_publication_ms(&self, now: Now) -> u64 {
        let Some(published_ms) = self.published_ms else {
            return 0;
        };
        let since_ms = reading_ms(now).saturating_sub(published_ms);
        if since_ms < 0 {
            return 0;
        }
        self.options
            .publish_every_ms
            .max(1)
            .saturating_sub(u64::try_from(since_ms).unwrap_or(u64::MAX))
    }

    /// Milliseconds from `now` until the host should call again (`[COOP-ENGINE-WAKE.1]`): a
    /// publication is due, a scene's time to live runs out
    /// ([`until_expiry_ms`](Self::until_expiry_ms)), or the step from the reading the core was
    /// last told of reaches [`Options::max_step_ms`], after which time the host's clock runs
    /// would no longer all count (`[COOP-ENGINE-STEP.1]`).
    #[must_use]
    pub fn until_timeout_ms(&self, now: Now) -> u64 {
        self.until_publication_ms(now)
            .min(self.until_expiry_ms(now))
            .min(self.until_step_limit_ms(now))
    }

    /// Milliseconds from `now` until the oldest live scene's time to live has run out, as the
    /// core counts time (`[COOP-TIME-EXPIRE.1]`): telling the core the time then retires it, and
    /// makes a publication due. `u64::MAX` with no live scene. One pass over the live scenes.
    #[must_use]
    pub fn until_expiry_ms(&self, now: Now) -> u64 {
        let Some(oldest_ms) = self.state().scenes().map(|(_, scene)| scene.age_ms()).max() else {
            return u64::MAX;
        };
        // A scene expires once its age is over the time to live.
        let left_ms = self
            .state()
            .limits()
            .ttl_ms
            .saturating_sub(oldest_ms)
            .saturating_add(1);
        let since_ms = self.read_ms.map_or(0, |read_ms| {
            u64::try_from(reading_ms(now).saturating_sub(read_ms)).unwrap_or(0)
        });
        left_ms.saturating_sub(since_ms)
    }

    /// Milliseconds from `now` until the step from the reading the core was last told of
    /// reaches [`Options::max_step_ms`]: the latest a host tells the time for all of it to count
    /// (`[COOP-ENGINE-STEP.1]`).
    #[must_use]
    pub fn until_step_limit_ms(&self, now: Now) -> u64 {
        let max_step_ms = self.options.max_step_ms.max(1);
        self.read_ms.map_or(max_step_ms, |read_ms| {
            let limit = i64::try_from(max_step_ms).unwrap_or(i64::MAX);
            let left = read_ms
                .saturating_add(limit)
                .saturating_sub(reading_ms(now));
            u64::try_from(left).unwrap_or(0)
        })
    }
}

/// The interval of periodic publications for a rate of `rate_hz` publications a second (a
/// node's `--rate`): every host takes a rate the same way.
///
/// # Errors
/// [`EngineError::PublicationRate`] for a rate that is not above 0 and at most
/// [`MAX_PUBLICATION_RATE_HZ`].
pub fn publish_every(rate_hz: f64) -> Result<std::time::Duration, EngineError> {
    let refused = || EngineError::PublicationRate(rate_hz.to_string());
    if !(rate_hz.is_finite() && rate_hz > 0.0 && rate_hz <= MAX_PUBLICATION_RATE_HZ) {
        return Err(refused());
    }
    std::time::Duration::try_from_secs_f64(1.0 / rate_hz).map_err(|_| refused())
}

/// `now`'s reading in whole milliseconds.
pub(crate) const fn reading_ms(now: Now) -> i64 {
    now.reading_ns.div_euclid(1_000_000)
}
