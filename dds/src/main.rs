//! `cooperation-dds`: serves the cooperation AD API as a ROS 2 node over DDS.

use std::net::IpAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use clap::Parser;
use cooperation_dds::graph::Distro;
use cooperation_dds::{Node, Options, Stack};

/// Serves the cooperation AD API (set_commands, set_policies, get_policies, velocity and
/// steering factors) and the planning modules' sync service as a ROS 2 node over DDS, as
/// rmw_cyclonedds_cpp speaks it; with --stack, the AD API over the planning modules' own RTC
/// endpoints instead.
#[derive(Parser, Debug)]
#[command(version)]
struct Args {
    /// The DDS domain (by default ROS_DOMAIN_ID, or 0).
    #[arg(long, env = "ROS_DOMAIN_ID", default_value_t = 0, value_parser = clap::value_parser!(u16).range(0..=i64::from(cooperation_dds::MAX_DOMAIN)))]
    domain: u16,
    /// A local address DDS may use; repeat for more (by default every interface).
    #[arg(long = "interface", value_name = "ADDRESS")]
    interfaces: Vec<IpAddr>,
    /// The settings file with the modules' default policies and the limits (by default the
    /// repository's config/cooperation.param.yaml, built into the node).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// The node's name in the ROS graph.
    #[arg(long, default_value = "cooperation")]
    name: String,
    /// The node's namespace.
    #[arg(long, default_value = "/")]
    namespace: String,
    /// The ROS 2 line of the peers (the length of a Gid in ros_discovery_info).
    #[arg(long, value_enum, default_value_t = Distro::Humble)]
    distro: Distro,
    /// Periodic publications of the factors per second (they are also published on change);
    /// the engine's default interval unless given.
    #[arg(long, default_value_t = cooperation_adapters::engine::PUBLICATION_RATE_HZ)]
    rate: f64,
    /// Live scenes each RTC interface may hold.
    #[arg(long, default_value_t = cooperation_adapters::rtc::SCENE_QUOTA)]
    scene_quota: usize,
    /// The stack mode (docs/autoware.md): relay the AD API to the planning modules' own RTC
    /// endpoints (`/planning/cooperate_status/<name>` and the others) instead of serving the
    /// sync service.
    #[arg(long)]
    stack: bool,
    /// In the stack mode, how long a module has to answer a call, in milliseconds.
    #[arg(long, default_value_t = cooperation_adapters::relay::DEADLINE_MS, requires = "stack",
          value_parser = clap::value_parser!(u64).range(1..=cooperation_adapters::relay::MAX_DEADLINE_MS))]
    deadline_ms: u64,
}

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .init();
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            tracing::error!("{message}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: Args) -> Result<(), String> {
    let publish_every = cooperation_adapters::engine::publish_every(args.rate)
        .map_err(|error| format!("--rate {}: {error}", args.rate))?;
    if !args.namespace.starts_with('/') {
        return Err(format!(
            "--namespace {}: a namespace starts with /",
            args.namespace
        ));
    }
    let options = Options {
        domain: args.domain,
        interfaces: args.interfaces,
        name: args.name,
        namespace: args.namespace,
        distro: args.distro,
        publish_every,
        scene_quota: args.scene_quota,
    };
    let stop = Arc::new(AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, Arc::clone(&stop))
            .map_err(|error| format!("signal {signal}: {error}"))?;
    }
    let name = format!(
        "{}{}{}",
        options.namespace,
        if options.namespace.ends_with('/') {
            ""
        } else {
            "/"
        },
        options.name
    );
    if args.stack {
        let deadline = Duration::from_millis(args.deadline_ms);
        let mut stack = Stack::new(args.settings.as_deref(), options.clone(), deadline)?;
        tracing::info!(
            "serving node {name} on DDS domain {} (ROS 2 {:?}) in the stack mode: the AD API over \
             the RTC interfaces {}",
            options.domain,
            options.distro,
            stack.interfaces().collect::<Vec<_>>().join(", "),
        );
        stack.run(&stop)?;
        tracing::info!("shutting down");
        return Ok(());
    }
    let mut node = Node::new(args.settings.as_deref(), options.clone())?;
    tracing::info!(
        "serving node {name} on DDS domain {} (ROS 2 {:?}, Cyclone DDS's service mapping)",
        options.domain,
        options.distro,
    );
    node.run(&stop)?;
    tracing::info!("shutting down");
    Ok(())
}
