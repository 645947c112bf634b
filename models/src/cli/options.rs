//! The checker command's options: every flag, its default, and the checks a combination must
//! pass before anything runs.

use std::path::PathBuf;

use cooperation::TableLayout;
use cooperation_models::check::budget::GIB;
use cooperation_models::check::run::{Settings, Stop, Strategy};
use cooperation_models::model::network::PlannerKind;
use cooperation_models::model::trivial::TrivialModel;
use cooperation_models::{Bounds, Fault, RtcFault, Views};

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
    pub(crate) quota: Option<usize>,
    pub(crate) views: Views,
    pub(crate) planner: PlannerKind,
    pub(crate) seeds: std::ops::Range<u64>,
    pub(crate) write: Option<PathBuf>,
    pub(crate) against: Option<PathBuf>,
}

pub(crate) fn parse(args: &[String]) -> Result<Options, String> {
    let mut bounds = Bounds::new(2, 3);
    let (mut live, mut retired) = (None, None);
    let mut settings = Settings {
        threads: default_threads(),
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
    let mut bytes = TrivialModel::REACH.bytes;
    let mut operators = cooperation_models::model::network::OPERATORS;
    let mut first_interface = 0;
    let mut quota = None;
    let mut views = Views::Identifiers;
    let mut planner = PlannerKind::Core;
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
            "--quota" => quota = Some(number()?),
            "--views" => {
                views = match value.as_str() {
                    "ids" => Views::Identifiers,
                    "statuses" => Views::Statuses,
                    other => return Err(format!("--views is ids or statuses, not {other:?}")),
                };
            }
            "--planner" => {
                planner = match value.as_str() {
                    "core" => PlannerKind::Core,
                    "engine" => PlannerKind::Engine {
                        written_fault: None,
                    },
                    other => return Err(format!("--planner is core or engine, not {other:?}")),
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
    // Symmetry defaults to depth first; without symmetry, breadth first keeps memory flat where
    // depth-first paths grow long. Breadth first reduces by symmetry through canonical states,
    // which the sequential model has on the default table only (a renamed state's table is
    // built anew, without the hashed table's history).
    settings.strategy = strategy.unwrap_or(if settings.symmetry {
        Strategy::Dfs
    } else {
        Strategy::Bfs
    });
    let canonical = which == Which::Sequential && table == TableLayout::Adaptive;
    if settings.strategy == Strategy::Bfs && !canonical {
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
        quota,
        views,
        planner,
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

/// As many threads as the machine runs at once (2 if it cannot say): a bigger machine checks
/// faster without being told. The counts do not depend on it.
fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(2, std::num::NonZeroUsize::get)
}
