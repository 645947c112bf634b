//! `cooperation-server`: serves the cooperation AD API over rosbridge, and the operator panel.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use clap::Parser;
use cooperation_server::{Access, Credentials, Node, Options};

/// Serves the cooperation AD API (set_commands, set_policies, get_policies, velocity and
/// steering factors) and the planning modules' sync service over the rosbridge v2 protocol,
/// and the operator panel at http://ADDR/.
#[derive(Parser, Debug)]
#[command(version)]
struct Args {
    /// The address to listen on: HOST:PORT, the host an IP address or a name (localhost:9090),
    /// a name standing for the first address it resolves to.
    #[arg(long, default_value = "127.0.0.1:9090", value_parser = listen_address)]
    listen: SocketAddr,
    /// The settings file with the modules' default policies and the limits (by default the
    /// repository's config/cooperation.param.yaml, built into the node).
    #[arg(long)]
    settings: Option<PathBuf>,
    /// Periodic publications of the factors per second (they are also published on change);
    /// the engine's default interval unless given.
    #[arg(long, default_value_t = cooperation_adapters::engine::PUBLICATION_RATE_HZ)]
    rate: f64,
    /// At most this many clients at once, when the node has no credentials.
    #[arg(long, default_value_t = 256)]
    max_clients: usize,
    /// The credentials file: one operator or planning module a line, with its token; a client
    /// must present one (docs/server.md, "Who may connect"). Read again on SIGHUP: a credential
    /// dropped or changed is revoked at once.
    #[arg(long, value_name = "FILE")]
    credentials: Option<PathBuf>,
    /// Connections each credential may have open at once.
    #[arg(long, default_value_t = 4)]
    per_credential: usize,
    /// Serve any client without a credential on an address other than loopback.
    #[arg(long)]
    anonymous: bool,
    /// Live scenes each RTC interface may hold.
    #[arg(long, default_value_t = cooperation_server::node::SCENE_QUOTA)]
    scene_quota: usize,
    /// An origin (`scheme://host[:port]`) whose pages may open a WebSocket to the node, besides
    /// the node's own panel; repeat for more. A browser page of any other origin is refused.
    #[arg(long = "allow-origin", value_name = "ORIGIN")]
    allow_origins: Vec<String>,
    /// A host name clients may reach the node by, besides its IP addresses and localhost;
    /// repeat for more. A request naming any other host is refused (DNS rebinding).
    #[arg(long = "allow-host", value_name = "NAME")]
    allow_hosts: Vec<String>,
    /// Serve the same core over DDS too, as `cooperation-dds` does, on this ROS 2 domain: an
    /// operator's panel and ROS 2 clients then see and change the same scenes.
    #[cfg(feature = "dds")]
    #[arg(long, value_name = "ID")]
    dds_domain: Option<u16>,
    /// With `--dds-domain`: a local address DDS may use; repeat for more (all by default).
    #[cfg(feature = "dds")]
    #[arg(
        long = "dds-interface",
        value_name = "ADDRESS",
        requires = "dds_domain"
    )]
    dds_interfaces: Vec<std::net::IpAddr>,
}

/// `--listen`'s address: an IP address and port, or a name and port, resolved.
fn listen_address(text: &str) -> Result<SocketAddr, String> {
    std::net::ToSocketAddrs::to_socket_addrs(text)
        .map_err(|error| format!("{text}: {error}"))?
        .next()
        .ok_or_else(|| format!("{text}: the name resolves to no address"))
}

#[tokio::main]
async fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        // Colour only on a terminal: a log written to a file or a pipe is plain text.
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .init();
    let args = Args::parse();
    match run(args).await {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            tracing::error!("{message}");
            ExitCode::FAILURE
        }
    }
}

async fn run(args: Args) -> Result<(), String> {
    let publish_every = cooperation_adapters::engine::publish_every(args.rate)
        .map_err(|error| format!("--rate {}: {error}", args.rate))?;
    let node = Node::from_settings(
        args.settings.as_deref(),
        cooperation_adapters::engine::Options {
            scene_quota: args.scene_quota,
            ..cooperation_adapters::engine::Options::default()
        },
    )
    .map_err(|error| error.to_string())?;
    let credentials = match &args.credentials {
        Some(path) => Some(read_credentials(path, args.per_credential)?),
        None => None,
    };
    if credentials.is_none() && !args.listen.ip().is_loopback() && !args.anonymous {
        return Err(format!(
            "--listen {}: a node reachable from other hosts lets any client act as the operator \
             or as any planning module unless it has credentials; give --credentials FILE, or \
             --anonymous to serve every client anyway",
            args.listen
        ));
    }
    let options = Options {
        publish_every,
        max_clients: args.max_clients,
        credentials,
        access: Access {
            origins: args.allow_origins,
            hosts: args.allow_hosts,
        },
        ..Options::default()
    };
    if let Some(problem) = options.problem() {
        return Err(format!(
            "--rate {} --max-clients {} --per-credential {}: {problem}",
            args.rate, args.max_clients, args.per_credential
        ));
    }
    let listener = cooperation_server::bind(args.listen)
        .await
        .map_err(|error| format!("cannot listen on {}: {error}", args.listen))?;
    tracing::info!(
        "serving rosbridge on ws://{0}/ and the operator panel on http://{0}/ ({1})",
        args.listen,
        match &args.credentials {
            Some(_) => "clients present a credential",
            None => "any client may act as the operator or as any planning module",
        }
    );
    let node = Arc::new(node);
    #[cfg(feature = "dds")]
    let dds = match args.dds_domain {
        Some(domain) => Some(dds_door(&node, domain, args.dds_interfaces)?),
        None => None,
    };
    #[cfg(not(feature = "dds"))]
    let dds: Option<DdsDoor> = None;
    let shutdown = async {
        let _ = tokio::signal::ctrl_c().await;
        tracing::info!("shutting down");
    };
    let reloads = reloads(args.credentials.clone(), args.per_credential);
    let served = cooperation_server::serve_reloading(listener, node, options, reloads, shutdown)
        .await
        .map_err(|error| error.to_string());
    let stopped = dds.map_or(Ok(()), |(stop, door)| {
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        door.join()
            .map_err(|_| "the DDS door's thread panicked".to_owned())
            .and_then(|ran| ran)
    });
    served.and(stopped)
}

/// The credentials file at `path`, read and checked.
fn read_credentials(path: &std::path::Path, places: usize) -> Result<Credentials, String> {
    let text = cooperation_server::auth::read_file(path)?;
    let rtc = cooperation_adapters::rtc::Rtc::standard();
    let interfaces: Vec<&str> = rtc.bindings().iter().map(|b| b.name.as_str()).collect();
    Credentials::parse(&text, &interfaces, places)
        .map_err(|error| format!("{}: {error}", path.display()))
}

/// The credentials file read again on each SIGHUP, for as long as the node runs: a file that
/// does not read is logged and leaves the credentials in force as they are. Nothing without a
/// file.
fn reloads(
    path: Option<PathBuf>,
    places: usize,
) -> impl futures_util::Stream<Item = Credentials> + Send + 'static {
    use tokio::signal::unix::{signal, SignalKind};
    let hangups = path.and_then(|path| match signal(SignalKind::hangup()) {
        Ok(hangups) => Some((hangups, path)),
        Err(error) => {
            tracing::error!(%error, "SIGHUP cannot be watched: the credentials are read once");
            None
        }
    });
    futures_util::stream::unfold(hangups, move |hangups| async move {
        let (mut hangups, path) = hangups?;
        loop {
            hangups.recv().await?;
            match read_credentials(&path, places) {
                Ok(credentials) => return Some((credentials, Some((hangups, path)))),
                Err(error) => tracing::error!(
                    "SIGHUP: the credentials file does not read, the credentials in force stay: \
                     {error}"
                ),
            }
        }
    })
}

/// The DDS door: `cooperation-dds`'s node on `node`'s engine and clock, polled by a thread of
/// its own until the flag is set.
#[cfg(feature = "dds")]
fn dds_door(
    node: &cooperation_server::Node,
    domain: u16,
    interfaces: Vec<std::net::IpAddr>,
) -> Result<DdsDoor, String> {
    let options = cooperation_dds::Options {
        domain,
        interfaces,
        ..cooperation_dds::Options::default()
    };
    let mut door =
        cooperation_dds::Node::with_shared(Arc::clone(node.shared()), *node.clock(), options)?;
    tracing::info!("serving the same core on DDS domain {domain}");
    let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let thread = std::thread::Builder::new()
        .name("dds".to_owned())
        .spawn(move || door.run(&flag))
        .map_err(|error| format!("the DDS door's thread: {error}"))?;
    Ok((stop, thread))
}

/// A running DDS door: its stop flag and its thread.
type DdsDoor = (
    Arc<std::sync::atomic::AtomicBool>,
    std::thread::JoinHandle<Result<(), String>>,
);
