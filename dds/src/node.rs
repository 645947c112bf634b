//! The node: the service engine ([`cooperation_adapters::engine`]) behind one lock ([`Shared`]), its
//! clock, and the DDS entities that reach it, driven by one thread that polls them.
//!
//! Each service request is read outside the lock ([`Endpoint::read`]), answered by the engine
//! in one short critical section ([`Engine::handle`]), and its reply written once the client's
//! reply reader is matched, or after [`REPLY_WAIT`] at most (`Replies`). The factors are
//! published when the engine says a publication is due: every `publish_every`, and at once
//! after a change they show.

use std::net::IpAddr;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use cooperation_adapters::clock::Clock;
use cooperation_adapters::dds::Endpoint;
use cooperation_adapters::engine::{self, Engine};
use cooperation_adapters::refusals::Refusals;
use cooperation_adapters::Shared;
use rustdds::mio1::{Events, Poll};
use rustdds::DomainParticipant;

pub use crate::entities::REPLY_WAIT;
use crate::entities::{
    refusal_log, refused_line, sum_up, wait, Factors, Participant, Replies, Server,
};
use crate::graph::Distro;
use crate::raw::{Raw, RawAdapter};

/// How the node runs.
#[derive(Clone, PartialEq, Debug)]
pub struct Options {
    /// The DDS domain (`ROS_DOMAIN_ID`).
    pub domain: u16,
    /// The local addresses DDS may use; empty for all.
    pub interfaces: Vec<IpAddr>,
    /// The node's name in the ROS graph.
    pub name: String,
    /// The node's namespace.
    pub namespace: String,
    /// The ROS 2 line the graph's messages are written for.
    pub distro: Distro,
    /// The interval of periodic factor publications.
    pub publish_every: Duration,
    /// The live scenes each RTC interface may hold.
    pub scene_quota: usize,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            domain: 0,
            interfaces: Vec::new(),
            name: "cooperation".to_owned(),
            namespace: "/".to_owned(),
            distro: Distro::Humble,
            publish_every: Duration::from_millis(engine::PUBLISH_EVERY_MS),
            scene_quota: engine::Options::default().scene_quota,
        }
    }
}

impl Options {
    /// The engine's options these give.
    #[must_use]
    pub fn engine(&self) -> engine::Options {
        engine::Options {
            scene_quota: self.scene_quota,
            ..engine::Options::default()
        }
        .publishing_every(self.publish_every)
    }
}

/// The node.
pub struct Node {
    shared: Arc<Shared>,
    clock: Clock,
    /// How many of the engine's publications the factor topics have had.
    sent: u64,
    options: Options,
    poll: Poll,
    servers: Vec<Server>,
    factors: Factors,
    replies: Replies,
    /// The log of what the clients send that is refused.
    refusals: Refusals,
    /// Kept for the life of the node: the graph's sample is transient-local.
    _graph: rustdds::no_key::DataWriter<Raw, RawAdapter>,
    /// Kept last: the entities above belong to it.
    _participant: DomainParticipant,
}

impl core::fmt::Debug for Node {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Node")
            .field("options", &self.options)
            .field("replies", &self.replies.len())
            .finish_non_exhaustive()
    }
}

impl Node {
    /// A node over a new engine built from the settings file at `settings` (the built-in
    /// settings for `None`) and `options` ([`Engine::from_settings`]), its DDS participant
    /// joined to the domain.
    ///
    /// # Errors
    /// The settings' or the core's refusal of the configuration, or what DDS could not create.
    pub fn new(settings: Option<&Path>, options: Options) -> Result<Self, String> {
        let engine =
            Engine::from_settings(settings, options.engine()).map_err(|error| error.to_string())?;
        Self::with_shared(Arc::new(Shared::new(engine)), Clock::start(), options)
    }

    /// A node serving `shared`'s engine, read on `clock`, its DDS participant joined to the
    /// domain: one door of a process whose other doors (`cooperation-server`'s rosbridge and
    /// panel) serve the same engine on the same clock. The engine's options are its own:
    /// `options.publish_every` and `options.scene_quota` are not read.
    ///
    /// # Errors
    /// What DDS could not create.
    pub fn with_shared(
        shared: Arc<Shared>,
        clock: Clock,
        options: Options,
    ) -> Result<Self, String> {
        let joined = Participant::join(options.domain, &options.interfaces)?;
        let factors = Factors::open(&joined)?;
        let poll = Poll::new().map_err(|error| format!("poll: {error}"))?;
        let servers = Endpoint::ALL
            .into_iter()
            .enumerate()
            .map(|(index, endpoint)| Server::open(&joined, &poll, endpoint, index))
            .collect::<Result<Vec<_>, _>>()?;
        let graph = joined.announce(&options, &servers, &factors, Vec::new(), Vec::new())?;
        Ok(Self {
            shared,
            clock,
            sent: 0,
            options,
            poll,
            servers,
            factors,
            replies: Replies::default(),
            refusals: refusal_log(),
            _graph: graph,
            _participant: joined.participant,
        })
    }

    /// The engine, behind the process's one lock.
    #[must_use]
    pub const fn shared(&self) -> &Arc<Shared> {
        &self.shared
    }

    /// Serves until `stop` is set (seen within 100 ms).
    ///
    /// # Errors
    /// The poll failed.
    pub fn run(&mut self, stop: &AtomicBool) -> Result<(), String> {
        let mut events = Events::with_capacity(64);
        while !stop.load(Ordering::Relaxed) {
            let now = self.clock.now();
            let until_timeout =
                Duration::from_millis(self.shared.read(|engine| engine.until_timeout_ms(now)));
            wait(
                &mut self.poll,
                &mut events,
                !self.replies.is_empty(),
                until_timeout,
            )?;
            self.step();
        }
        if let Some(summary) = self.refusals.end_period() {
            tracing::warn!("{summary}");
        }
        Ok(())
    }

    /// One turn: the matches, the requests, the replies due, the clock and the publications.
    fn step(&mut self) {
        let now = self.clock.now();
        sum_up(&self.refusals, now.reading_ns);
        self.shared.update(|engine| engine.handle_timeout(now));
        for server in &mut self.servers {
            server.track_matches();
        }
        for index in 0..self.servers.len() {
            self.serve(index);
        }
        self.replies.flush(&self.servers);
        self.publish();
    }

    /// Answers every request waiting at server `index`.
    fn serve(&mut self, index: usize) {
        loop {
            let Some(server) = self.servers.get_mut(index) else {
                return;
            };
            let endpoint = server.endpoint;
            let Some((client, header, incoming)) = server.next_request(&self.refusals) else {
                return;
            };
            let now = self.clock.now();
            let handled = self.shared.update(|engine| engine.handle(incoming, now));
            for line in &handled.refused {
                refused_line(&self.refusals, endpoint.name(), line);
            }
            if !handled.reply.success() {
                tracing::debug!(service = endpoint.name(), "a request refused");
            }
            if let Some(server) = self.servers.get(index) {
                self.replies
                    .push(server, index, client, header, &handled.reply);
            }
        }
    }

    /// Publishes both factor arrays if the engine says a publication is due, or another door
    /// of the process polled one these topics have not had: taken under the lock, written
    /// outside.
    fn publish(&mut self) {
        let now = self.clock.now();
        let Some((number, publication)) = self.shared.publication(now, self.sent) else {
            return;
        };
        self.sent = number;
        self.factors.publish(&publication);
    }
}
