//! The node: the service engine ([`cooperation_adapters::engine`]) behind one lock ([`Shared`]), its
//! clock, and the DDS entities that reach it, driven by one thread that polls them.
//!
//! Each service request is read outside the lock ([`Endpoint::read`]), answered by the engine
//! in one short critical section ([`Engine::handle`]), and its reply written once the client's
//! reply reader is matched, or after [`REPLY_WAIT`] at most: a reliable, volatile writer does not
//! send a sample to a reader it matches later, so a reply written before the match would be
//! lost. The factors are published when the engine says a publication is due: every
//! `publish_every`, and at once after a change they show.

use std::collections::BTreeSet;
use std::net::IpAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use cooperation::Config;
use cooperation_adapters::clock::Clock;
use cooperation_adapters::dds::{self, Endpoint};
use cooperation_adapters::engine::{self, Engine, Request};
use cooperation_adapters::wire;
use cooperation_adapters::{cdr, Shared};
use rustdds::mio1::{Events, Interest, Poll, Token};
use rustdds::no_key::{DataReader, DataWriter};
use rustdds::policy::{Durability, History, Reliability};
use rustdds::{
    DataWriterStatus, DomainParticipant, DomainParticipantBuilder, Publisher, QosPolicies,
    QosPolicyBuilder, RTPSEntity, StatusEvented, Subscriber, Topic, TopicKind, GUID,
};

use crate::graph::{self, Distro, Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use crate::raw::{Raw, RawAdapter};

/// How long a reply waits for its client's reply reader to be matched, as `rmw_cyclonedds_cpp`
/// waits before it answers.
pub const REPLY_WAIT: Duration = Duration::from_millis(100);

/// How often the poll wakes while replies wait for their readers.
const REPLY_POLL: Duration = Duration::from_millis(2);

/// The longest the poll sleeps, whatever the publication interval: how soon a stop is seen.
const STOP_POLL: Duration = Duration::from_millis(100);

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

/// One service: where its requests arrive, where its replies leave, and which reply readers are
/// matched.
struct Server {
    endpoint: Endpoint,
    requests: DataReader<Raw, RawAdapter>,
    replies: DataWriter<Raw, RawAdapter>,
    matched: BTreeSet<GUID>,
}

/// A reply waiting for its client's reader.
struct Pending {
    server: usize,
    client: [u8; 12],
    reply: Raw,
    deadline: Instant,
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
    velocity: DataWriter<Raw, RawAdapter>,
    steering: DataWriter<Raw, RawAdapter>,
    /// Kept for the life of the node: the graph's sample is transient-local.
    _graph: DataWriter<Raw, RawAdapter>,
    pending: Vec<Pending>,
    /// Kept last: the entities above belong to it.
    _participant: DomainParticipant,
}

impl core::fmt::Debug for Node {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Node")
            .field("options", &self.options)
            .field("pending", &self.pending.len())
            .finish_non_exhaustive()
    }
}

/// The participant a DDS entity belongs to: its GUID's prefix.
fn participant(guid: GUID) -> [u8; 12] {
    guid.to_bytes().first_chunk().copied().unwrap_or_default()
}

/// Reliable, with `durability`, the newest `depth` samples kept.
fn qos(durability: Durability, depth: i32) -> QosPolicies {
    QosPolicyBuilder::new()
        .reliability(Reliability::Reliable {
            max_blocking_time: rustdds::Duration::from_millis(100),
        })
        .durability(durability)
        .history(History::KeepLast { depth })
        .build()
}

/// The AD API's QoS for the factors: reliable, volatile, the newest one kept.
fn factors_qos() -> QosPolicies {
    qos(Durability::Volatile, 1)
}

/// ROS 2's default QoS for services: reliable, volatile, ten kept.
fn services_qos() -> QosPolicies {
    qos(Durability::Volatile, 10)
}

/// The graph's QoS: reliable, transient local (a late joiner is sent the newest sample).
fn graph_qos() -> QosPolicies {
    qos(Durability::TransientLocal, 1)
}

fn topic(
    participant: &DomainParticipant,
    name: &str,
    type_name: &str,
    qos: &QosPolicies,
) -> Result<Topic, String> {
    participant
        .create_topic(name.to_owned(), type_name.to_owned(), qos, TopicKind::NoKey)
        .map_err(|error| format!("topic {name}: {error}"))
}

fn writer(
    participant: &DomainParticipant,
    publisher: &Publisher,
    name: &str,
    type_name: &str,
    qos: &QosPolicies,
) -> Result<DataWriter<Raw, RawAdapter>, String> {
    publisher
        .create_datawriter_no_key(
            &topic(participant, name, type_name, qos)?,
            Some(qos.clone()),
        )
        .map_err(|error| format!("writer of {name}: {error}"))
}

fn reader(
    participant: &DomainParticipant,
    subscriber: &Subscriber,
    name: &str,
    type_name: &str,
    qos: &QosPolicies,
) -> Result<DataReader<Raw, RawAdapter>, String> {
    subscriber
        .create_datareader_no_key(
            &topic(participant, name, type_name, qos)?,
            Some(qos.clone()),
        )
        .map_err(|error| format!("reader of {name}: {error}"))
}

impl Node {
    /// A node over a new core with `config`, its DDS participant joined to the domain.
    ///
    /// # Errors
    /// The core's refusal of the configuration, or what DDS could not create.
    pub fn new(config: Config, options: Options) -> Result<Self, String> {
        let engine = Engine::new(
            config,
            engine::Options {
                scene_quota: options.scene_quota,
                publish_every_ms: u64::try_from(options.publish_every.as_millis())
                    .unwrap_or(u64::MAX),
            },
        )
        .map_err(|error| error.to_string())?;
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
        let mut builder = DomainParticipantBuilder::new(options.domain);
        if !options.interfaces.is_empty() {
            builder = builder.with_only_networks(options.interfaces.iter().copied());
        }
        let participant = builder
            .build()
            .map_err(|error| format!("DDS domain {}: {error}", options.domain))?;
        let publisher = participant
            .create_publisher(&services_qos())
            .map_err(|error| format!("publisher: {error}"))?;
        let subscriber = participant
            .create_subscriber(&services_qos())
            .map_err(|error| format!("subscriber: {error}"))?;
        let factors = factors_qos();
        let velocity = writer(
            &participant,
            &publisher,
            &dds::topic(wire::VELOCITY_FACTORS),
            &dds::type_name(wire::VELOCITY_FACTORS_TYPE, ""),
            &factors,
        )?;
        let steering = writer(
            &participant,
            &publisher,
            &dds::topic(wire::STEERING_FACTORS),
            &dds::type_name(wire::STEERING_FACTORS_TYPE, ""),
            &factors,
        )?;
        let poll = Poll::new().map_err(|error| format!("poll: {error}"))?;
        let mut servers = Vec::new();
        for (index, endpoint) in Endpoint::ALL.into_iter().enumerate() {
            let mut requests = reader(
                &participant,
                &subscriber,
                &endpoint.request_topic(),
                &endpoint.request_type(),
                &services_qos(),
            )?;
            let mut replies = writer(
                &participant,
                &publisher,
                &endpoint.reply_topic(),
                &endpoint.reply_type(),
                &services_qos(),
            )?;
            poll.registry()
                .register(&mut requests, Token(2 * index), Interest::READABLE)
                .map_err(|error| format!("poll: {error}"))?;
            poll.registry()
                .register(
                    replies.as_status_source_mio1(),
                    Token(2 * index + 1),
                    Interest::READABLE,
                )
                .map_err(|error| format!("poll: {error}"))?;
            servers.push(Server {
                endpoint,
                requests,
                replies,
                matched: BTreeSet::new(),
            });
        }
        let graph = writer(
            &participant,
            &publisher,
            graph::TOPIC,
            graph::TYPE,
            &graph_qos(),
        )?;
        let gid = |guid: GUID| Gid {
            guid: guid.to_bytes(),
            len: options.distro.gid_len(),
        };
        let info = ParticipantEntitiesInfo {
            gid: gid(participant.guid()),
            node_entities_info_seq: vec![NodeEntitiesInfo {
                node_namespace: options.namespace.clone(),
                node_name: options.name.clone(),
                reader_gid_seq: servers.iter().map(|s| gid(s.requests.guid())).collect(),
                writer_gid_seq: [velocity.guid(), steering.guid()]
                    .into_iter()
                    .chain(servers.iter().map(|s| s.replies.guid()))
                    .map(gid)
                    .collect(),
            }],
        };
        let sample = cdr::to_vec(&info).map_err(|error| format!("{}: {error}", graph::TOPIC))?;
        graph
            .write(Raw(sample), None)
            .map_err(|error| format!("{}: {error}", graph::TOPIC))?;
        Ok(Self {
            shared,
            clock,
            sent: 0,
            options,
            poll,
            servers,
            velocity,
            steering,
            _graph: graph,
            pending: Vec::new(),
            _participant: participant,
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
            let until_publication =
                Duration::from_millis(self.shared.read(|engine| engine.until_publication_ms(now)));
            let timeout = if self.pending.is_empty() {
                STOP_POLL
            } else {
                REPLY_POLL
            }
            .min(until_publication);
            match self.poll.poll(&mut events, Some(timeout)) {
                Ok(()) => {}
                Err(error) if error.kind() == std::io::ErrorKind::Interrupted => {}
                Err(error) => return Err(format!("poll: {error}")),
            }
            self.step();
        }
        Ok(())
    }

    /// One turn: the matches, the requests, the replies due, the clock and the publications.
    fn step(&mut self) {
        let now = self.clock.now();
        self.shared.update(|engine| engine.handle_timeout(now));
        for server in &mut self.servers {
            while let Some(status) = server.replies.try_recv_status() {
                if let DataWriterStatus::PublicationMatched {
                    current, reader, ..
                } = status
                {
                    if current.count_change() > 0 {
                        server.matched.insert(reader);
                    } else if current.count_change() < 0 {
                        server.matched.remove(&reader);
                    }
                }
            }
        }
        for index in 0..self.servers.len() {
            self.serve(index);
        }
        self.flush();
        self.publish();
    }

    /// Answers every request waiting at server `index`.
    fn serve(&mut self, index: usize) {
        loop {
            let Some(server) = self.servers.get_mut(index) else {
                return;
            };
            let endpoint = server.endpoint;
            let sample = match server.requests.take_next_sample() {
                Ok(Some(sample)) => sample,
                Ok(None) => return,
                Err(error) => {
                    // Tried again on the next turn; nothing is answered from a failed read.
                    tracing::warn!(service = endpoint.name(), %error, "requests not read");
                    return;
                }
            };
            let client = participant(sample.sample_info().writer_guid());
            let Raw(bytes) = sample.into_value();
            let (header, incoming) = match endpoint.read(&bytes) {
                Ok(read) => read,
                Err(error) => {
                    tracing::warn!(service = endpoint.name(), %error, "a request refused unanswered");
                    continue;
                }
            };
            if let Request::Malformed(_, error) = &incoming {
                tracing::warn!(service = endpoint.name(), %error, "a malformed request refused");
            }
            let now = self.clock.now();
            let handled = self.shared.update(|engine| engine.handle(incoming, now));
            if !handled.reply.success() {
                tracing::debug!(service = endpoint.name(), "a request refused");
            }
            match dds::to_cdr(&handled.reply) {
                Ok(reply) => self.pending.push(Pending {
                    server: index,
                    client,
                    reply: Raw(header.frame(&reply)),
                    deadline: Instant::now() + REPLY_WAIT,
                }),
                Err(error) => {
                    tracing::error!(service = endpoint.name(), %error, "a reply not written");
                }
            }
        }
    }

    /// Writes every reply whose client's reader is matched or that waited long enough.
    fn flush(&mut self) {
        let now = Instant::now();
        let servers = &self.servers;
        self.pending.retain(|pending| {
            let Some(server) = servers.get(pending.server) else {
                return false;
            };
            let matched = server
                .matched
                .iter()
                .any(|&reader| participant(reader) == pending.client);
            if !matched && now < pending.deadline {
                return true;
            }
            if !matched {
                tracing::warn!(
                    service = server.endpoint.name(),
                    "the client's reply reader is not matched after {REPLY_WAIT:?}: the reply may \
                     be lost"
                );
            }
            if let Err(error) = server.replies.write(pending.reply.clone(), None) {
                tracing::error!(service = server.endpoint.name(), %error, "a reply not written");
            }
            false
        });
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
        let (velocity, steering) = (&publication.velocity, &publication.steering);
        for (writer, sample, name) in [
            (
                &self.velocity,
                cdr::to_vec(&velocity),
                wire::VELOCITY_FACTORS,
            ),
            (
                &self.steering,
                cdr::to_vec(&steering),
                wire::STEERING_FACTORS,
            ),
        ] {
            let written = sample
                .map_err(|error| error.to_string())
                .and_then(|sample| {
                    writer
                        .write(Raw(sample), None)
                        .map_err(|error| error.to_string())
                });
            if let Err(error) = written {
                tracing::error!(topic = name, %error, "a publication not written");
            }
        }
    }
}
