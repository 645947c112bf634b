//! The server's benchmark: command round trips and publications over rosbridge on loopback,
//! with 500 live scenes, against the core's own share of each, measured in the same run.
//!
//! `cargo bench -p cooperation-server --bench roundtrip` prints markdown tables:
//!
//! - **Round trips.** 1, 10 and 100 operator clients, each on its own WebSocket, send
//!   `set_commands` (one command, alternating activate and deactivate) and wait for each
//!   `service_response` before sending the next. Every latency is recorded, from just before
//!   the frame is written to just after its response is read. A `get_policies` round trip
//!   (which changes nothing, so publishes nothing) is the transport's floor; one more client
//!   times `get_policies` while the 100 command clients run.
//! - **In process.** The same command through `Node::call` (JSON, core, response, and the
//!   publication a change causes), through the JSON service alone, and through the core alone
//!   (`Shared::set_commands`); `Node::publish` against its parts: the core's factor queries,
//!   the conversion to the AD API messages, and their serialization. These are interleaved in
//!   rounds, so load from elsewhere falls on all of them alike.
//! - **Delivery.** The time from calling `Node::publish` to each of 1 and 100 subscribers
//!   having received both topics' frames.
//! - **Fairness.** `get_policies` round trips from one client while another sends syncs of
//!   1,024 statuses back to back, against the same on the otherwise idle node, as ratios.
//!
//! The node's periodic publication and its clock are set to an hour, so the only publications
//! are those the commands cause and those the benchmark makes, and no scene expires.
//! Everything is bounded by counts and by a deadline per case; nothing leaves 127.0.0.1.

use std::fmt::Write as _;
use std::hint::black_box;
use std::net::SocketAddr;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use cooperation::{Command, FactorLists, Input, OperatorDecision, SceneId};
use cooperation_adapters::engine::{Endpoint, Request};
use cooperation_adapters::wire::{self, Service};
use cooperation_server::{Node, Options, Topic};
use futures_util::{SinkExt, StreamExt};
use serde::Serialize;
use tokio::sync::{mpsc, Barrier};
use tokio_tungstenite::tungstenite::Message;

mod delivery;
mod fairness;
mod in_process;
mod summary;

use delivery::delivery;
use fairness::{fairness, HEAVY_ENTRIES};
use in_process::{
    in_process, CALL, CONVERT, CORE_COMMAND, JSON_SERVICE, PUBLISH, QUERY, QUERY_KEYED, SERIALIZE,
};
use summary::{share, show, Summary};

/// Live scenes while everything is measured.
const SCENES: usize = 500;
/// The RTC interfaces the scenes are spread over: two steering, two velocity.
const INTERFACES: [&str; 4] = [
    "lane_change_left",
    "lane_change_right",
    "crosswalk",
    "intersection",
];
/// The numbers of concurrent operator clients.
const CLIENTS: [usize; 3] = [1, 10, 100];
/// With this many `set_commands` clients, one more client times `get_policies` beside them.
const BESIDE: usize = 100;
/// Round trips timed per client count, shared evenly between the clients.
const ROUND_TRIPS: usize = 10_000;
/// Round trips per client before timing starts.
const WARM_UP: usize = 5;
/// A case stops here even if its round trips are not done.
const CASE_DEADLINE: Duration = Duration::from_secs(40);
/// Rounds of the in-process measurements, and iterations of each measurement per round.
const ROUNDS: usize = 10;
const PER_ROUND: usize = 200;
/// The numbers of subscribers, and the publications timed for each.
const SUBSCRIBERS: [(usize, usize); 2] = [(1, 200), (100, 20)];

const SET_COMMANDS: &str = "/api/planning/cooperation/set_commands";
const GET_POLICIES: &str = "/api/planning/cooperation/get_policies";
/// AD API decision constants.
const DEACTIVATE: u8 = 1;
const ACTIVATE: u8 = 2;

/// A scene identifier that looks random: splitmix64 of the index, twice.
fn uuid(index: usize) -> [u8; 16] {
    fn mix(mut z: u64) -> u64 {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    let seed = index as u64;
    let high = u128::from(mix(seed.wrapping_mul(2)));
    let low = u128::from(mix(seed.wrapping_mul(2) + 1));
    ((high << 64) | low).to_be_bytes()
}

fn uuid_json(bytes: &[u8; 16]) -> String {
    let numbers: Vec<String> = bytes.iter().map(u8::to_string).collect();
    format!("{{\"uuid\":[{}]}}", numbers.join(","))
}

/// The `/cooperation/rtc/sync` arguments that register (or refresh) `indices` on `interface`.
fn sync_args(interface: &str, indices: impl Iterator<Item = usize>) -> String {
    let statuses: Vec<String> = indices
        .map(|index| {
            // Distances spread out and unordered, so the factor lists are really sorted.
            let start = 5.0 + ((index * 7_919) % 1_000) as f32 * 0.25;
            format!(
                "{{\"stamp\":{{\"sec\":0,\"nanosec\":0}},\"uuid\":{},\"module\":{{\"type\":0}},\
                 \"safe\":{},\"command_status\":{{\"type\":0}},\"state\":{{\"type\":{}}},\
                 \"auto_mode\":false,\"start_distance\":{start},\"finish_distance\":{}}}",
                uuid_json(&uuid(index)),
                index % 3 != 0,
                index % 2,
                start + 40.0,
            )
        })
        .collect();
    format!(
        "{{\"interface\":\"{interface}\",\"statuses\":[{}]}}",
        statuses.join(",")
    )
}

/// `set_commands` arguments: one command for scene `index`.
fn command_args(index: usize, decision: u8) -> String {
    format!(
        "{{\"commands\":[{{\"uuid\":{},\"cooperator\":{{\"decision\":{decision}}}}}]}}",
        uuid_json(&uuid(index % SCENES))
    )
}

/// The decision of a scene's `pass`-th command: they alternate, so that every command changes
/// the core and is published before it is answered (a command that changes nothing is answered
/// at once, which would measure the transport instead).
fn decision(pass: usize) -> u8 {
    if pass.is_multiple_of(2) {
        ACTIVATE
    } else {
        DEACTIVATE
    }
}

/// The load averages, from `/proc/loadavg` (Linux); empty elsewhere.
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|text| {
            text.split_whitespace()
                .take(3)
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_default()
}

/// What an operator client asks.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Ask {
    SetCommands,
    GetPolicies,
}

/// The frame of `client`'s `iteration`-th call, one of `clients`. A command's number
/// `iteration × clients + client` is unique in the case: it names the scene (modulo the scenes)
/// and, by its pass over them, the decision.
fn frame(ask: Ask, client: usize, clients: usize, iteration: usize) -> String {
    let command = iteration * clients + client;
    match ask {
        Ask::SetCommands => format!(
            "{{\"op\":\"call_service\",\"id\":\"c{client}-{iteration}\",\"service\":\"{SET_COMMANDS}\",\
             \"args\":{}}}",
            command_args(command, decision(command / SCENES))
        ),
        Ask::GetPolicies => format!(
            "{{\"op\":\"call_service\",\"id\":\"c{client}-{iteration}\",\"service\":\"{GET_POLICIES}\",\
             \"args\":{{}}}}"
        ),
    }
}

/// When a client stops timing: after its count, at the deadline, or when told to.
#[derive(Clone)]
struct Until {
    deadline: Instant,
    stop: Arc<AtomicBool>,
}

impl Until {
    fn new() -> Self {
        Self {
            deadline: Instant::now() + CASE_DEADLINE,
            stop: Arc::new(AtomicBool::new(false)),
        }
    }

    fn reached(&self) -> bool {
        Instant::now() > self.deadline || self.stop.load(Ordering::Relaxed)
    }
}

/// One operator client: connects, warms up, waits for the others, then times `count` round
/// trips (fewer if `until` is reached first). Fails on a response that is not the call's
/// success.
async fn operator(
    address: SocketAddr,
    ask: Ask,
    (client, clients): (usize, usize),
    count: usize,
    start: Arc<Barrier>,
    until: Until,
) -> Result<Vec<Duration>, String> {
    let url = format!("ws://{address}/");
    let (mut socket, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .map_err(|error| format!("client {client}: {error}"))?;
    let mut latencies = Vec::with_capacity(count);
    for iteration in 0..WARM_UP + count {
        if iteration == WARM_UP {
            start.wait().await;
        }
        if iteration > WARM_UP && until.reached() {
            break;
        }
        let text = frame(ask, client, clients, iteration);
        let id = format!("\"id\":\"c{client}-{iteration}\"");
        let sent = Instant::now();
        socket
            .send(Message::text(text))
            .await
            .map_err(|error| format!("client {client}: {error}"))?;
        let response = loop {
            match socket.next().await {
                Some(Ok(Message::Text(response))) => break response,
                Some(Ok(_)) => {}
                Some(Err(error)) => return Err(format!("client {client}: {error}")),
                None => return Err(format!("client {client}: the server closed")),
            }
        };
        let elapsed = sent.elapsed();
        let ok = response.contains(&id)
            && response.contains("\"result\":true")
            && response.contains("\"success\":true");
        if !ok {
            return Err(format!("client {client}: an unexpected answer: {response}"));
        }
        if iteration >= WARM_UP {
            latencies.push(elapsed);
        }
    }
    let _closed = socket.close(None).await;
    Ok(latencies)
}

/// Runs `work` on a single-threaded runtime of its own (on the calling thread).
fn on_own_runtime<T>(
    work: impl std::future::Future<Output = Result<T, String>>,
) -> Result<T, String> {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|error| error.to_string())?
        .block_on(work)
}

/// One round-trip case's results.
struct Case {
    label: String,
    clients: usize,
    summary: Summary,
    per_second: f64,
}

/// `clients` operators sending `ask`, and optionally one more sending `get_policies` until
/// they are done; the first's results and the other's.
async fn round_trips(
    address: SocketAddr,
    ask: Ask,
    clients: usize,
    bystander: bool,
) -> Result<(Case, Option<Case>), String> {
    let each = ROUND_TRIPS / clients;
    let start = Arc::new(Barrier::new(clients + 1 + usize::from(bystander)));
    let until = Until::new();
    let tasks: Vec<_> = (0..clients)
        .map(|client| {
            tokio::spawn(operator(
                address,
                ask,
                (client, clients),
                each,
                Arc::clone(&start),
                until.clone(),
            ))
        })
        .collect();
    let watching = Until::new();
    // On a thread and runtime of its own, so that it does not wait behind the other clients'
    // tasks on the client side.
    let other = bystander.then(|| {
        let (start, watching) = (Arc::clone(&start), watching.clone());
        std::thread::spawn(move || {
            on_own_runtime(operator(
                address,
                Ask::GetPolicies,
                (clients, clients + 1),
                ROUND_TRIPS,
                start,
                watching,
            ))
        })
    });
    start.wait().await;
    let began = Instant::now();
    let mut latencies = Vec::with_capacity(ROUND_TRIPS);
    for task in tasks {
        let client = task.await.map_err(|error| error.to_string())??;
        latencies.extend(client);
    }
    let wall = began.elapsed();
    watching.stop.store(true, Ordering::Relaxed);
    let label = |ask: Ask| match ask {
        Ask::SetCommands => "`set_commands`".to_owned(),
        Ask::GetPolicies => "`get_policies`".to_owned(),
    };
    let other = match other {
        None => None,
        Some(task) => {
            let latencies = task
                .join()
                .map_err(|_| "the get_policies client panicked".to_owned())??;
            let done = latencies.len();
            Some(Case {
                label: format!(
                    "{} beside {clients} {} clients",
                    label(Ask::GetPolicies),
                    label(ask)
                ),
                clients: 1,
                summary: Summary::of(latencies),
                per_second: done as f64 / wall.as_secs_f64(),
            })
        }
    };
    let done = latencies.len();
    let case = Case {
        label: if ask == Ask::GetPolicies {
            format!("{} (transport floor)", label(ask))
        } else {
            label(ask)
        },
        clients,
        summary: Summary::of(latencies),
        per_second: done as f64 / wall.as_secs_f64(),
    };
    Ok((case, other))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // `cargo bench` passes `--bench`; `cargo test --benches` passes nothing and only builds.
    if !std::env::args().any(|arg| arg == "--bench") {
        println!("roundtrip: run with `cargo bench -p cooperation-server --bench roundtrip`");
        return Ok(());
    }
    let load_before = load_average();
    let began = Instant::now();

    let mut config = cooperation_adapters::settings::parse(include_str!(
        "../../../config/cooperation.param.yaml"
    ))?;
    config.limits.max_scenes = config.limits.max_scenes.max(SCENES);
    // Every request tells the core its time: no scene may expire during the run.
    config.limits.ttl_ms = 3_600_000;
    let per_interface = SCENES.div_ceil(INTERFACES.len());
    let node = Arc::new(Node::with_scene_quota(config, per_interface)?);
    for (at, interface) in INTERFACES.iter().enumerate() {
        let indices = at * per_interface..((at + 1) * per_interface).min(SCENES);
        let request =
            cooperation_server::sync::read_json(sync_args(interface, indices).as_bytes())?;
        let (reply, _) = node.handle(Request::Sync(request));
        if !reply.success() {
            return Err(format!("the scenes of {interface} did not register: {reply:?}").into());
        }
    }
    let live = node
        .shared()
        .expect("a node over its own engine")
        .read(|host| host.state().scene_count());
    if live != SCENES {
        return Err(format!("{live} live scenes, not {SCENES}").into());
    }
    node.publish();
    let frame_bytes: Vec<usize> = Topic::ALL
        .iter()
        .map(|topic| node.subscribe(*topic).borrow().frame.len())
        .collect();

    // The server on its own runtime (one worker per core, as `#[tokio::main]` makes), the
    // clients on another, single-threaded one.
    let server = tokio::runtime::Runtime::new()?;
    let listener = server.block_on(cooperation_server::bind("127.0.0.1:0".parse()?))?;
    let address = listener.local_addr()?;
    let options = Options {
        publish_every: Duration::from_secs(3_600),
        max_clients: 512,
        // Every client is on loopback, one address.
        admission: cooperation_server::Admission {
            per_peer: 512,
            ..cooperation_server::Admission::default()
        },
        ..Options::default()
    };
    server.spawn(cooperation_server::serve(
        listener,
        Arc::clone(&node),
        options,
        std::future::pending(),
    ));
    let clients = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;

    let measured = in_process(&node);

    let mut cases = Vec::new();
    cases.push(
        clients
            .block_on(round_trips(address, Ask::GetPolicies, 1, false))?
            .0,
    );
    for count in CLIENTS {
        let (case, bystander) = clients.block_on(round_trips(
            address,
            Ask::SetCommands,
            count,
            count == BESIDE,
        ))?;
        cases.push(case);
        cases.extend(bystander);
    }

    let mut deliveries = Vec::new();
    for (count, rounds) in SUBSCRIBERS {
        let (each, all) = clients.block_on(delivery(address, &node, count, rounds))?;
        deliveries.push((count, each, all));
    }
    let fair = fairness(&clients, address)?;
    let live_after = node
        .shared()
        .expect("a node over its own engine")
        .read(|host| host.state().scene_count());
    let load_after = load_average();

    let mut out = String::new();
    let _ = writeln!(
        out,
        "\n{SCENES} live scenes ({live_after} at the end); publish frames: velocity {} bytes, \
         steering {} bytes; load average before {load_before}, after {load_after}; \
         {:.0} s in all.\n",
        frame_bytes[0],
        frame_bytes[1],
        began.elapsed().as_secs_f64()
    );
    let _ = writeln!(out, "### Command round trips over WebSocket\n");
    let _ = writeln!(
        out,
        "| call | clients | round trips | p50 | p99 | max | mean | round trips/s | core's share of p50 |"
    );
    let _ = writeln!(out, "|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    let core = measured.summary(CORE_COMMAND);
    for case in &cases {
        let core_share = if case.label == "`set_commands`" {
            share(core.p50, case.summary.p50)
        } else {
            "–".to_owned()
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {:.0} | {} |",
            case.label,
            case.clients,
            case.summary.count,
            show(case.summary.p50),
            show(case.summary.p99),
            show(case.summary.max),
            show(case.summary.mean),
            case.per_second,
            core_share,
        );
    }
    let one_client = cases
        .iter()
        .find(|case| case.clients == 1 && case.label == "`set_commands`")
        .map_or(Duration::ZERO, |case| case.summary.p50);
    let publish = measured.summary(PUBLISH);
    let _ = writeln!(
        out,
        "\n### In process, {} iterations each, interleaved in {ROUNDS} rounds\n",
        ROUNDS * PER_ROUND
    );
    let _ = writeln!(
        out,
        "| what | p50 | p99 | mean | share of the p50 it is part of |"
    );
    let _ = writeln!(out, "|---|---:|---:|---:|---:|");
    for (name, whole, of) in [
        (CALL, one_client, "of the 1-client round trip"),
        (JSON_SERVICE, one_client, "of the 1-client round trip"),
        (CORE_COMMAND, one_client, "of the 1-client round trip"),
        (PUBLISH, one_client, "of the 1-client round trip"),
        (CONVERT, publish.p50, "of Node::publish"),
        (QUERY, publish.p50, "of Node::publish"),
        (QUERY_KEYED, publish.p50, "of Node::publish"),
        (SERIALIZE, publish.p50, "of Node::publish"),
    ] {
        let summary = measured.summary(name);
        let _ = writeln!(
            out,
            "| {name} | {} | {} | {} | {} {of} |",
            show(summary.p50),
            show(summary.p99),
            show(summary.mean),
            share(summary.p50, whole),
        );
    }
    let _ = writeln!(out, "\n### Delivery of one publication (both topics)\n");
    let _ = writeln!(
        out,
        "| subscribers | publications | each subscriber p50 | each subscriber p99 | last subscriber p50 | last subscriber p99 | Node::publish p50 share of the last's p50 |"
    );
    let _ = writeln!(out, "|---:|---:|---:|---:|---:|---:|---:|");
    for (count, each, all) in &deliveries {
        let _ = writeln!(
            out,
            "| {count} | {} | {} | {} | {} | {} | {} |",
            all.count,
            show(each.p50),
            show(each.p99),
            show(all.p50),
            show(all.p99),
            share(publish.p50, all.p50),
        );
    }
    let _ = writeln!(
        out,
        "\n### One client's heavy requests beside another's `get_policies`\n"
    );
    let _ = writeln!(
        out,
        "| what | round trips | p50 | p99 | max | p50 / idle | p99 / idle |"
    );
    let _ = writeln!(out, "|---|---:|---:|---:|---:|---:|---:|");
    for (what, summary) in [
        ("`get_policies`, the node otherwise idle", &fair.idle),
        (
            &*format!("`get_policies` beside one client's {HEAVY_ENTRIES}-status syncs"),
            &fair.beside,
        ),
        (
            &*format!("the {HEAVY_ENTRIES}-status syncs themselves"),
            &fair.heavy,
        ),
    ] {
        let _ = writeln!(
            out,
            "| {what} | {} | {} | {} | {} | {:.1} | {:.1} |",
            summary.count,
            show(summary.p50),
            show(summary.p99),
            show(summary.max),
            summary.p50.as_secs_f64() / fair.idle.p50.as_secs_f64(),
            summary.p99.as_secs_f64() / fair.idle.p99.as_secs_f64(),
        );
    }
    print!("{out}");
    server.shutdown_background();
    Ok(())
}
