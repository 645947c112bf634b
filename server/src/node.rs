//! The node: the verified core with its RTC interfaces behind one lock
//! ([`cooperation_ros::Shared`]), the clock that ticks it, and the two factor streams.
//!
//! Every service call, module sync and tick is one short critical section on that lock, and
//! nothing else is locked: the streams are read under it, serialized outside it, once per
//! publication, and handed to every subscriber as the same bytes. Each publication carries the
//! revision of the state it shows (changes are counted under the lock), so a stream never goes
//! back to an older state, whatever order publications finish in, and a caller whose call
//! changed the state can wait for the publication that shows it.

use std::sync::atomic::{AtomicU64, Ordering};

use axum::extract::ws::Utf8Bytes;
use cooperation::{Config, ConfigError, State};
use cooperation_ros::rtc::Rtc;
use cooperation_ros::wire::{self, Request, Response};
use cooperation_ros::{Host, Shared};
use serde::Serialize;
use tokio::sync::{watch, Notify};

use crate::scenes;
use crate::sync::{self, SyncRequest, SyncResponse};
use cooperation_ros::clock::Clock;

/// The topics the node publishes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Topic {
    /// `/api/planning/velocity_factors`.
    Velocity,
    /// `/api/planning/steering_factors`.
    Steering,
    /// `/cooperation/scenes` ([`crate::scenes`]).
    Scenes,
}

impl Topic {
    /// Every topic, in the order of [`index`](Self::index).
    pub const ALL: [Self; 3] = [Self::Velocity, Self::Steering, Self::Scenes];

    /// The topic's position in [`ALL`](Self::ALL).
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The topic's name.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Velocity => wire::VELOCITY_FACTORS,
            Self::Steering => wire::STEERING_FACTORS,
            Self::Scenes => scenes::NAME,
        }
    }

    /// The topic's message type.
    #[must_use]
    pub const fn type_name(self) -> &'static str {
        match self {
            Self::Velocity => wire::VELOCITY_FACTORS_TYPE,
            Self::Steering => wire::STEERING_FACTORS_TYPE,
            Self::Scenes => scenes::TYPE,
        }
    }

    /// The topic named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|topic| topic.name() == name)
    }
}

/// One publication of a topic: the `publish` frame, and the revision of the state it shows.
#[derive(Clone, Debug, Default)]
pub struct Publication {
    /// How many changes the state it shows had had.
    pub revision: u64,
    /// The rosbridge `publish` frame.
    pub frame: Utf8Bytes,
}

/// What the node serves, and the core it serves it from.
#[derive(Debug)]
pub struct Node {
    /// The one lock: the core, the RTC interfaces' routing, and the time the core was told.
    shared: Shared,
    clock: Clock,
    /// Counts the changes made to the core, from 1. Written and read only with the lock held,
    /// so its value, read under the lock, is the revision of the state the lock guards.
    revision: AtomicU64,
    /// Each topic's newest publication, in [`Topic::ALL`]'s order.
    topics: [watch::Sender<Publication>; 3],
    /// Woken by a change that should be published soon.
    changed: Notify,
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

/// Replaces the topic's publication with one of the same state or a newer one (a periodic
/// publication of an unchanged state goes out with its new stamp); one of an older state, read
/// before the current one was, is dropped.
fn send_newer(topic: &watch::Sender<Publication>, publication: Publication) {
    topic.send_if_modified(|current| {
        let newer = publication.revision >= current.revision;
        if newer {
            *current = publication;
        }
        newer
    });
}

/// The live scenes each RTC interface may hold, unless told otherwise.
pub use cooperation_ros::rtc::SCENE_QUOTA;

impl Node {
    /// A node over a new core with `config`, and the standard RTC interfaces, each holding at
    /// most [`SCENE_QUOTA`] live scenes.
    ///
    /// # Errors
    /// The core's refusal of the configuration.
    pub fn new(config: Config) -> Result<Self, ConfigError> {
        Self::with_scene_quota(config, SCENE_QUOTA)
    }

    /// As [`new`](Self::new), each RTC interface holding at most `quota` live scenes
    /// ([`Rtc::with_scene_quota`]).
    ///
    /// # Errors
    /// The core's refusal of the configuration.
    pub fn with_scene_quota(config: Config, quota: usize) -> Result<Self, ConfigError> {
        let state = State::new(config)?;
        let node = Self {
            shared: Shared::new(Host::new(state, Rtc::standard().with_scene_quota(quota))),
            clock: Clock::start(),
            revision: AtomicU64::new(0),
            topics: core::array::from_fn(|_| watch::channel(Publication::default()).0),
            changed: Notify::new(),
        };
        node.publish();
        Ok(node)
    }

    /// The core and its RTC interfaces, behind the node's one lock.
    #[must_use]
    pub const fn shared(&self) -> &Shared {
        &self.shared
    }

    /// The node's clock.
    #[must_use]
    pub const fn clock(&self) -> &Clock {
        &self.clock
    }

    /// A receiver of `topic`'s publications: always the newest, earlier ones skipped.
    #[must_use]
    pub fn subscribe(&self, topic: Topic) -> watch::Receiver<Publication> {
        self.sender(topic).subscribe()
    }

    fn sender(&self, topic: Topic) -> &watch::Sender<Publication> {
        // `topics` has one sender per topic, in `Topic::ALL`'s order.
        #[allow(clippy::indexing_slicing)]
        &self.topics[topic.index()]
    }

    /// Counts a change, with the lock held: the state's new revision.
    fn count_change(&self) -> u64 {
        self.revision.fetch_add(1, Ordering::SeqCst) + 1
    }

    /// Reads every topic from the core as it is now and publishes them: read under the lock,
    /// serialized outside it.
    pub fn publish(&self) {
        let stamp = self.clock.stamp();
        let (revision, velocity, steering, scenes) = self.shared.read(|host| {
            (
                self.revision.load(Ordering::SeqCst),
                wire::velocity_factors(host.state(), stamp),
                wire::steering_factors(host.state(), stamp),
                scenes::scene_array(host.state(), stamp),
            )
        });
        let frames = [
            publish_frame(Topic::Velocity, &velocity),
            publish_frame(Topic::Steering, &steering),
            publish_frame(Topic::Scenes, &scenes),
        ];
        for (topic, frame) in Topic::ALL.into_iter().zip(frames) {
            send_newer(self.sender(topic), Publication { revision, frame });
        }
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

    /// Waits until every stream shows revision `revision` or a later one, asking for a
    /// publication. Callers changing the core at once share that publication.
    pub async fn published(&self, revision: u64) {
        self.publish_soon();
        for topic in Topic::ALL {
            let mut receiver = self.subscribe(topic);
            // The sender lives as long as the node, so the wait ends with the publication.
            let _shown = receiver
                .wait_for(|publication| publication.revision >= revision)
                .await;
        }
    }

    /// An AD API service call, already read: the typed response, and the revision of the
    /// state it made if it changed the core (wait for [`published`](Self::published) before
    /// answering, so that the caller's next publication shows the change). Takes the lock: call
    /// it where blocking is allowed.
    #[must_use]
    pub fn call(&self, request: &Request) -> (Response, Option<u64>) {
        self.shared.update(|host| {
            let answer = host.answer(request);
            let revision = answer.changed.then(|| self.count_change());
            (answer.response, revision)
        })
    }

    /// A planning module's sync (`docs/server.md`), already read. The core's time is brought
    /// up to now first, so a scene reported here starts its time to live now, not at the last
    /// periodic tick. Takes the lock: call it where blocking is allowed.
    #[must_use]
    pub fn sync(&self, request: &SyncRequest) -> SyncResponse {
        let stamp = self.clock.stamp();
        let now_ms = self.clock.elapsed_ms();
        let (response, shown) = self.shared.update(|host| {
            let expired = catch_up(host, now_ms);
            let (response, effect) = sync::answer(host, request, stamp);
            if effect.changed || expired {
                self.count_change();
            }
            (response, effect.shown || expired)
        });
        // A report that changed nothing the streams show (the same status again) waits for
        // the periodic publication.
        if shown {
            self.publish_soon();
        }
        response
    }

    /// Tells the core how much monotonic time passed since it was last told; publishes soon if
    /// scenes expired.
    pub fn tick(&self) {
        let now_ms = self.clock.elapsed_ms();
        let expired = self.shared.update(|host| {
            let expired = catch_up(host, now_ms);
            if expired {
                self.count_change();
            }
            expired
        });
        if expired {
            self.publish_soon();
        }
    }
}

/// The core's `Tick` up to `now_ms` on the node's monotonic clock; whether scenes expired.
fn catch_up(host: &mut Host, now_ms: u64) -> bool {
    match host.advance_to(now_ms) {
        Ok(transition) => transition.is_some_and(|t| !t.retired.is_empty()),
        Err(error) => {
            tracing::error!(%error, "the core refused a tick");
            false
        }
    }
}
