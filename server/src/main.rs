//! `cooperation-server`: serves the cooperation AD API over rosbridge, and the operator panel.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use clap::Parser;
use cooperation_server::{Access, Credentials, Node, Options};

/// Serves the cooperation AD API (set_commands, set_policies, get_policies, velocity and
/// steering factors) and the planning modules' sync service over the rosbridge v2 protocol,
/// and the operator panel at http://ADDR/; with --stack, the AD API over the planning modules'
/// own RTC endpoints instead, over DDS and rosbridge at once.
#[derive(Parser, Debug)]
#[command(version)]
#[cfg_attr(
    feature = "dds",
    command(group(clap::ArgGroup::new("over_dds").args(["dds_domain", "stack"]).multiple(true)))
)]
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
    #[arg(long, default_value_t = cooperation_server::Options::default().max_clients)]
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
    #[arg(long, value_name = "ID",
          value_parser = clap::value_parser!(u16).range(0..=i64::from(cooperation_dds::MAX_DOMAIN)))]
    dds_domain: Option<u16>,
    /// With `--dds-domain` or `--stack`: a local address DDS may use; repeat for more (all by
    /// default).
    #[cfg(feature = "dds")]
    #[arg(long = "dds-interface", value_name = "ADDRESS", requires = "over_dds")]
    dds_interfaces: Vec<std::net::IpAddr>,
    /// The stack mode (docs/autoware.md): the AD API over the planning modules' own RTC
    /// endpoints, relayed over DDS as `cooperation-dds --stack` does, on the domain of
    /// `--dds-domain` (by default ROS_DOMAIN_ID, or 0); the WebSocket and the panel serve the
    /// same relay.
    #[cfg(feature = "dds")]
    #[arg(long)]
    stack: bool,
    /// In the stack mode, how long a module has to answer a call, in milliseconds.
    #[cfg(feature = "dds")]
    #[arg(long, default_value_t = cooperation_adapters::relay::DEADLINE_MS, requires = "stack",
          value_parser = clap::value_parser!(u64).range(1..=cooperation_adapters::relay::MAX_DEADLINE_MS))]
    deadline_ms: u64,
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
    #[cfg(feature = "dds")]
    let (node, dds) = dds::doors(&args, publish_every)?;
    #[cfg(not(feature = "dds"))]
    let (node, dds) = (Arc::new(own_engine(&args, publish_every)?), None::<Door>);
    // A module's credential may name the interfaces the engine binds.
    let interfaces = node.interfaces();
    let credentials = match &args.credentials {
        Some(path) => Some(read_credentials(path, &interfaces, args.per_credential)?),
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
            origins: args.allow_origins.clone(),
            hosts: args.allow_hosts.clone(),
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
    // A door's thread that ends, for whatever reason (its sender dropped unsent when it
    // panics), stops the node.
    let (dds, door_ended) = match dds {
        Some(door) => {
            let (ended, door_ended) = tokio::sync::oneshot::channel::<()>();
            (Some(door.watched(ended)), Some(door_ended))
        }
        None => (None, None),
    };
    let door_ended = async move {
        match door_ended {
            Some(ended) => {
                let _ = ended.await;
            }
            None => std::future::pending().await,
        }
    };
    let shutdown = async {
        tokio::select! {
            _ = tokio::signal::ctrl_c() => tracing::info!("shutting down"),
            () = door_ended => tracing::error!("the DDS door stopped: shutting down"),
        }
    };
    let reloads = reloads(args.credentials.clone(), interfaces, args.per_credential);
    let served = cooperation_server::serve_reloading(listener, node, options, reloads, shutdown)
        .await
        .map_err(|error| error.to_string());
    let stopped = dds.map_or(Ok(()), Door::stop);
    served.and(stopped)
}

/// A node over an engine of its own, built from the settings, publishing every
/// `publish_every` from the start (a DDS door serving it publishes at once).
fn own_engine(args: &Args, publish_every: std::time::Duration) -> Result<Node, String> {
    Node::from_settings(
        args.settings.as_deref(),
        cooperation_adapters::engine::Options {
            scene_quota: args.scene_quota,
            ..cooperation_adapters::engine::Options::default()
        }
        .publishing_every(publish_every),
    )
    .map_err(|error| error.to_string())
}

/// The credentials file at `path`, read and checked against the node's `interfaces`.
fn read_credentials(
    path: &std::path::Path,
    interfaces: &[String],
    places: usize,
) -> Result<Credentials, String> {
    let text = cooperation_server::auth::read_file(path)?;
    let interfaces: Vec<&str> = interfaces.iter().map(String::as_str).collect();
    Credentials::parse(&text, &interfaces, places)
        .map_err(|error| format!("{}: {error}", path.display()))
}

/// The credentials file read again on each SIGHUP, for as long as the node runs: a file that
/// does not read is logged and leaves the credentials in force as they are. Nothing without a
/// file.
fn reloads(
    path: Option<PathBuf>,
    interfaces: Vec<String>,
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
    let interfaces = std::sync::Arc::new(interfaces);
    futures_util::stream::unfold(hangups, move |hangups| {
        let interfaces = std::sync::Arc::clone(&interfaces);
        async move {
            let (mut hangups, path) = hangups?;
            loop {
                hangups.recv().await?;
                match read_credentials(&path, &interfaces, places) {
                    Ok(credentials) => return Some((credentials, Some((hangups, path)))),
                    Err(error) => tracing::error!(
                    "SIGHUP: the credentials file does not read, the credentials in force stay: \
                     {error}"
                ),
                }
            }
        }
    })
}

/// What a DDS door's thread runs, until the flag is set.
type Run = Box<dyn FnOnce(&std::sync::atomic::AtomicBool) -> Result<(), String> + Send>;

/// A running DDS door: its stop flag and its thread, which says when it ends.
struct Door {
    stop: Arc<std::sync::atomic::AtomicBool>,
    run: Run,
    thread: Option<std::thread::JoinHandle<Result<(), String>>>,
}

impl Door {
    /// Starts the door's thread, which sends on `ended` when it ends, for whatever reason.
    fn watched(mut self, ended: tokio::sync::oneshot::Sender<()>) -> Self {
        let flag = Arc::clone(&self.stop);
        let run = std::mem::replace(&mut self.run, Box::new(|_| Ok(())));
        let thread = std::thread::Builder::new()
            .name("dds".to_owned())
            .spawn(move || {
                let ran = run(&flag);
                let _told = ended.send(());
                ran
            });
        match thread {
            Ok(thread) => self.thread = Some(thread),
            Err(error) => tracing::error!(%error, "the DDS door's thread did not start"),
        }
        self
    }

    /// Stops the door and waits for its thread: what it ended with.
    fn stop(self) -> Result<(), String> {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        let thread = self
            .thread
            .ok_or_else(|| "the DDS door's thread did not start".to_owned())?;
        thread
            .join()
            .map_err(|_| "the DDS door's thread panicked".to_owned())
            .and_then(|ran| ran)
    }
}

/// The doors over DDS (the `dds` feature).
#[cfg(feature = "dds")]
mod dds {
    use std::sync::Arc;
    use std::time::Duration;

    use cooperation_server::Node;

    use super::{own_engine, Args, Door};

    /// The node, and its DDS door: `cooperation-dds`'s stack node in the stack mode (the node
    /// a door onto its relay), or its node on the node's own engine with `--dds-domain`.
    pub(super) fn doors(
        args: &Args,
        publish_every: Duration,
    ) -> Result<(Arc<Node>, Option<Door>), String> {
        if args.stack {
            let (node, door) = stack(args, publish_every)?;
            return Ok((node, Some(door)));
        }
        let node = Arc::new(own_engine(args, publish_every)?);
        let Some(domain) = args.dds_domain else {
            return Ok((node, None));
        };
        let shared = node
            .shared()
            .ok_or_else(|| "a node without an engine of its own".to_owned())?;
        let options = cooperation_dds::Options {
            domain,
            interfaces: args.dds_interfaces.clone(),
            ..cooperation_dds::Options::default()
        };
        let mut door =
            cooperation_dds::Node::with_shared(Arc::clone(shared), *node.clock(), options)?;
        tracing::info!("serving the same core on DDS domain {domain}");
        Ok((node, Some(Door::new(move |stop| door.run(stop)))))
    }

    /// The stack mode: the stack node, and this node a door onto its relay.
    fn stack(args: &Args, publish_every: Duration) -> Result<(Arc<Node>, Door), String> {
        let domain = match args.dds_domain {
            Some(domain) => domain,
            None => match std::env::var("ROS_DOMAIN_ID") {
                Ok(text) => cooperation_dds::domain(&text)
                    .map_err(|error| format!("ROS_DOMAIN_ID: {error}"))?,
                Err(_) => 0,
            },
        };
        let options = cooperation_dds::Options {
            domain,
            interfaces: args.dds_interfaces.clone(),
            publish_every,
            scene_quota: args.scene_quota,
            ..cooperation_dds::Options::default()
        };
        let deadline = Duration::from_millis(args.deadline_ms);
        let mut stack = cooperation_dds::Stack::new(args.settings.as_deref(), options, deadline)?;
        let waker = stack.waker();
        let (calls, incoming) = std::sync::mpsc::channel();
        let wake = move || {
            if let Err(error) = waker.wake() {
                tracing::error!(%error, "the stack node could not be woken for a call");
            }
        };
        let interfaces = stack.interfaces().map(str::to_owned).collect();
        let node = Arc::new(Node::relayed(
            calls,
            Box::new(wake),
            Duration::from_millis(cooperation_adapters::relay::answer_wait_ms(
                args.deadline_ms,
            )),
            interfaces,
        ));
        let shown = Arc::clone(&node);
        stack.open_door(cooperation_dds::Door {
            calls: incoming,
            shown: Box::new(move |publication| shown.show(publication)),
        });
        tracing::info!(
            "the stack mode on DDS domain {domain}: the AD API over the RTC interfaces {}",
            stack.interfaces().collect::<Vec<_>>().join(", "),
        );
        Ok((node, Door::new(move |stop| stack.run(stop))))
    }

    impl Door {
        /// A door that runs `run` on its thread until its flag is set.
        fn new(
            run: impl FnOnce(&std::sync::atomic::AtomicBool) -> Result<(), String> + Send + 'static,
        ) -> Self {
            Self {
                stop: Arc::new(std::sync::atomic::AtomicBool::new(false)),
                run: Box::new(run),
                thread: None,
            }
        }
    }
}
