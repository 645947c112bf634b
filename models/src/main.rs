//! `cooperation-models`: the exhaustive model check of the cooperation core.
//!
//! ```text
//! cooperation-models check   [--model sequential|network|rtc] [--modules M] [--scenes N] [--live L] [--retired R]
//!                            [--threads T] [--strategy dfs|bfs] [--no-symmetry]
//!                            [--fault NAME] [--out DIR] [--timeout SECONDS] [--summary]
//!                            [--keep-going] [--memory-gib G] [--max-states N]
//!                            [--table adaptive|hashed] [--keep-stalled]
//! cooperation-models check   --model rtc [--modules INTERFACES] [--first-interface I] ...
//! cooperation-models check   --model network [--operators 1|2] [--views ids|statuses] [--scenes N] ...
//! cooperation-models simulate [--modules M] [--scenes N] [--live L] [--retired R]
//!                            [--seeds A..B] [--depth D] [--threads T] [--fault NAME]
//! cooperation-models reach   [--full] [--only BOUNDS] [--write FILE]
//! cooperation-models coverage [--modules M] [--scenes N] [--live L] [--retired R]
//!                            [--threads T] [--no-symmetry] [--fault NAME] [--timeout SECONDS]
//!                            [--memory-gib G] [--max-states N] [--write FILE] [--against FILE]
//! cooperation-models explore [--modules M] [--scenes N] [--live L] [--retired R] [--address A]
//! cooperation-models replay  FILE
//! ```

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use cooperation::TableLayout;
use cooperation_models::budget::GIB;
use cooperation_models::run::{Settings, Stop, Strategy};

mod checks;
mod pairs;
mod reach;
mod swarm;
use cooperation_models::{Bounds, Fault, RtcFault, Trace, Views};
use stateright::Model;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const USAGE: &str = "usage:
  cooperation-models check   [--model sequential|network|rtc] [--modules M] [--scenes N]
                             [--live L] [--retired R] [--threads T] [--strategy dfs|bfs]
                             [--no-symmetry] [--fault NAME] [--out DIR]
                             [--timeout SECONDS] [--summary] [--keep-going]
                             [--memory-gib G] [--max-states N] [--table adaptive|hashed]
                             [--depth STEPS] [--keep-stalled]
  cooperation-models check   --model rtc [--modules INTERFACES] [--first-interface I] ...
  cooperation-models check   --model network [--operators 1|2] [--views ids|statuses]
                             [--scenes N] [--threads T] [--fault NAME] ...
  cooperation-models check   --model trivial [--threads T] [--bytes B]
  cooperation-models simulate [--modules M] [--scenes N] [--live L] [--retired R]
                             [--seeds A..B] [--depth D] [--threads T] [--fault NAME]
                             [--table adaptive|hashed] [--out DIR]
  cooperation-models reach   [--full] [--only BOUNDS] [--write FILE]
  cooperation-models coverage [--modules M] [--scenes N] [--live L] [--retired R]
                             [--threads T] [--no-symmetry] [--fault NAME]
                             [--timeout SECONDS] [--memory-gib G] [--max-states N]
                             [--write FILE] [--against FILE]
  cooperation-models explore [--modules M] [--scenes N] [--live L] [--retired R] [--address A]
  cooperation-models replay  FILE
  cooperation-models diagrams [--check]
  cooperation-models traceability [--check]
  cooperation-models witnesses [--check]

defaults: 2 modules, 3 scene identifiers, at most scenes-1 live, every retired one remembered,
2 threads, depth first with symmetry reduction (breadth first when symmetry is off or cannot
apply, that is when fewer retired identifiers are remembered than there are identifiers),
counterexamples saved under target/counterexamples. --table hashed lays every state's scenes
out in the hashed index from the first scene, under a colliding hash (same counts). An input
that changes nothing ends a path, and all such ends that fired one rule count as one state
(--keep-stalled counts each as its own, for cross-checking; same verdicts). The network
model (breadth first) defaults to 2 scene identifiers, 2 operators and --views ids: status
messages tell operators which scenes exist; --views statuses makes them carry the library's
whole statuses, decisions included, and lets owners abort a scene (complete for --operators 1;
with 2 operators it outgrows memory). The rtc model's --modules is its number of interfaces,
taken in order from lane_change_left, lane_change_right, intersection,
static_obstacle_avoidance_left and static_obstacle_avoidance_right, from position
--first-interface (default 0; 3 for the avoidances). The check stops at the first violated
`always` property (--keep-going collects every violation), and stops incomplete, with a
report and exit status 1, when the process reaches 16 GiB resident (--memory-gib) or 400
million distinct states (--max-states), or the time limit. simulate takes one random walk of
the sequential model per seed (default 0..100, 1000 inputs a walk, up to 64 identifiers and 8
modules), checks every property in every state visited, and stops at the first violation,
saving its trace; a walk depends on its seed alone, so disjoint seed ranges on separate
machines make one run. coverage explores the sequential model's reachable states breadth
first (symmetry as check uses it) and lists every ordered pair of consecutive rules, on the same
scene, on different scenes or not scene-specific; --write saves them as JSON (rewritten after
every level, so a run that dies leaves what it found), --against FILE compares with such a file.
Exit status: 0 every property satisfied (and, for check and coverage, the search complete), 1
otherwise, 2 bad usage. Faults (sensitivity tests): ";

/// Which model to check.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Which {
    Sequential,
    Network,
    Rtc,
    Trivial,
}

pub(crate) struct Options {
    pub(crate) which: Which,
    pub(crate) bounds: Bounds,
    pub(crate) settings: Settings,
    pub(crate) fault: Option<String>,
    pub(crate) out: PathBuf,
    pub(crate) address: String,
    pub(crate) stop: Stop,
    pub(crate) table: TableLayout,
    pub(crate) keep_stalled: bool,
    pub(crate) summary: bool,
    pub(crate) bytes: usize,
    pub(crate) operators: usize,
    pub(crate) first_interface: usize,
    pub(crate) views: Views,
    pub(crate) seeds: std::ops::Range<u64>,
    pub(crate) write: Option<PathBuf>,
    pub(crate) against: Option<PathBuf>,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut bounds = Bounds::new(2, 3);
    let (mut live, mut retired) = (None, None);
    let mut settings = Settings {
        threads: 2,
        strategy: Strategy::Dfs,
        symmetry: true,
    };
    let mut strategy = None;
    let mut fault = None;
    let mut out = PathBuf::from("target/counterexamples");
    let mut address = "127.0.0.1:3000".to_owned();
    let mut which = Which::Sequential;
    let mut stop = Stop::first_violation();
    let mut table = TableLayout::Adaptive;
    let mut summary = false;
    let mut keep_stalled = false;
    let mut bytes = reach::TRIVIAL.bytes;
    let mut operators = cooperation_models::network::OPERATORS;
    let mut first_interface = 0;
    let mut views = Views::Identifiers;
    let mut seeds = 0..100;
    let (mut write, mut against) = (None, None);
    let mut rest = args.iter();
    while let Some(flag) = rest.next() {
        if flag == "--no-symmetry" {
            settings.symmetry = false;
            continue;
        }
        if flag == "--keep-stalled" {
            keep_stalled = true;
            continue;
        }
        if flag == "--summary" {
            summary = true;
            continue;
        }
        if flag == "--keep-going" {
            stop.keep_going = true;
            continue;
        }
        let value = rest.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let number = || {
            value
                .parse::<usize>()
                .map_err(|_| format!("{flag} takes a number, not {value:?}"))
        };
        match flag.as_str() {
            "--modules" => bounds.modules = number()?,
            "--scenes" => bounds.scenes = number()?,
            "--live" => live = Some(number()?),
            "--retired" => retired = Some(number()?),
            "--threads" => settings.threads = number()?,
            "--strategy" => {
                strategy = Some(match value.as_str() {
                    "dfs" => Strategy::Dfs,
                    "bfs" => Strategy::Bfs,
                    other => return Err(format!("--strategy is dfs or bfs, not {other:?}")),
                });
            }
            "--fault" => {
                let known = Fault::ALL.iter().map(|f| format!("{f:?}"));
                let mut known = known.chain(RtcFault::ALL.iter().map(|f| format!("{f:?}")));
                if !known.any(|name| name == *value) {
                    return Err(format!("no fault is named {value:?}"));
                }
                fault = Some(value.clone());
            }
            "--out" => out = PathBuf::from(value),
            "--write" => write = Some(PathBuf::from(value)),
            "--against" => against = Some(PathBuf::from(value)),
            "--bytes" => bytes = number()?,
            "--operators" => operators = number()?,
            "--first-interface" => first_interface = number()?,
            "--views" => {
                views = match value.as_str() {
                    "ids" => Views::Identifiers,
                    "statuses" => Views::Statuses,
                    other => return Err(format!("--views is ids or statuses, not {other:?}")),
                };
            }
            "--depth" => stop.depth = Some(number()?),
            "--seeds" => seeds = seed_range(value)?,
            "--timeout" => {
                stop.timeout = Some(std::time::Duration::from_secs(number()? as u64));
            }
            "--memory-gib" => stop.budget.memory_bytes = (number()? as u64).saturating_mul(GIB),
            "--max-states" => stop.budget.states = number()?,
            "--table" => {
                table = match value.as_str() {
                    "adaptive" => TableLayout::Adaptive,
                    "hashed" => TableLayout::Colliding,
                    other => return Err(format!("--table is adaptive or hashed, not {other:?}")),
                };
            }
            "--model" => {
                which = match value.as_str() {
                    "sequential" => Which::Sequential,
                    "network" => Which::Network,
                    "trivial" => Which::Trivial,
                    "rtc" => Which::Rtc,
                    other => {
                        return Err(format!(
                            "--model is sequential, network, rtc or trivial, not {other:?}"
                        ))
                    }
                }
            }
            "--address" => address.clone_from(value),
            other => return Err(format!("unknown option {other:?}")),
        }
    }
    let defaults = Bounds::new(bounds.modules, bounds.scenes);
    bounds.live = live.unwrap_or(defaults.live);
    bounds.retired = retired.unwrap_or(defaults.retired);
    if settings.symmetry && bounds.retired < bounds.scenes {
        // Forgetting identifiers makes the retirement order matter, and it is not symmetric.
        settings.symmetry = false;
    }
    // Symmetry needs depth first (breadth first ignores it); without symmetry, breadth first
    // keeps memory flat where depth-first paths grow long.
    settings.strategy = strategy.unwrap_or(if settings.symmetry {
        Strategy::Dfs
    } else {
        Strategy::Bfs
    });
    if settings.strategy == Strategy::Bfs {
        settings.symmetry = false;
    }
    if which == Which::Network && !args.iter().any(|a| a == "--scenes") {
        bounds.scenes = 2;
    }
    Ok(Options {
        which,
        bounds,
        settings,
        fault,
        out,
        address,
        stop,
        table,
        keep_stalled,
        summary,
        bytes,
        operators,
        first_interface,
        views,
        seeds,
        write,
        against,
    })
}

/// `A..B`: the seeds from A up to but not including B.
fn seed_range(text: &str) -> Result<std::ops::Range<u64>, String> {
    let bad = || format!("--seeds takes A..B, with A and B numbers and A below B, not {text:?}");
    let (start, end) = text.split_once("..").ok_or_else(bad)?;
    let (start, end): (u64, u64) = (
        start.parse().map_err(|_| bad())?,
        end.parse().map_err(|_| bad())?,
    );
    if start >= end {
        return Err(bad());
    }
    Ok(start..end)
}

fn replay(file: &str) -> Result<bool, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{file}: {e}"))?;
    let trace: Trace = serde_json::from_str(&text).map_err(|e| format!("{file}: {e}"))?;
    print!("{}", trace.render().map_err(|e| e.to_string())?);
    let holds = trace.holds_at_end().map_err(|e| e.to_string())?;
    println!(
        "\nat the end, the property {}",
        if holds { "holds" } else { "is violated" }
    );
    Ok(holds)
}

/// Rewrites the generated diagrams in the spec (or, with `--check`, only says whether they are
/// current).
fn diagrams(args: &[String]) -> Result<bool, String> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../spec/cooperation.md");
    let spec = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let current = cooperation_models::diagrams::regenerate(&spec);
    if current == spec {
        println!("the diagrams in spec/cooperation.md are current");
        return Ok(true);
    }
    if args.iter().any(|a| a == "--check") {
        println!("the diagrams in spec/cooperation.md differ from the code");
        return Ok(false);
    }
    std::fs::write(path, current).map_err(|e| format!("{path}: {e}"))?;
    println!("rewrote the diagrams in spec/cooperation.md");
    Ok(true)
}

/// Writes docs/traceability.md from the sources (or, with `--check`, only compares).
fn traceability(args: &[String]) -> Result<bool, String> {
    use cooperation_models::traceability::{gaps, markdown, rows};
    let root = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let rows = rows(root);
    for gap in gaps(&rows) {
        println!("gap: {gap}");
    }
    let text = markdown(&rows);
    let path = root.join("docs/traceability.md");
    let current = std::fs::read_to_string(&path).unwrap_or_default();
    if current == text {
        println!("docs/traceability.md is current ({} tags)", rows.len());
        return Ok(gaps(&rows).is_empty());
    }
    if args.iter().any(|a| a == "--check") {
        println!("docs/traceability.md is stale");
        return Ok(false);
    }
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("wrote docs/traceability.md ({} tags)", rows.len());
    Ok(gaps(&rows).is_empty())
}

/// Writes docs/witnesses.md (or, with `--check`, only compares).
fn witnesses(args: &[String]) -> Result<bool, String> {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/witnesses.md");
    let text = cooperation_models::witnesses::page();
    let current = std::fs::read_to_string(path).unwrap_or_default();
    if current == text {
        println!("docs/witnesses.md is current");
        return Ok(true);
    }
    if args.iter().any(|a| a == "--check") {
        println!("docs/witnesses.md is stale");
        return Ok(false);
    }
    std::fs::write(path, text).map_err(|e| format!("{path}: {e}"))?;
    println!("wrote docs/witnesses.md");
    Ok(true)
}

fn explore(options: &Options) -> Result<bool, String> {
    let model = checks::model(options)?;
    println!(
        "serving stateright's Explorer on http://{} (Ctrl-C to stop)",
        options.address
    );
    let _ = std::io::stdout().flush();
    model.checker().serve(options.address.as_str());
    Ok(true)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let faults: Vec<String> = Fault::ALL.iter().map(|f| format!("{f:?}")).collect();
    let rtc: Vec<String> = RtcFault::ALL.iter().map(|f| format!("{f:?}")).collect();
    let usage = format!(
        "{USAGE}{}; with --model rtc: {}",
        faults.join(", "),
        rtc.join(", ")
    );
    let asks_for_help = args.iter().any(|arg| arg == "--help" || arg == "-h");
    let result = match args.split_first() {
        _ if asks_for_help => {
            println!("{usage}");
            Ok(true)
        }
        Some((command, rest)) if command == "check" => parse(rest).and_then(|o| checks::run(&o)),
        Some((command, rest)) if command == "reach" => reach::run(rest),
        Some((command, rest)) if command == "coverage" => parse(rest).and_then(|o| pairs::run(&o)),
        Some((command, rest)) if command == "simulate" => parse(rest).and_then(|o| swarm::run(&o)),
        Some((command, rest)) if command == "explore" => parse(rest).and_then(|o| explore(&o)),
        Some((command, [file])) if command == "replay" => replay(file),
        Some((command, rest)) if command == "diagrams" => diagrams(rest),
        Some((command, rest)) if command == "traceability" => traceability(rest),
        Some((command, rest)) if command == "witnesses" => witnesses(rest),
        Some((command, _)) if command == "help" => {
            println!("{usage}");
            Ok(true)
        }
        _ => Err(usage),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(message) => {
            eprintln!("{message}");
            ExitCode::from(2)
        }
    }
}
