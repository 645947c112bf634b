//! `cooperation-models`: the exhaustive model check of the cooperation core.
//!
//! ```text
//! cooperation-models check   [--model sequential|network] [--modules M] [--scenes N] [--live L] [--retired R]
//!                            [--threads T] [--strategy dfs|bfs] [--no-symmetry]
//!                            [--fault NAME] [--out DIR] [--timeout SECONDS] [--summary]
//! cooperation-models reach   [--full] [--only BOUNDS] [--write FILE]
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

use cooperation_models::network::{COMMANDS_IN_FLIGHT, OPERATORS, STATUSES_IN_FLIGHT};
use cooperation_models::run::{check_for, Settings, Strategy};
use cooperation_models::trivial;

mod reach;
use cooperation_models::{Bounds, Fault, NetBounds, NetworkModel, SequentialModel, Trace};
use stateright::Model;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const USAGE: &str = "usage:
  cooperation-models check   [--model sequential|network] [--modules M] [--scenes N]
                             [--live L] [--retired R] [--threads T] [--strategy dfs|bfs]
                             [--no-symmetry] [--fault NAME] [--out DIR]
                             [--timeout SECONDS] [--summary]
  cooperation-models check   --model trivial [--threads T] [--bytes B]
  cooperation-models reach   [--full] [--only BOUNDS] [--write FILE]
  cooperation-models explore [--modules M] [--scenes N] [--live L] [--retired R] [--address A]
  cooperation-models replay  FILE
  cooperation-models diagrams [--check]
  cooperation-models traceability [--check]
  cooperation-models witnesses [--check]

defaults: 2 modules, 3 scene identifiers, at most scenes-1 live, every retired one remembered,
2 threads, depth first with symmetry reduction (breadth first when symmetry is off or cannot
apply, that is when fewer retired identifiers are remembered than there are identifiers),
counterexamples saved under target/counterexamples. Faults (sensitivity tests): ";

/// Which model to check.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Which {
    Sequential,
    Network,
    Trivial,
}

struct Options {
    which: Which,
    bounds: Bounds,
    settings: Settings,
    fault: Option<Fault>,
    out: PathBuf,
    address: String,
    timeout: Option<std::time::Duration>,
    summary: bool,
    bytes: usize,
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
    let mut timeout = None;
    let mut summary = false;
    let mut bytes = reach::TRIVIAL.bytes;
    let mut rest = args.iter();
    while let Some(flag) = rest.next() {
        if flag == "--no-symmetry" {
            settings.symmetry = false;
            continue;
        }
        if flag == "--summary" {
            summary = true;
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
                let found = Fault::ALL.into_iter().find(|f| format!("{f:?}") == *value);
                fault = Some(found.ok_or_else(|| format!("no fault is named {value:?}"))?);
            }
            "--out" => out = PathBuf::from(value),
            "--bytes" => bytes = number()?,
            "--timeout" => {
                timeout = Some(std::time::Duration::from_secs(number()? as u64));
            }
            "--model" => {
                which = match value.as_str() {
                    "sequential" => Which::Sequential,
                    "network" => Which::Network,
                    "trivial" => Which::Trivial,
                    other => {
                        return Err(format!(
                            "--model is sequential, network or trivial, not {other:?}"
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
        timeout,
        summary,
        bytes,
    })
}

fn model(options: &Options) -> Result<SequentialModel, String> {
    let model = SequentialModel::new(options.bounds).map_err(|e| e.to_string())?;
    Ok(match options.fault {
        Some(fault) => model.with_fault(fault),
        None => model,
    })
}

fn run_check(options: &Options) -> Result<bool, String> {
    match options.which {
        Which::Network => return run_network(options),
        Which::Trivial => return run_trivial(options),
        Which::Sequential => {}
    }
    let model = model(options)?;
    let Bounds {
        modules,
        scenes,
        live,
        retired,
    } = options.bounds;
    println!(
        "sequential model: {modules} modules, {scenes} scene identifiers, at most {live} live, \
         {retired} retired remembered; {} inputs in every state",
        model.alphabet().len()
    );
    let Settings {
        threads,
        strategy,
        symmetry,
    } = options.settings;
    println!(
        "checking to completion: {strategy:?}, {threads} thread(s), symmetry {}{}",
        if symmetry { "on" } else { "off" },
        options
            .fault
            .map_or(String::new(), |f| format!(", injected fault {f:?}"))
    );
    let report = check_for(
        &model,
        options.settings,
        options.timeout,
        &mut std::io::stderr(),
    );
    summarise(
        options,
        report.unique,
        report.generated,
        report.elapsed,
        report.complete,
    );
    present(&report, &options.out)
}

/// With `--summary`, one JSON line for `reach`: counts, time, completion and peak memory.
fn summarise(
    options: &Options,
    unique: usize,
    generated: usize,
    elapsed: std::time::Duration,
    complete: bool,
) {
    if options.summary {
        let summary = reach::Summary {
            unique,
            generated,
            seconds: elapsed.as_secs_f64(),
            complete,
            peak_rss_bytes: reach::peak_rss_bytes(),
        };
        println!("summary: {}", serde_json::json!(summary));
    }
}

fn run_trivial(options: &Options) -> Result<bool, String> {
    let model = trivial::TrivialModel {
        bytes: options.bytes,
        ..reach::TRIVIAL
    };
    println!(
        "trivial model: {} counters of {} values in a {}-byte state ({} states), breadth first, \
         {} thread(s)",
        model.digits,
        model.base,
        model.bytes,
        model.states(),
        options.settings.threads
    );
    let result = trivial::run(model, options.settings.threads);
    println!(
        "{} unique states, {} generated, {:.1} s",
        result.unique,
        result.generated,
        result.elapsed.as_secs_f64()
    );
    summarise(
        options,
        result.unique,
        result.generated,
        result.elapsed,
        result.complete,
    );
    Ok(result.complete && result.unique as u128 == model.states())
}

fn run_network(options: &Options) -> Result<bool, String> {
    let bounds = NetBounds {
        scenes: options.bounds.scenes,
    };
    let model = NetworkModel::new(bounds).map_err(|e| e.to_string())?;
    let model = match options.fault {
        Some(fault) => model.with_fault(fault),
        None => model,
    };
    println!(
        "network model: the planner and {OPERATORS} operators, {} scene identifiers, at most \
         {STATUSES_IN_FLIGHT} status message per operator and {COMMANDS_IN_FLIGHT} commands in flight, \
         delivered in any order, duplicated or lost",
        bounds.scenes
    );
    let settings = Settings {
        strategy: Strategy::Bfs,
        symmetry: false,
        ..options.settings
    };
    println!(
        "checking to completion: {:?}, {} thread(s), symmetry off{}",
        settings.strategy,
        settings.threads,
        options
            .fault
            .map_or(String::new(), |f| format!(", injected fault {f:?}"))
    );
    let report = check_for(&model, settings, options.timeout, &mut std::io::stderr());
    summarise(
        options,
        report.unique,
        report.generated,
        report.elapsed,
        report.complete,
    );
    present(&report, &options.out)
}

fn present(
    report: &cooperation_models::run::Report,
    out: &std::path::Path,
) -> Result<bool, String> {
    println!(
        "\n{} unique states, {} generated, depth {}, {:.1} s\n",
        report.unique,
        report.generated,
        report.depth,
        report.elapsed.as_secs_f64()
    );
    print!("{}", report.table());
    let held = report.outcomes.iter().filter(|o| o.holds).count();
    println!("\n{held} of {} properties satisfied", report.outcomes.len());
    for outcome in &report.outcomes {
        let Some(trace) = &outcome.counterexample else {
            continue;
        };
        println!("\nshortest counterexample, {} steps:", trace.len());
        print!("{}", trace.render().map_err(|e| e.to_string())?);
        let file = save(out, trace)?;
        let diagram = trace.sequence_diagram().map_err(|e| e.to_string())?;
        let mermaid = file.with_extension("mmd");
        std::fs::write(&mermaid, diagram).map_err(|e| format!("{}: {e}", mermaid.display()))?;
        println!(
            "saved as {} (sequence diagram: {})",
            file.display(),
            mermaid.display()
        );
    }
    Ok(report.passed())
}

fn save(dir: &std::path::Path, trace: &Trace) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let name: String = trace
        .property()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    let file = dir.join(format!("{}.json", name.trim_matches('-')));
    let text = serde_json::to_string_pretty(trace).map_err(|e| e.to_string())?;
    std::fs::write(&file, text + "\n").map_err(|e| format!("{}: {e}", file.display()))?;
    Ok(file)
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
    let model = model(options)?;
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
    let usage = format!("{USAGE}{}", faults.join(", "));
    let result = match args.split_first() {
        Some((command, rest)) if command == "check" => parse(rest).and_then(|o| run_check(&o)),
        Some((command, rest)) if command == "reach" => reach::run(rest),
        Some((command, rest)) if command == "explore" => parse(rest).and_then(|o| explore(&o)),
        Some((command, [file])) if command == "replay" => replay(file),
        Some((command, rest)) if command == "diagrams" => diagrams(rest),
        Some((command, rest)) if command == "traceability" => traceability(rest),
        Some((command, rest)) if command == "witnesses" => witnesses(rest),
        Some((command, _)) if command == "help" || command == "--help" => {
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
