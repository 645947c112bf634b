//! The node: the verified core behind [`Shared`](cooperation::Shared), the RTC interfaces beside it, the clock that
//! ticks it, and the two factor streams.
//!
//! Every service call, module sync and tick is one short critical section on the core; the
//! streams are serialized once per publication and handed to every subscriber as the same
//! bytes.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use axum::extract::ws::Utf8Bytes;
use cooperation::rtc::Rtc;
use cooperation::wire::{self, Service};
use cooperation::{Config, ConfigError, State};
use serde::Serialize;
use tokio::sync::{watch, Notify};

use crate::clock::Clock;
use crate::sync;

/// The two topics the node publishes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Topic {
    /// `/api/planning/velocity_factors`.
    Velocity,
    /// `/api/planning/steering_factors`.
    Steering,
}

impl Topic {
    /// Both topics.
    pub const ALL: [Self; 2] = [Self::Velocity, Self::Steering];

    /// The topic's name.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Velocity => "/api/planning/velocity_factors",
            Self::Steering => "/api/planning/steering_factors",
        }
    }

    /// The topic's message type.
    #[must_use]
    pub const fn type_name(self) -> &'static str {
        match self {
            Self::Velocity => "autoware_adapi_v1_msgs/msg/VelocityFactorArray",
            Self::Steering => "autoware_adapi_v1_msgs/msg/SteeringFactorArray",
        }
    }

    /// The topic named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|topic| topic.name() == name)
    }
}

/// What the node serves, and the core it serves it from.
#[derive(Debug)]
pub struct Node {
    shared: cooperation::Shared,
    /// The RTC interfaces' routing. Locked before the core, never after it.
    rtc: Mutex<Rtc>,
    clock: Clock,
    /// Counts the changes answered to callers that wait for their publication
    /// ([`call`](Self::call)), from 1.
    changes: AtomicU64,
    /// Held while a publication is read and sent, so publications leave in the order their
    /// states were read: a stream never goes back to an older state. It holds the number of
    /// changes the newest publication is known to show.
    publishing: Mutex<u64>,
    velocity: watch::Sender<Utf8Bytes>,
    steering: watch::Sender<Utf8Bytes>,
    /// Woken by a change that should be published soon (module syncs, expiries).
    changed: Notify,
    /// The monotonic time of the last tick, in milliseconds.
    ticked_ms: Mutex<u64>,
}

/// A lock whose holder panicked is used as it is: the core's own lock explains why the core
/// cannot be half-changed, and the node's other locks guard no invariant a panic could break.
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(PoisonError::into_inner)
}

/// A `publish` frame of rosbridge.
#[derive(Serialize)]
struct Publish<'a, M> {
    op: &'static str,
    topic: &'static str,
    msg: &'a M,
}

fn publish_frame<M: Serialize>(topic: Topic, msg: &M) -> Utf8Bytes {
    let frame = Publish {
        op: "publish",
        topic: topic.name(),
        msg,
    };
    Utf8Bytes::from(serde_json::to_string(&frame).unwrap_or_default())
}

impl Node {
    /// A node over a new core with `config`, and the standard RTC interfaces.
    ///
    /// # Errors
    /// The core's refusal of the configuration.
    pub fn new(config: Config) -> Result<Self, ConfigError> {
        let state = State::new(config)?;
        let (velocity, _) = watch::channel(Utf8Bytes::default());
        let (steering, _) = watch::channel(Utf8Bytes::default());
        let node = Self {
            shared: cooperation::Shared::new(state),
            rtc: Mutex::new(Rtc::standard()),
            clock: Clock::start(),
            changes: AtomicU64::new(0),
            publishing: Mutex::new(0),
            velocity,
            steering,
            changed: Notify::new(),
            ticked_ms: Mutex::new(0),
        };
        node.publish();
        Ok(node)
    }

    /// The core, for reading.
    #[must_use]
    pub const fn shared(&self) -> &cooperation::Shared {
        &self.shared
    }

    /// The node's clock.
    #[must_use]
    pub const fn clock(&self) -> &Clock {
        &self.clock
    }

    /// A receiver of `topic`'s publications: always the newest, earlier ones skipped.
    #[must_use]
    pub fn subscribe(&self, topic: Topic) -> watch::Receiver<Utf8Bytes> {
        match topic {
            Topic::Velocity => self.velocity.subscribe(),
            Topic::Steering => self.steering.subscribe(),
        }
    }

    /// Reads both streams from the core as it is now and publishes them.
    pub fn publish(&self) {
        self.publish_holding(&mut lock(&self.publishing));
    }

    /// [`publish`](Self::publish), with the publishing lock held; `shown` is what it guards.
    fn publish_holding(&self, shown: &mut u64) {
        // Read before the core: every change counted so far is in the core read below.
        *shown = self.changes.load(Ordering::SeqCst);
        let stamp = self.clock.stamp();
        let (velocity, steering) = self.shared.read(|state| {
            (
                wire::velocity_factors(state, stamp),
                wire::steering_factors(state, stamp),
            )
        });
        self.velocity
            .send_replace(publish_frame(Topic::Velocity, &velocity));
        self.steering
            .send_replace(publish_frame(Topic::Steering, &steering));
    }

    /// Asks the publishing task to publish soon; several asks before it runs make one
    /// publication.
    pub fn publish_soon(&self) {
        self.changed.notify_one();
    }

    /// Waits for [`publish_soon`](Self::publish_soon).
    pub async fn publish_asked(&self) {
        self.changed.notified().await;
    }

    /// An AD API service call, from the request's JSON to the response's. A call that changed
    /// the core is published before this returns, so the caller's next publication shows it.
    ///
    /// Callers changing the core at once share publications: a call whose change is already
    /// shown by a publication that read the core after it does not publish again. It may wait
    /// for that publication (publications are made one at a time), so call it where blocking
    /// is allowed.
    #[must_use]
    pub fn call(&self, service: Service, args: &[u8]) -> Vec<u8> {
        let response = self.shared.update(|state| service.call_json(state, args));
        if service != Service::GetPolicies && succeeded(&response) {
            // Counted after the change is in the core, so a publication that reads the count
            // first and the core after shows it.
            let change = self.changes.fetch_add(1, Ordering::SeqCst) + 1;
            let mut shown = lock(&self.publishing);
            if *shown < change {
                self.publish_holding(&mut shown);
            }
        }
        response
    }

    /// A planning module's sync (`docs/server.md`), from JSON to JSON. The core's time is
    /// brought up to now first, so a scene reported here starts its time to live now, not at
    /// the last periodic tick.
    #[must_use]
    pub fn sync(&self, args: &[u8]) -> Vec<u8> {
        // Read before any lock is taken, so a large request holds up no one else.
        let request = match sync::read(args) {
            Ok(request) => request,
            Err(message) => return wire::to_json(&sync::refused(message)),
        };
        let mut rtc = lock(&self.rtc);
        let stamp = self.clock.stamp();
        let (expired, (response, changed)) = self.shared.update(|state| {
            let expired = self.catch_up(&mut rtc, state);
            (expired, sync::answer(&mut rtc, state, &request, stamp))
        });
        drop(rtc);
        if changed || expired {
            self.publish_soon();
        }
        wire::to_json(&response)
    }

    /// Tells the core how much monotonic time passed since it was last told; publishes soon if
    /// scenes expired.
    pub fn tick(&self) {
        let mut rtc = lock(&self.rtc);
        let expired = self.shared.update(|state| self.catch_up(&mut rtc, state));
        drop(rtc);
        if expired {
            self.publish_soon();
        }
    }

    /// The core's `Tick` for the time since the last one, with the RTC interfaces' lock and the
    /// core's held; whether scenes expired.
    fn catch_up(&self, rtc: &mut Rtc, state: &mut State) -> bool {
        let now = self.clock.elapsed_ms();
        let mut ticked = lock(&self.ticked_ms);
        let elapsed_ms = now.saturating_sub(*ticked);
        *ticked = now;
        drop(ticked);
        if elapsed_ms == 0 {
            return false;
        }
        match rtc.tick(state, elapsed_ms) {
            Ok(transition) => !transition.retired.is_empty(),
            Err(error) => {
                tracing::error!(%error, "the core refused a tick");
                false
            }
        }
    }
}

/// Whether a `set_*` response's status is a success.
fn succeeded(response: &[u8]) -> bool {
    wire::from_json::<wire::SetCooperationCommandsResponse>(response)
        .is_ok_and(|response| response.status.success)
}
