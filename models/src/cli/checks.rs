//! `check`: builds the model the options name, checks it, prints the report and saves the
//! counterexamples.

use std::path::PathBuf;

use cooperation::TableLayout;
use cooperation_models::model::network::{
    PlannerKind, Views, COMMANDS_IN_FLIGHT, STATUSES_IN_FLIGHT,
};
use core::fmt::Debug;
use core::hash::Hash;

use cooperation_models::check::run::{check_for, Checkable, Ended, Settings, Strategy};
use cooperation_models::{
    model::trivial, Bounds, Fault, NetBounds, NetworkModel, RtcBounds, RtcFault, RtcModel,
    SequentialModel, Trace,
};
use stateright::Representative;

use cooperation_models::check::summary::{Summary, PREFIX};

use crate::{Options, Which};

/// The fault the options name, of the kind a model takes.
fn fault<F: Copy + core::fmt::Debug>(options: &Options, all: &[F]) -> Result<Option<F>, String> {
    let Some(name) = &options.fault else {
        return Ok(None);
    };
    all.iter()
        .copied()
        .find(|f| format!("{f:?}") == *name)
        .map(Some)
        .ok_or_else(|| format!("this model has no fault named {name:?}"))
}

/// ", injected fault NAME", or nothing.
fn injected(options: &Options) -> String {
    options
        .fault
        .as_ref()
        .map_or(String::new(), |f| format!(", injected fault {f}"))
}

/// Runs `check` as the options say; `Ok(true)` if every property is satisfied and the search
/// completed.
pub(crate) fn run(options: &Options) -> Result<bool, String> {
    match options.which {
        Which::Network => run_network(options),
        Which::Rtc => run_rtc(options),
        Which::Trivial => run_trivial(options),
        Which::Sequential => run_sequential(options),
    }
}

/// The sequential model the options describe.
pub(crate) fn model(options: &Options) -> Result<SequentialModel, String> {
    let model = SequentialModel::new(options.bounds)
        .map_err(|e| e.to_string())?
        .with_table(options.table)
        .with_stalled_merged(!options.keep_stalled);
    Ok(match fault(options, &Fault::ALL)? {
        Some(fault) => model.with_fault(fault),
        None => model,
    })
}

fn run_sequential(options: &Options) -> Result<bool, String> {
    let model = model(options)?;
    let Bounds {
        modules,
        scenes,
        live,
        retired,
    } = options.bounds;
    println!(
        "sequential model: {modules} modules, {scenes} scene identifiers, at most {live} live, \
         {retired} retired remembered; {} inputs in every state; scene table {}",
        model.alphabet().len(),
        match options.table {
            TableLayout::Adaptive => "adaptive (a sorted vector at these sizes)",
            TableLayout::Colliding => "hashed from the first scene, under a colliding hash",
        }
    );
    check_and_present(&model, options.settings, options)
}

fn run_rtc(options: &Options) -> Result<bool, String> {
    let Bounds {
        modules: interfaces,
        scenes,
        live,
        retired,
    } = options.bounds;
    let bounds = RtcBounds {
        interfaces,
        first_interface: options.first_interface,
        scenes,
        live,
        retired,
        quota: options.quota,
    };
    let model = RtcModel::new(bounds).map_err(|e| e.to_string())?;
    let model = match fault(options, &RtcFault::ALL)? {
        Some(fault) => model.with_fault(fault),
        None => model,
    };
    println!(
        "rtc model: {interfaces} interfaces ({}), {scenes} scene identifiers, at most {live} \
         live, {retired} retired remembered{}; {} calls in every state",
        model.names().join(", "),
        options.quota.map_or_else(String::new, |quota| format!(
            ", at most {quota} per interface"
        )),
        model.alphabet().len()
    );
    check_and_present(&model, options.settings, options)
}

/// With `--summary`, one JSON line for `reach`: counts, time, what stopped an incomplete
/// search, and peak memory.
fn summarise(
    options: &Options,
    unique: usize,
    generated: usize,
    elapsed: std::time::Duration,
    stopped: Option<String>,
) {
    if options.summary {
        let summary = Summary {
            unique,
            generated,
            seconds: elapsed.as_secs_f64(),
            complete: stopped.is_none(),
            stopped,
            peak_rss_bytes: cooperation_models::check::budget::status_bytes("VmHWM:"),
        };
        println!("{PREFIX}{}", serde_json::json!(summary));
    }
}

fn run_trivial(options: &Options) -> Result<bool, String> {
    let model = trivial::TrivialModel {
        bytes: options.bytes,
        ..trivial::TrivialModel::REACH
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
        (!result.complete).then(|| "the time limit".to_owned()),
    );
    Ok(result.complete && result.unique as u128 == model.states())
}

fn run_network(options: &Options) -> Result<bool, String> {
    let bounds = NetBounds {
        scenes: options.bounds.scenes,
    };
    let model = NetworkModel::new(bounds)
        .and_then(|model| model.with_operators(options.operators))
        .map_err(|e| e.to_string())?
        .with_views(options.views)
        .with_planner(options.planner);
    let through_engine = options.planner != PlannerKind::Core;
    let model = match fault(options, &Fault::ALL)? {
        Some(fault) if through_engine => {
            return Err(format!(
                "--fault {fault:?} is a fault of the core's transition, which the engine calls \
                 itself: it cannot be planted with --planner engine"
            ))
        }
        Some(fault) => model.with_fault(fault),
        None => model,
    };
    let operators = model.operators();
    println!(
        "network model: the planner{} and {operators} operator{}, {} scene identifiers, at most \
         {STATUSES_IN_FLIGHT} status message per operator and {COMMANDS_IN_FLIGHT} commands in flight, \
         delivered in any order, duplicated or lost; operators are told {}",
        if through_engine {
            " (the service engine, publishing when a change makes a publication due: --planner engine)"
        } else {
            ""
        },
        if operators == 1 { "" } else { "s" },
        bounds.scenes,
        match (options.views, through_engine) {
            (Views::Identifiers, _) => "which scenes exist (--views ids)",
            (Views::Statuses, false) => "the library's statuses, decisions included (--views statuses)",
            (Views::Statuses, true) => "the statuses the engine's factors carry, decisions included (--views statuses)",
        }
    );
    let settings = Settings {
        strategy: Strategy::Bfs,
        symmetry: false,
        ..options.settings
    };
    check_and_present(&model, settings, options)
}

/// Checks `model` to completion under `settings` and the options' stop conditions, printing
/// the settings first and the report, counterexamples included, after.
fn check_and_present<M>(model: &M, settings: Settings, options: &Options) -> Result<bool, String>
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    let Settings {
        threads,
        strategy,
        symmetry,
    } = settings;
    println!(
        "checking to completion: {strategy:?}, {threads} thread(s), symmetry {}{}",
        match (symmetry, strategy) {
            (false, _) => "off",
            (true, Strategy::Dfs) => "on",
            (true, Strategy::Bfs) => "on (canonical states)",
        },
        injected(options)
    );
    let report = check_for(model, settings, options.stop, &mut std::io::stderr());
    summarise(
        options,
        report.unique,
        report.generated,
        report.elapsed,
        match report.ended {
            _ if report.complete => None,
            Ended::Complete => Some("its depth bound".to_owned()),
            Ended::Violation => Some("a violated property".to_owned()),
            Ended::Exceeded(exceeded) => Some(exceeded.to_string()),
        },
    );
    present(&report, &options.out)
}

fn present(
    report: &cooperation_models::check::run::Report,
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
    println!("\n{}", report.tally());
    match report.ended {
        Ended::Complete => {
            if let Some(steps) = report.depth_bound {
                println!("complete to depth {steps} only (--depth): longer paths are unchecked");
            }
        }
        Ended::Violation => println!(
            "incomplete: stopped at the first violated property (--keep-going collects every \
             violation)"
        ),
        Ended::Exceeded(exceeded) => println!(
            "incomplete: stopped after reaching {exceeded}; the states not explored are \
             unchecked"
        ),
    }
    for outcome in &report.outcomes {
        let Some(trace) = &outcome.counterexample else {
            continue;
        };
        let which = if outcome.shortest {
            "shortest counterexample"
        } else {
            "counterexample (the search for a shorter one would outgrow the budget)"
        };
        println!("\n{which}, {} steps:", trace.len());
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

pub(crate) fn save(dir: &std::path::Path, trace: &Trace) -> Result<PathBuf, String> {
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
