//! The ROS 2 node's benchmark: service round trips and publications over DDS on loopback, with
//! 500 live scenes, against the same work done in process, measured in the same run.
//!
//! `cargo bench -p cooperation-dds --bench dds` prints markdown tables (`docs/performance.md`):
//!
//! - **Round trips.** A client participant in the same process (rustdds, Cyclone's request
//!   header) calls `get_policies` (which changes nothing, so publishes nothing: the transport's
//!   floor) and `set_commands` (one command, activate and deactivate alternating over the scenes,
//!   so every call changes the core and causes a publication of both topics), each waiting for
//!   its reply before the next. Timed from just before the request is written to just after its
//!   reply is taken; every latency is kept.
//! - **Command to publication.** For each `set_commands`, the time until the client's reader of
//!   `velocity_factors` has a sample published after the command's reply; the next command
//!   waits, untimed, for the publication's `steering_factors` sample too.
//! - **In process.** The same requests read, answered and framed without DDS
//!   (`Endpoint::read`, `Engine::handle`, `dds::to_cdr`), on an engine with the same scenes; and a
//!   publication's two messages built and written in CDR, against their JSON for rosbridge.
//!
//! The node's periodic publication is set to an hour. Nothing leaves the host; run it in a
//! network namespace (`unshare -n`, as `tools/ros2-interop` does) to keep DDS off the network.

use std::hint::black_box;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use cooperation_adapters::dds::{self, Endpoint, RequestHeader};
use cooperation_adapters::engine::{self, Engine, Now, Reply, Request};
use cooperation_adapters::rtc::{self, CooperateStatus};
use cooperation_adapters::sync::{SyncRequest, SyncStatus};
use cooperation_adapters::wire::{self, *};
use cooperation_adapters::{cdr, Time};
use cooperation_dds::raw::{Raw, RawAdapter};
use cooperation_dds::{Node, Options};
use rustdds::mio1::{Events, Interest, Poll, Token};
use rustdds::no_key::{DataReader, DataWriter};
use rustdds::policy::{Durability, History, Reliability};
use rustdds::{
    DataWriterStatus, DomainParticipant, DomainParticipantBuilder, QosPolicies, QosPolicyBuilder,
    StatusEvented, TopicKind,
};

const SCENES: usize = 500;
const INTERFACES: [&str; 4] = [
    "lane_change_left",
    "lane_change_right",
    "crosswalk",
    "intersection",
];
const ROUND_TRIPS: usize = 2_000;
const DOMAIN: u16 = 97;
const DEADLINE: Duration = Duration::from_secs(5);

fn qos(depth: i32) -> QosPolicies {
    QosPolicyBuilder::new()
        .reliability(Reliability::Reliable {
            max_blocking_time: rustdds::Duration::from_millis(100),
        })
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth })
        .build()
}

fn scene(index: usize) -> rtc::Uuid {
    let mixed = (index as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    let mut uuid = [0; 16];
    uuid[..8].copy_from_slice(&mixed.to_le_bytes());
    uuid[8..].copy_from_slice(&(index as u64).to_le_bytes());
    rtc::Uuid { uuid }
}

/// Registers the scenes, 125 on each interface, through the sync service.
fn register(engine: &mut Engine) {
    for (which, interface) in INTERFACES.into_iter().enumerate() {
        let statuses = (0..SCENES / INTERFACES.len())
            .map(|i| {
                let index = which * SCENES / INTERFACES.len() + i;
                SyncStatus::from(&CooperateStatus {
                    uuid: scene(index),
                    safe: !index.is_multiple_of(3),
                    state: rtc::Lifecycle::new(if index.is_multiple_of(2) {
                        rtc::Lifecycle::RUNNING
                    } else {
                        rtc::Lifecycle::WAITING_FOR_EXECUTION
                    }),
                    start_distance: ((index * 37) % 500) as f32,
                    finish_distance: ((index * 37) % 500 + 20) as f32,
                    ..CooperateStatus::default()
                })
            })
            .collect();
        let request = SyncRequest {
            interface: interface.to_owned(),
            statuses,
            sequences: Vec::new(),
            removed: Vec::new(),
        };
        let handled = engine.handle(Request::Sync(request), Now::default());
        let Reply::Sync(response) = handled.reply else {
            panic!("a sync's reply is a sync response")
        };
        assert!(response.success, "{}", response.message);
    }
    assert_eq!(engine.state().scenes().count(), SCENES);
}

fn command(iteration: usize) -> SetCooperationCommandsRequest {
    let decision = if (iteration / SCENES).is_multiple_of(2) {
        CooperationDecision::ACTIVATE
    } else {
        CooperationDecision::DEACTIVATE
    };
    SetCooperationCommandsRequest {
        commands: vec![CooperationCommand {
            uuid: Uuid {
                uuid: scene(iteration % SCENES).uuid,
            },
            cooperator: CooperationDecision { decision },
        }],
    }
}

struct Client {
    requests: DataWriter<Raw, RawAdapter>,
    replies: DataReader<Raw, RawAdapter>,
    poll: Poll,
    seq: i64,
}

impl Client {
    fn new(participant: &DomainParticipant, endpoint: Endpoint) -> Self {
        let publisher = participant.create_publisher(&qos(10)).expect("publisher");
        let subscriber = participant.create_subscriber(&qos(10)).expect("subscriber");
        let topic = |name: String, type_name: String| {
            participant
                .create_topic(name, type_name, &qos(10), TopicKind::NoKey)
                .expect("topic")
        };
        let requests = publisher
            .create_datawriter_no_key::<Raw, RawAdapter>(
                &topic(endpoint.request_topic(), endpoint.request_type()),
                None,
            )
            .expect("writer");
        let mut replies = subscriber
            .create_datareader_no_key::<Raw, RawAdapter>(
                &topic(endpoint.reply_topic(), endpoint.reply_type()),
                None,
            )
            .expect("reader");
        let poll = Poll::new().expect("poll");
        poll.registry()
            .register(&mut replies, Token(0), Interest::READABLE)
            .expect("register");
        let started = Instant::now();
        let mut matched = false;
        while !matched {
            assert!(started.elapsed() < DEADLINE, "the node was not discovered");
            while let Some(status) = requests.try_recv_status() {
                matched |= matches!(status, DataWriterStatus::PublicationMatched { .. });
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        Self {
            requests,
            replies,
            poll,
            seq: 0,
        }
    }

    /// One call: the reply's message, with its encapsulation header.
    fn call(&mut self, message: &[u8]) -> Vec<u8> {
        self.seq += 1;
        let header = RequestHeader {
            guid: 42,
            seq: self.seq,
        };
        self.requests
            .write(Raw(header.frame(message)), None)
            .expect("written");
        let started = Instant::now();
        let mut events = Events::with_capacity(4);
        loop {
            while let Some(sample) = self.replies.take_next_sample().expect("read") {
                let Raw(bytes) = sample.into_value();
                let (reply, body) = RequestHeader::split(&bytes).expect("a reply");
                if reply == header {
                    return body;
                }
            }
            assert!(started.elapsed() < DEADLINE, "a reply was lost");
            self.poll
                .poll(&mut events, Some(Duration::from_millis(50)))
                .expect("poll");
        }
    }
}

fn percentile(sorted: &[Duration], p: f64) -> Duration {
    let rank = ((sorted.len() as f64 - 1.0) * p).round() as usize;
    sorted[rank.min(sorted.len() - 1)]
}

fn show(d: Duration) -> String {
    let ns = d.as_nanos() as f64;
    if ns >= 1e6 {
        format!("{:.2} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.0} µs", ns / 1e3)
    } else {
        format!("{ns:.0} ns")
    }
}

struct Row {
    name: &'static str,
    times: Vec<Duration>,
}

impl Row {
    fn p50(&self) -> Duration {
        percentile(&self.sorted(), 0.5)
    }
    fn sorted(&self) -> Vec<Duration> {
        let mut sorted = self.times.clone();
        sorted.sort();
        sorted
    }
}

fn main() {
    let config = cooperation_adapters::settings::load(None)
        .expect("settings")
        .config;
    let options = Options {
        domain: DOMAIN,
        publish_every: Duration::from_secs(3600),
        ..Options::default()
    };
    let mut node = Node::new(None, options).expect("the node");
    node.shared().update(register);
    let stop = Arc::new(AtomicBool::new(false));
    let running = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || node.run(&stop))
    };

    let participant = DomainParticipantBuilder::new(DOMAIN)
        .build()
        .expect("participant");
    let mut policies = Client::new(&participant, Endpoint::Ad(Service::GetPolicies));
    let mut commands = Client::new(&participant, Endpoint::Ad(Service::SetCommands));
    let subscriber = participant.create_subscriber(&qos(1)).expect("subscriber");
    let factors_topic = participant
        .create_topic(
            dds::topic(VELOCITY_FACTORS),
            dds::type_name(VELOCITY_FACTORS_TYPE, ""),
            &qos(1),
            TopicKind::NoKey,
        )
        .expect("topic");
    let mut factors = subscriber
        .create_datareader_no_key::<Raw, RawAdapter>(&factors_topic, None)
        .expect("reader");
    let mut factors_poll = Poll::new().expect("poll");
    factors_poll
        .registry()
        .register(&mut factors, Token(0), Interest::READABLE)
        .expect("register");
    // The steering factors, the publication's second sample: each command waits for it before
    // the next, so that no timed call meets the node still writing the last publication.
    let steering_topic = participant
        .create_topic(
            dds::topic(STEERING_FACTORS),
            dds::type_name(STEERING_FACTORS_TYPE, ""),
            &qos(1),
            TopicKind::NoKey,
        )
        .expect("topic");
    let mut steering = subscriber
        .create_datareader_no_key::<Raw, RawAdapter>(&steering_topic, None)
        .expect("reader");
    factors_poll
        .registry()
        .register(&mut steering, Token(1), Interest::READABLE)
        .expect("register");

    let get = cdr::to_vec(&GetCooperationPoliciesRequest {}).expect("encodes");
    let set: Vec<Vec<u8>> = (0..ROUND_TRIPS + 20)
        .map(|i| cdr::to_vec(&command(i)).expect("encodes"))
        .collect();
    // Untimed: the first calls wait for the node to match the client's reply readers.
    for message in set.iter().take(20) {
        let reply: SetCooperationCommandsResponse =
            cdr::from_slice(&commands.call(message)).expect("a reply");
        assert!(reply.status.success);
        policies.call(&get);
    }
    let mut floor = Row {
        name: "`get_policies` (transport floor: publishes nothing)",
        times: Vec::new(),
    };
    for _ in 0..ROUND_TRIPS {
        let started = Instant::now();
        black_box(policies.call(&get));
        floor.times.push(started.elapsed());
    }
    let mut round_trips = Row {
        name: "`set_commands`, one command (each publishes both topics)",
        times: Vec::new(),
    };
    let mut published = Row {
        name: "`set_commands` to the publication that shows it, at a subscriber",
        times: Vec::new(),
    };
    let mut events = Events::with_capacity(4);
    for message in set.iter().skip(20) {
        while factors.take_next_sample().expect("read").is_some() {}
        while steering.take_next_sample().expect("read").is_some() {}
        let started = Instant::now();
        let reply: SetCooperationCommandsResponse =
            cdr::from_slice(&commands.call(message)).expect("a reply");
        round_trips.times.push(started.elapsed());
        assert!(reply.status.success, "{reply:?}");
        loop {
            if factors.take_next_sample().expect("read").is_some() {
                published.times.push(started.elapsed());
                break;
            }
            assert!(started.elapsed() < DEADLINE, "a publication was lost");
            factors_poll
                .poll(&mut events, Some(Duration::from_millis(50)))
                .expect("poll");
        }
        while steering.take_next_sample().expect("read").is_none() {
            assert!(started.elapsed() < DEADLINE, "a publication was lost");
            factors_poll
                .poll(&mut events, Some(Duration::from_millis(50)))
                .expect("poll");
        }
    }
    stop.store(true, Ordering::Relaxed);
    running
        .join()
        .expect("the node's thread")
        .expect("the node ran");

    // In process: the same work without DDS.
    let mut host = Engine::new(config, engine::Options::default()).expect("config");
    register(&mut host);
    let header = RequestHeader { guid: 1, seq: 1 };
    let framed_get = header.frame(&get);
    let framed_set: Vec<Vec<u8>> = set.iter().map(|m| header.frame(m)).collect();
    let mut answer_get = Row {
        name: "in process: `get_policies` read, answered, framed",
        times: Vec::new(),
    };
    let mut answer_set = Row {
        name: "in process: `set_commands` read, answered, framed",
        times: Vec::new(),
    };
    let mut publish_cdr = Row {
        name: "in process: both factor messages built (under the lock) and written in CDR",
        times: Vec::new(),
    };
    let mut publish_json = Row {
        name: "for comparison: the same two messages written in JSON (rosbridge)",
        times: Vec::new(),
    };
    for framed in framed_set.iter().take(ROUND_TRIPS) {
        let started = Instant::now();
        let (h, incoming) = Endpoint::Ad(Service::GetPolicies)
            .read(&framed_get)
            .expect("read");
        let reply = host.handle(incoming, Now::default());
        black_box(h.frame(&dds::to_cdr(&reply.reply).expect("encodes")));
        answer_get.times.push(started.elapsed());

        let started = Instant::now();
        let (h, incoming) = Endpoint::Ad(Service::SetCommands)
            .read(framed)
            .expect("read");
        let reply = host.handle(incoming, Now::default());
        black_box(h.frame(&dds::to_cdr(&reply.reply).expect("encodes")));
        answer_set.times.push(started.elapsed());

        let started = Instant::now();
        let velocity = wire::velocity_factors(host.state(), Time::default());
        let steering = wire::steering_factors(host.state(), Time::default());
        black_box(cdr::to_vec(&velocity).expect("encodes"));
        black_box(cdr::to_vec(&steering).expect("encodes"));
        publish_cdr.times.push(started.elapsed());

        let started = Instant::now();
        black_box(wire::to_json(&velocity));
        black_box(wire::to_json(&steering));
        publish_json.times.push(started.elapsed());
    }
    let velocity = cdr::to_vec(&wire::velocity_factors(host.state(), Time::default()))
        .expect("encodes")
        .len();
    let steering = cdr::to_vec(&wire::steering_factors(host.state(), Time::default()))
        .expect("encodes")
        .len();

    println!(
        "{SCENES} live scenes; the CDR samples are {velocity} bytes (velocity) and {steering} \
         bytes (steering).\n"
    );
    println!("| over DDS on loopback, {ROUND_TRIPS} each | p50 | p99 | max | in process p50 | in process / over DDS |");
    println!("|---|---:|---:|---:|---:|---:|");
    for (row, local) in [
        (&floor, &answer_get),
        (&round_trips, &answer_set),
        (&published, &publish_cdr),
    ] {
        let sorted = row.sorted();
        println!(
            "| {} | {} | {} | {} | {} | {:.2} % |",
            row.name,
            show(percentile(&sorted, 0.5)),
            show(percentile(&sorted, 0.99)),
            show(*sorted.last().expect("timed")),
            show(local.p50()),
            100.0 * local.p50().as_secs_f64() / row.p50().as_secs_f64(),
        );
    }
    println!("\n| in process, {ROUND_TRIPS} each | p50 | p99 |");
    println!("|---|---:|---:|");
    for row in [&answer_get, &answer_set, &publish_cdr, &publish_json] {
        let sorted = row.sorted();
        println!(
            "| {} | {} | {} |",
            row.name,
            show(percentile(&sorted, 0.5)),
            show(percentile(&sorted, 0.99)),
        );
    }
    println!(
        "\nJSON / CDR for a publication's two messages: {:.2}",
        publish_json.p50().as_secs_f64() / publish_cdr.p50().as_secs_f64()
    );
}
