//! The node: the service engine ([`cooperation_adapters::engine`]) behind one lock
//! ([`cooperation_adapters::Shared`]), the clock it is told the time by, and the streams; or, in
//! the stack mode ([`Node::relayed`]), a door onto a relay another thread owns.
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

/// Where the node's answers and publications come from.
enum Core {
    /// The engine, behind the process's one lock, shared with its other doors.
    Engine(Arc<Shared>),
    /// The stack mode: a relay another thread owns (`cooperation-dds`'s stack node), which
    /// answers the calls sent to it and shows the node its publications ([`Node::show`]).
    Relayed(Relayed),
}

/// The node's side of a relay's door.
struct Relayed {
    /// Where calls go, each with where its reply comes back.
    calls: std::sync::mpsc::Sender<(Request, std::sync::mpsc::Sender<Reply>)>,
    /// Wakes the relay's thread for a call.
    wake: Box<dyn Fn() + Send + Sync>,
    /// The longest a call waits for its reply.
    wait: std::time::Duration,
    /// The names of the relay's RTC interfaces.
    interfaces: Vec<String>,
    /// Calls waiting for their reply now, all connections together.
    waiting: std::sync::atomic::AtomicUsize,
}

/// The most calls the stack mode's door holds waiting for the relay at once, all connections
/// together. Each holds a thread of the runtime's blocking pool (512 threads) until its reply
/// comes or its wait runs out, so one more is refused at once, saying so, rather than taking a
/// thread the node's other work needs.
pub const MAX_WAITING_CALLS: usize = 128;

/// One call counted among [`Relayed::waiting`] while it lives.
struct Waiting<'a>(&'a std::sync::atomic::AtomicUsize);

impl Drop for Waiting<'_> {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

impl core::fmt::Debug for Core {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Engine(shared) => f.debug_tuple("Engine").field(shared).finish(),
            Self::Relayed(relayed) => f
                .debug_struct("Relayed")
                .field("wait", &relayed.wait)
                .finish_non_exhaustive(),
        }
    }
}

/// What the node serves, and the core it serves it from.
#[derive(Debug)]
pub struct Node {
    core: Core,
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
        let node = Self::over(Core::Engine(shared), clock);
        node.publish();
        node
    }

    /// The stack mode's node: a door onto a relay another thread owns. Each call is sent on
    /// `calls` with where its reply goes, `wake` wakes that thread for it, and a call not
    /// answered within `wait` is answered with a refusal that says so. The relay shows the
    /// node what to publish ([`show`](Self::show)); until it first does, the streams have
    /// nothing to send. `interfaces` are the names of the relay's RTC interfaces.
    #[must_use]
    pub fn relayed(
        calls: std::sync::mpsc::Sender<(Request, std::sync::mpsc::Sender<Reply>)>,
        wake: Box<dyn Fn() + Send + Sync>,
        wait: std::time::Duration,
        interfaces: Vec<String>,
    ) -> Self {
        let relayed = Relayed {
            calls,
            wake,
            wait,
            interfaces,
            waiting: std::sync::atomic::AtomicUsize::new(0),
        };
        Self::over(Core::Relayed(relayed), Clock::start())
    }

    fn over(core: Core, clock: Clock) -> Self {
        Self {
            core,
            clock,
            sent: AtomicU64::new(0),
            topics: core::array::from_fn(|_| watch::channel(Publication::default()).0),
            changed: Notify::new(),
        }
    }

    /// The engine, behind the process's one lock; `None` in the stack mode, whose engine is
    /// inside a relay another thread owns.
    #[must_use]
    pub const fn shared(&self) -> Option<&Arc<Shared>> {
        match &self.core {
            Core::Engine(shared) => Some(shared),
            Core::Relayed(_) => None,
        }
    }

    /// The names of the RTC interfaces the node's engine binds (the standard ones and those
    /// its settings add), in the engine's order: those a module's credential may name.
    #[must_use]
    pub fn interfaces(&self) -> Vec<String> {
        match &self.core {
            Core::Engine(shared) => shared.read(|engine| {
                engine
                    .host()
                    .rtc()
                    .bindings()
                    .iter()
                    .map(|binding| binding.name.clone())
                    .collect()
            }),
            Core::Relayed(relayed) => relayed.interfaces.clone(),
        }
    }

    /// The services the node answers, as [`Endpoint::ALL`](engine::Endpoint::ALL) orders
    /// them: all of them, or in the stack mode all but the module sync, since planning modules
    /// report there through their own RTC topics (a sync is refused, saying so).
    #[must_use]
    pub fn endpoints(&self) -> Vec<engine::Endpoint> {
        engine::Endpoint::ALL
            .into_iter()
            .filter(|endpoint| {
                matches!(self.core, Core::Engine(_)) || *endpoint != engine::Endpoint::Sync
            })
            .collect()
    }

    /// The operator decisions `set_commands` may set, as the AD API's constants: all four,
    /// or in the stack mode those a planning module's RTC interface can take
    /// ([`cooperation_adapters::relay::EXPRESSIBLE`]); any other is refused.
    #[must_use]
    pub fn decisions(&self) -> Vec<u8> {
        let decisions: &[cooperation::OperatorDecision] = match &self.core {
            Core::Engine(_) => &cooperation::OperatorDecision::ALL,
            Core::Relayed(_) => &cooperation_adapters::relay::EXPRESSIBLE,
        };
        decisions
            .iter()
            .map(|&decision| wire::CooperationDecision::of(decision).decision)
            .collect()
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
    /// In the stack mode the relay's thread publishes ([`show`](Self::show)): nothing is done.
    pub fn publish(&self) {
        let Core::Engine(shared) = &self.core else {
            return;
        };
        let now = self.clock.now();
        let sent = self.sent.load(Ordering::SeqCst);
        let Some((number, publication)) = shared.publication(now, sent) else {
            return;
        };
        self.sent.fetch_max(number, Ordering::SeqCst);
        self.show(&publication);
    }

    /// Publishes `publication` on every topic, unless a newer state was shown already.
    pub fn show(&self, publication: &engine::Publication) {
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

    /// How long until the engine wants the time told, at the latest: a publication is due, a
    /// scene's time to live runs out, or its step limit is reached
    /// ([`Engine::until_timeout_ms`], `[COOP-ENGINE-STEP.1]`), as every host asks it.
    /// Far off in the stack mode, where the relay's thread tells its engine the time.
    #[must_use]
    pub fn until_timeout(&self) -> std::time::Duration {
        let now = self.clock.now();
        self.read(FAR, |engine| engine.until_timeout_ms(now))
    }

    /// How long until the engine's next periodic publication; far off in the stack mode, where
    /// the relay's thread publishes.
    #[must_use]
    pub fn until_publication(&self) -> std::time::Duration {
        let now = self.clock.now();
        self.read(FAR, |engine| engine.until_publication_ms(now))
    }

    /// `ms(engine)` milliseconds, or `otherwise` in the stack mode.
    fn read(
        &self,
        otherwise: std::time::Duration,
        ms: impl FnOnce(&Engine) -> u64,
    ) -> std::time::Duration {
        match &self.core {
            Core::Engine(shared) => std::time::Duration::from_millis(shared.read(ms)),
            Core::Relayed(_) => otherwise,
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

    /// A request, already read ([`Endpoint::read_json`](cooperation_adapters::engine::Endpoint::read_json)), answered by the engine at the node's time: the
    /// reply, and the revision of the state it made if it changed what the streams show (wait
    /// for [`published`](Self::published) before answering, so that the caller's next
    /// publication shows the change). Takes the lock: call it where blocking is allowed.
    /// A caller that does not wait asks for the publication with
    /// [`publish_soon`](Self::publish_soon).
    ///
    /// In the stack mode the call goes to the relay's thread and this waits for its reply (the
    /// modules' answers included): the streams already show what it changed, so no revision is
    /// given. A call the relay does not answer within the node's wait, or one the relay can no
    /// longer take, is answered with a refusal that says so.
    #[must_use]
    pub fn handle(&self, request: Request) -> (Reply, Option<u64>) {
        match &self.core {
            Core::Engine(shared) => {
                let now = self.clock.now();
                let handled = shared.update(|engine| engine.handle(request, now));
                // A connected client's refusals are logged one a line (docs/server.md).
                for line in &handled.refused {
                    tracing::warn!("{line}");
                }
                let shown = handled.change.revision.filter(|_| handled.change.publish);
                (handled.reply, shown)
            }
            Core::Relayed(relayed) => (relayed.call(request), None),
        }
    }

    /// Tells the engine the time; publishes soon if scenes expired. Nothing in the stack mode,
    /// where the relay's thread does.
    pub fn tick(&self) {
        let Core::Engine(shared) = &self.core else {
            return;
        };
        let now = self.clock.now();
        let change = shared.update(|engine| engine.handle_timeout(now));
        if change.publish {
            self.publish_soon();
        }
    }
}

/// How long the periodic tasks wait in the stack mode, where they have nothing to do.
const FAR: std::time::Duration = std::time::Duration::from_secs(3600);

impl Relayed {
    /// `request` answered by the relay's thread.
    fn call(&self, request: Request) -> Reply {
        let endpoint = request.endpoint();
        let before = self.waiting.fetch_add(1, Ordering::SeqCst);
        let _waiting = Waiting(&self.waiting);
        if before >= MAX_WAITING_CALLS {
            return Reply::refusal(
                endpoint,
                format!(
                    "the stack mode's relay has {MAX_WAITING_CALLS} calls waiting, the most the \
                     node holds: call again"
                ),
            );
        }
        let (to, from) = std::sync::mpsc::channel();
        if self.calls.send((request, to)).is_err() {
            return Reply::refusal(endpoint, "the stack mode's relay has stopped".to_owned());
        }
        (self.wake)();
        from.recv_timeout(self.wait).unwrap_or_else(|error| {
            let why = match error {
                std::sync::mpsc::RecvTimeoutError::Timeout => format!(
                    "the stack mode's relay did not answer within {} ms",
                    self.wait.as_millis()
                ),
                std::sync::mpsc::RecvTimeoutError::Disconnected => {
                    "the stack mode's relay has stopped".to_owned()
                }
            };
            Reply::refusal(endpoint, why)
        })
    }
}
