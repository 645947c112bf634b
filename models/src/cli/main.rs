//! `cooperation-models`: the exhaustive model check of the cooperation core. This folder
//! (`src/cli/`) holds the command: its options (`options.rs`), and one file per command that
//! runs the library's models and checks and reports what they found (`checks.rs`: `check`;
//! `pairs.rs`: `coverage`; `swarm.rs`: `simulate`).
//!
//! ```text
//! cooperation-models check   [--model sequential|network|rtc] [--modules M] [--scenes N] [--live L] [--retired R]
//!                            [--threads T] [--strategy dfs|bfs] [--no-symmetry]
//!                            [--fault NAME] [--out DIR] [--timeout SECONDS] [--summary]
//!                            [--keep-going] [--memory-gib G] [--max-states N]
//!                            [--table adaptive|hashed] [--keep-stalled]
//! cooperation-models check   --model rtc [--modules INTERFACES] [--first-interface I] [--quota Q] ...
//! cooperation-models check   --model network [--operators 1|2] [--views ids|statuses] [--planner core|engine] [--scenes N] ...
//! cooperation-models simulate [--modules M] [--scenes N] [--live L] [--retired R]
//!                            [--seeds A..B] [--depth D] [--threads T] [--fault NAME]
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
use std::process::ExitCode;

use cooperation_models::{Fault, RtcFault, Trace};
use stateright::Model;

mod checks;
mod options;
mod pairs;
mod swarm;

pub(crate) use options::Which;
use options::{parse, Options};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const USAGE: &str = "usage:
  cooperation-models check   [--model sequential|network|rtc] [--modules M] [--scenes N]
                             [--live L] [--retired R] [--threads T] [--strategy dfs|bfs]
                             [--no-symmetry] [--fault NAME] [--out DIR]
                             [--timeout SECONDS] [--summary] [--keep-going]
                             [--memory-gib G] [--max-states N] [--table adaptive|hashed]
                             [--depth STEPS] [--keep-stalled]
  cooperation-models check   --model rtc [--modules INTERFACES] [--first-interface I]
                             [--quota Q] ...
  cooperation-models check   --model network [--operators 1|2] [--views ids|statuses]
                             [--planner core|engine] [--scenes N] [--threads T]
                             [--fault NAME] ...
  cooperation-models check   --model trivial [--threads T] [--bytes B]
  cooperation-models simulate [--modules M] [--scenes N] [--live L] [--retired R]
                             [--seeds A..B] [--depth D] [--threads T] [--fault NAME]
                             [--table adaptive|hashed] [--out DIR]
  cooperation-models coverage [--modules M] [--scenes N] [--live L] [--retired R]
                             [--threads T] [--no-symmetry] [--fault NAME]
                             [--timeout SECONDS] [--memory-gib G] [--max-states N]
                             [--write FILE] [--against FILE]
  cooperation-models explore [--modules M] [--scenes N] [--live L] [--retired R] [--address A]
  cooperation-models replay  FILE

defaults: 2 modules, 3 scene identifiers, at most scenes-1 live, every retired one remembered,
as many threads as the machine has cores, depth first with symmetry reduction (breadth first
when symmetry is off or cannot apply, that is when fewer retired identifiers are remembered
than there are identifiers; --strategy bfs keeps symmetry on the sequential model's default
table, through canonical states: each successor is renamed to its representative, so breadth
first meets each class once, with the depth-first counts and without depth-first paths'
memory),
counterexamples saved under target/counterexamples. --table hashed lays every state's scenes
out in the hashed index from the first scene, under a colliding hash (same counts). An input
that changes nothing ends a path, and all such ends that fired one rule count as one state
(--keep-stalled counts each as its own, for cross-checking; same verdicts). The network
model (breadth first) defaults to 2 scene identifiers, 2 operators and --views ids: status
messages tell operators which scenes exist; --views statuses makes them carry the library's
whole statuses, decisions included, and lets owners abort a scene (complete for --operators 1;
with 2 operators it outgrows memory). --planner engine makes the planner a node's service
engine: reports go through a module's sync, commands are set_commands requests, statuses are
published when a change makes one due and read from the factors it writes (--fault, a fault
of the core, cannot be planted there). The rtc model's --modules is its number of interfaces,
taken in order from lane_change_left, lane_change_right, intersection,
static_obstacle_avoidance_left and static_obstacle_avoidance_right, from position
--first-interface (default 0; 3 for the avoidances); --quota Q gives the adapter a quota of Q
live scenes per interface (none by default). The check stops at the first violated
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
        Some((command, rest)) if command == "coverage" => parse(rest).and_then(|o| pairs::run(&o)),
        Some((command, rest)) if command == "simulate" => parse(rest).and_then(|o| swarm::run(&o)),
        Some((command, rest)) if command == "explore" => parse(rest).and_then(|o| explore(&o)),
        Some((command, [file])) if command == "replay" => replay(file),
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
