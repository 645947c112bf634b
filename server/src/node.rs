//! The node: the service engine ([`cooperation_adapters::engine`]) behind one lock
//! ([`cooperation_adapters::Shared`]), the clock it is told the time by, and the streams.
//!
//! Every service call, module sync and tick is one short critical section on that lock, and
//! nothing else is locked: the engine decides when a publication is due and hands out its
//! messages under the lock; they are serialized outside it, once per publication, and handed to
//! every subscriber as the same bytes. Each publication carries the revision of the state it
//! shows, so a stream never goes back to an older state, whatever order publications finish in,
//! and a caller whose call changed what the streams show can wait for the publication that
//! shows it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use axum::extract::ws::Utf8Bytes;
use cooperation::Config;
use cooperation_adapters::engine::EngineError;
use cooperation_adapters::engine::{self, Engine, Reply, Request};
use cooperation_adapters::wire;
use cooperation_adapters::Shared;
use serde::Serialize;
use tokio::sync::{watch, Notify};

use crate::scenes;
use cooperation_adapters::clock::Clock;

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
    /// The one lock: the engine, shared with the process's other doors.
    shared: Arc<Shared>,
    clock: Clock,
    /// How many of the engine's publications the streams have had.
    sent: AtomicU64,
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
pub use cooperation_adapters::rtc::SCENE_QUOTA;

impl Node {
    /// A node over a new core with `config`, and the engine's default options
    /// ([`engine::Options`]).
    ///
    /// # Errors
    /// The engine's refusal of the configuration ([`EngineError`]).
    pub fn new(config: Config) -> Result<Self, EngineError> {
        Self::with_options(config, engine::Options::default())
    }

    /// As [`new`](Self::new), each RTC interface holding at most `quota` live scenes.
    ///
    /// # Errors
    /// The engine's refusal of the configuration, the quota included ([`EngineError`]).
    pub fn with_scene_quota(config: Config, quota: usize) -> Result<Self, EngineError> {
        Self::with_options(
            config,
            engine::Options {
                scene_quota: quota,
                ..engine::Options::default()
            },
        )
    }

    /// A node over a new engine built from the settings file at `settings` (the built-in
    /// settings for `None`) and `options` ([`Engine::from_settings`]).
    ///
    /// # Errors
    /// The settings' or the engine's refusal of the configuration ([`EngineError`]).
    pub fn from_settings(
        settings: Option<&std::path::Path>,
        options: engine::Options,
    ) -> Result<Self, EngineError> {
        let shared = Arc::new(Shared::new(Engine::from_settings(settings, options)?));
        Ok(Self::with_shared(shared, Clock::start()))
    }

    /// A node over a new engine with `config` and `options`.
    ///
    /// # Errors
    /// The engine's refusal of the configuration ([`EngineError`]).
    pub fn with_options(config: Config, options: engine::Options) -> Result<Self, EngineError> {
        let shared = Arc::new(Shared::new(Engine::new(config, options)?));
        Ok(Self::with_shared(shared, Clock::start()))
    }

    /// A node serving `shared`'s engine, read on `clock`: one door of a process whose other
    /// doors (`cooperation-dds`'s DDS node) serve the same engine on the same clock.
    #[must_use]
    pub fn with_shared(shared: Arc<Shared>, clock: Clock) -> Self {
        let node = Self {
            shared,
            clock,
            sent: AtomicU64::new(0),
            topics: core::array::from_fn(|_| watch::channel(Publication::default()).0),
            changed: Notify::new(),
        };
        node.publish();
        node
    }

    /// The engine, behind the process's one lock.
    #[must_use]
    pub const fn shared(&self) -> &Arc<Shared> {
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

    /// Publishes every topic if the engine says a publication is due now, or another door of
    /// the process polled one these streams have not had: its messages taken under the lock,
    /// serialized outside it.
    pub fn publish(&self) {
        let now = self.clock.now();
        let sent = self.sent.load(Ordering::SeqCst);
        let Some((number, publication)) = self.shared.publication(now, sent) else {
            return;
        };
        self.sent.fetch_max(number, Ordering::SeqCst);
        let revision = publication.revision;
        let frames = [
            publish_frame(Topic::Velocity, &publication.velocity),
            publish_frame(Topic::Steering, &publication.steering),
            publish_frame(Topic::Scenes, &publication.scenes),
        ];
        for (topic, frame) in Topic::ALL.into_iter().zip(frames) {
            send_newer(self.sender(topic), Publication { revision, frame });
        }
    }

    /// How long until the engine wants the time told, at the latest (its step limit,
    /// `[COOP-ENGINE-STEP.1]`).
    #[must_use]
    pub fn until_step_limit(&self) -> std::time::Duration {
        let now = self.clock.now();
        let ms = self.shared.read(|engine| engine.until_step_limit_ms(now));
        std::time::Duration::from_millis(ms)
    }

    /// How long until the engine's next periodic publication.
    #[must_use]
    pub fn until_publication(&self) -> std::time::Duration {
        let now = self.clock.now();
        let ms = self.shared.read(|engine| engine.until_publication_ms(now));
        std::time::Duration::from_millis(ms)
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

    /// A request, already read ([`Endpoint::read_json`](cooperation_adapters::engine::Endpoint::read_json)), answered by the engine at the node's time: the
    /// reply, and the revision of the state it made if it changed what the streams show (wait
    /// for [`published`](Self::published) before answering, so that the caller's next
    /// publication shows the change). Takes the lock: call it where blocking is allowed.
    /// A caller that does not wait asks for the publication with
    /// [`publish_soon`](Self::publish_soon).
    #[must_use]
    pub fn handle(&self, request: Request) -> (Reply, Option<u64>) {
        let now = self.clock.now();
        let handled = self.shared.update(|engine| engine.handle(request, now));
        let shown = handled.change.revision.filter(|_| handled.change.publish);
        (handled.reply, shown)
    }

    /// Tells the engine the time; publishes soon if scenes expired.
    pub fn tick(&self) {
        let now = self.clock.now();
        let change = self.shared.update(|engine| engine.handle_timeout(now));
        if change.publish {
            self.publish_soon();
        }
    }
}
