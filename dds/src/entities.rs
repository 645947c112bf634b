//! The DDS entities both nodes are made of ([`Node`](crate::Node), [`Stack`](crate::Stack)):
//! the participant, the QoS ROS 2 gives topics and services, the AD API's servers with their
//! replies waiting for the client's reader, the factor writers, and the graph's sample.

use std::collections::BTreeSet;
use std::net::IpAddr;
use std::time::{Duration, Instant};

use cooperation_adapters::cdr;
use cooperation_adapters::dds::{Endpoint, RequestHeader};
use cooperation_adapters::engine::{Publication, Request};
use cooperation_adapters::refusals::{self, Refusals};
use cooperation_adapters::wire;
use rustdds::mio1::{Events, Interest, Poll, Token};
use rustdds::no_key::{DataReader, DataWriter};
use rustdds::policy::{Durability, History, Reliability};
use rustdds::{
    DataWriterStatus, DomainParticipant, DomainParticipantBuilder, Publisher, QosPolicies,
    QosPolicyBuilder, RTPSEntity, StatusEvented, Subscriber, Topic, TopicKind, GUID,
};

use crate::graph::{self, Gid, NodeEntitiesInfo, ParticipantEntitiesInfo};
use crate::raw::{Raw, RawAdapter};

/// How long a reply waits for its client's reply reader to be matched, as `rmw_cyclonedds_cpp`
/// waits before it answers.
pub const REPLY_WAIT: Duration = Duration::from_millis(100);

/// How often the poll wakes while replies wait for their readers.
const REPLY_POLL: Duration = Duration::from_millis(2);

/// The longest the poll sleeps, whatever the publication interval: how soon a stop is seen.
const STOP_POLL: Duration = Duration::from_millis(100);

/// The log of what the node's peers send that it refuses, by service, topic or interface,
/// summed up every [`refusals::PERIOD`].
pub(crate) fn refusal_log() -> Refusals {
    Refusals::new("source", "sources", refusals::PERIOD)
}

/// A peer's message, request or status that `source` (a service, topic or interface) refused,
/// logged whole if it is the first of the period of `refusals`, else counted for its summary
/// (`docs/ros2.md`, *Errors and limits*).
pub(crate) fn refused(
    refusals: &Refusals,
    source: &str,
    what: &str,
    error: &dyn core::fmt::Display,
) {
    refused_line(refusals, source, &format!("{what}: {error}"));
}

/// As [`refused`], said by a whole line.
pub(crate) fn refused_line(refusals: &Refusals, source: &str, line: &str) {
    if refusals.refused(source, &format!("{line} ({source})")) {
        tracing::warn!(source, "{line}");
    }
}

/// Sums up the refusals of a period that has passed at `reading_ns`, if any were counted.
pub(crate) fn sum_up(refusals: &Refusals, reading_ns: i64) {
    if let Some(summary) = refusals.poll(reading_ns) {
        tracing::warn!("{summary}");
    }
}

/// The participant a DDS entity belongs to: its GUID's prefix.
pub(crate) fn participant_of(guid: GUID) -> [u8; 12] {
    guid.to_bytes().first_chunk().copied().unwrap_or_default()
}

/// Reliable, with `durability`, the newest `depth` samples kept.
pub(crate) fn qos(durability: Durability, depth: i32) -> QosPolicies {
    QosPolicyBuilder::new()
        .reliability(Reliability::Reliable {
            max_blocking_time: rustdds::Duration::from_millis(100),
        })
        .durability(durability)
        .history(History::KeepLast { depth })
        .build()
}

/// ROS 2's default QoS for services: reliable, volatile, ten kept.
pub(crate) fn services_qos() -> QosPolicies {
    qos(Durability::Volatile, 10)
}

/// A participant, with the publisher and subscriber of every entity of the node.
pub(crate) struct Participant {
    pub(crate) participant: DomainParticipant,
    pub(crate) publisher: Publisher,
    pub(crate) subscriber: Subscriber,
}

impl Participant {
    /// Joins `domain`, on `interfaces` only unless empty.
    pub(crate) fn join(domain: u16, interfaces: &[IpAddr]) -> Result<Self, String> {
        let mut builder = DomainParticipantBuilder::new(domain);
        if !interfaces.is_empty() {
            builder = builder.with_only_networks(interfaces.iter().copied());
        }
        let participant = builder
            .build()
            .map_err(|error| format!("DDS domain {domain}: {error}"))?;
        let publisher = participant
            .create_publisher(&services_qos())
            .map_err(|error| format!("publisher: {error}"))?;
        let subscriber = participant
            .create_subscriber(&services_qos())
            .map_err(|error| format!("subscriber: {error}"))?;
        Ok(Self {
            participant,
            publisher,
            subscriber,
        })
    }

    fn topic(&self, name: &str, type_name: &str, qos: &QosPolicies) -> Result<Topic, String> {
        self.participant
            .create_topic(name.to_owned(), type_name.to_owned(), qos, TopicKind::NoKey)
            .map_err(|error| format!("topic {name}: {error}"))
    }

    /// A writer of the DDS topic `name`.
    pub(crate) fn writer(
        &self,
        name: &str,
        type_name: &str,
        qos: &QosPolicies,
    ) -> Result<DataWriter<Raw, RawAdapter>, String> {
        self.publisher
            .create_datawriter_no_key(&self.topic(name, type_name, qos)?, Some(qos.clone()))
            .map_err(|error| format!("writer of {name}: {error}"))
    }

    /// A reader of the DDS topic `name`.
    pub(crate) fn reader(
        &self,
        name: &str,
        type_name: &str,
        qos: &QosPolicies,
    ) -> Result<DataReader<Raw, RawAdapter>, String> {
        self.subscriber
            .create_datareader_no_key(&self.topic(name, type_name, qos)?, Some(qos.clone()))
            .map_err(|error| format!("reader of {name}: {error}"))
    }

    /// Writes the node's entry of `ros_discovery_info` (what `ros2 node list` and `ros2 node
    /// info` read): its servers' and factor writers' entities, and `readers` and `writers`
    /// besides. The writer returned must live as long as the node (the sample is
    /// transient-local).
    pub(crate) fn announce(
        &self,
        options: &crate::Options,
        servers: &[Server],
        factors: &Factors,
        mut readers: Vec<GUID>,
        mut writers: Vec<GUID>,
    ) -> Result<DataWriter<Raw, RawAdapter>, String> {
        readers.extend(servers.iter().map(|s| s.requests.guid()));
        writers.extend(factors.guids());
        writers.extend(servers.iter().map(|s| s.replies.guid()));
        let (distro, namespace, name) = (options.distro, &options.namespace, &options.name);
        let graph = self.writer(
            graph::TOPIC,
            graph::TYPE,
            &qos(Durability::TransientLocal, 1),
        )?;
        let gid = |guid: &GUID| Gid {
            guid: guid.to_bytes(),
            len: distro.gid_len(),
        };
        let info = ParticipantEntitiesInfo {
            gid: gid(&self.participant.guid()),
            node_entities_info_seq: vec![NodeEntitiesInfo {
                node_namespace: namespace.to_owned(),
                node_name: name.to_owned(),
                reader_gid_seq: readers.iter().map(gid).collect(),
                writer_gid_seq: writers.iter().map(gid).collect(),
            }],
        };
        let sample = cdr::to_vec(&info).map_err(|error| format!("{}: {error}", graph::TOPIC))?;
        graph
            .write(Raw(sample), None)
            .map_err(|error| format!("{}: {error}", graph::TOPIC))?;
        Ok(graph)
    }
}

/// One service the node serves: where its requests arrive, where its replies leave, and which
/// reply readers are matched.
pub(crate) struct Server {
    pub(crate) endpoint: Endpoint,
    pub(crate) requests: DataReader<Raw, RawAdapter>,
    pub(crate) replies: DataWriter<Raw, RawAdapter>,
    matched: BTreeSet<GUID>,
}

impl Server {
    /// The server of `endpoint`, its requests and reply matches polled with tokens `2 * index`
    /// and `2 * index + 1`.
    pub(crate) fn open(
        participant: &Participant,
        poll: &Poll,
        endpoint: Endpoint,
        index: usize,
    ) -> Result<Self, String> {
        let mut requests = participant.reader(
            &endpoint.request_topic(),
            &endpoint.request_type(),
            &services_qos(),
        )?;
        let mut replies = participant.writer(
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
        Ok(Self {
            endpoint,
            requests,
            replies,
            matched: BTreeSet::new(),
        })
    }

    /// Notes the reply readers matched and unmatched since the last call.
    pub(crate) fn track_matches(&mut self) {
        while let Some(status) = self.replies.try_recv_status() {
            if let DataWriterStatus::PublicationMatched {
                current, reader, ..
            } = status
            {
                if current.count_change() > 0 {
                    self.matched.insert(reader);
                } else if current.count_change() < 0 {
                    self.matched.remove(&reader);
                }
            }
        }
    }

    /// The next request that can be answered: the participant of the client that sent it, its
    /// header, and what it asks ([`Request::Malformed`] for one that does not read, logged).
    /// `None` when none waits; a request too short for its headers is logged and dropped, and a
    /// failed read is logged and tried again on the next turn. A peer's refused request is
    /// logged through `refusals`.
    pub(crate) fn next_request(
        &mut self,
        refusals: &Refusals,
    ) -> Option<([u8; 12], RequestHeader, Request)> {
        let name = self.endpoint.name();
        loop {
            let sample = match self.requests.take_next_sample() {
                Ok(Some(sample)) => sample,
                Ok(None) => return None,
                Err(error) => {
                    tracing::warn!(service = name, %error, "requests not read");
                    return None;
                }
            };
            let client = participant_of(sample.sample_info().writer_guid());
            let Raw(bytes) = sample.into_value();
            match self.endpoint.read(&bytes) {
                Ok((header, request)) => {
                    if let Request::Malformed(_, error) = &request {
                        refused(refusals, name, "a malformed request refused", error);
                    }
                    return Some((client, header, request));
                }
                Err(error) => refused(refusals, name, "a request left unanswered", &error),
            }
        }
    }
}

/// Waits for `poll`'s events: at most until the engine asks to be called (`until_timeout`), and
/// no longer than [`REPLY_POLL`] while something is on its way (`busy`), else [`STOP_POLL`].
pub(crate) fn wait(
    poll: &mut Poll,
    events: &mut Events,
    busy: bool,
    until_timeout: Duration,
) -> Result<(), String> {
    let timeout = if busy { REPLY_POLL } else { STOP_POLL }.min(until_timeout);
    match poll.poll(events, Some(timeout)) {
        Ok(()) => Ok(()),
        Err(error) if error.kind() == std::io::ErrorKind::Interrupted => Ok(()),
        Err(error) => Err(format!("poll: {error}")),
    }
}

/// A reply waiting for its client's reader.
struct Waiting {
    server: usize,
    client: [u8; 12],
    reply: Raw,
    deadline: Instant,
}

/// The replies written once their client's reply reader is matched, or after [`REPLY_WAIT`] at
/// most: a reliable, volatile writer does not send a sample to a reader it matches later, so a
/// reply written before the match would be lost.
#[derive(Default)]
pub(crate) struct Replies {
    waiting: Vec<Waiting>,
}

impl Replies {
    /// Whether a reply waits.
    pub(crate) fn is_empty(&self) -> bool {
        self.waiting.is_empty()
    }

    pub(crate) fn len(&self) -> usize {
        self.waiting.len()
    }

    /// `reply`, framed with the request's `header`, for `client` of server `server`.
    pub(crate) fn push(
        &mut self,
        server: &Server,
        index: usize,
        client: [u8; 12],
        header: RequestHeader,
        reply: &cooperation_adapters::engine::Reply,
    ) {
        match cooperation_adapters::dds::to_cdr(reply) {
            Ok(bytes) => self.waiting.push(Waiting {
                server: index,
                client,
                reply: Raw(header.frame(&bytes)),
                deadline: Instant::now() + REPLY_WAIT,
            }),
            Err(error) => {
                tracing::error!(service = server.endpoint.name(), %error, "a reply not written");
            }
        }
    }

    /// Writes every reply whose client's reader is matched or that waited long enough; then,
    /// if it wrote any, yields the thread. A written sample is sent by the participant's own
    /// thread: yielding lets it send the replies before the caller builds and writes a
    /// publication, whose fragments it could otherwise send first when it found both waiting
    /// (docs/performance-history.md, *The DDS node on the engine*).
    pub(crate) fn flush(&mut self, servers: &[Server]) {
        let now = Instant::now();
        let waiting = self.waiting.len();
        self.waiting.retain(|waiting| {
            let Some(server) = servers.get(waiting.server) else {
                return false;
            };
            let matched = server
                .matched
                .iter()
                .any(|&reader| participant_of(reader) == waiting.client);
            if !matched && now < waiting.deadline {
                return true;
            }
            if !matched {
                tracing::warn!(
                    service = server.endpoint.name(),
                    "the client's reply reader is not matched after {REPLY_WAIT:?}: the reply may \
                     be lost"
                );
            }
            if let Err(error) = server.replies.write(waiting.reply.clone(), None) {
                tracing::error!(service = server.endpoint.name(), %error, "a reply not written");
            }
            false
        });
        if self.waiting.len() < waiting {
            std::thread::yield_now();
        }
    }
}

/// The writers of the AD API's factor topics: reliable, volatile, the newest one kept.
pub(crate) struct Factors {
    pub(crate) velocity: DataWriter<Raw, RawAdapter>,
    pub(crate) steering: DataWriter<Raw, RawAdapter>,
}

impl Factors {
    pub(crate) fn open(participant: &Participant) -> Result<Self, String> {
        let factors = qos(Durability::Volatile, 1);
        let type_name = |name| cooperation_adapters::dds::type_name(name, "");
        Ok(Self {
            velocity: participant.writer(
                &cooperation_adapters::dds::topic(wire::VELOCITY_FACTORS),
                &type_name(wire::VELOCITY_FACTORS_TYPE),
                &factors,
            )?,
            steering: participant.writer(
                &cooperation_adapters::dds::topic(wire::STEERING_FACTORS),
                &type_name(wire::STEERING_FACTORS_TYPE),
                &factors,
            )?,
        })
    }

    /// Writes both arrays of `publication`.
    pub(crate) fn publish(&self, publication: &Publication) {
        self.write(&publication.velocity, &publication.steering);
    }

    /// Writes both arrays.
    pub(crate) fn write(
        &self,
        velocity: &wire::VelocityFactorArray,
        steering: &wire::SteeringFactorArray,
    ) {
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

    /// Their GUIDs, for the graph.
    pub(crate) fn guids(&self) -> [GUID; 2] {
        [self.velocity.guid(), self.steering.guid()]
    }
}
