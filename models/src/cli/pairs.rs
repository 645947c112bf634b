//! `coverage`: the pairs of consecutive rules of `cooperation_models::check::coverage`, with live
//! progress, the pairs per scope and their list, a JSON record (`--write`, rewritten after
//! every level so that a run that dies leaves what it found) and a comparison with an earlier
//! record (`--against`).

use std::path::Path;
use std::sync::atomic::Ordering::Relaxed;
use std::time::{Duration, Instant};

use cooperation::Rule;
use cooperation_models::check::budget::{status_bytes, Halt, GIB};
use cooperation_models::check::coverage::{
    explore, Found, Pairs, Progress, Record, Scope, MAX_COVERED_SCENES,
};
use cooperation_models::SequentialModel;

use crate::{checks, Options, Which};

pub(crate) fn run(options: &Options) -> Result<bool, String> {
    if options.which != Which::Sequential {
        return Err("coverage measures the sequential model only".to_owned());
    }
    let model = checks::model(options)?;
    let symmetry = options.settings.symmetry;
    let threads = options.settings.threads.max(1);
    let bounds = model.bounds();
    let (plain, symmetric) = MAX_COVERED_SCENES;
    if bounds.scenes > if symmetry { symmetric } else { plain } {
        return Err(format!(
            "coverage takes at most {symmetric} scene identifiers with symmetry (--no-symmetry: \
             {plain}), not {}",
            bounds.scenes
        ));
    }
    println!(
        "coverage: sequential model, {} modules, {} scene identifiers, at most {} live, {} \
         retired remembered; {} inputs in every state; breadth first, {threads} thread(s), \
         symmetry {}{}",
        bounds.modules,
        bounds.scenes,
        bounds.live,
        bounds.retired,
        model.alphabet().len(),
        if symmetry { "on" } else { "off" },
        model
            .fault()
            .map(|f| format!(", fault {f:?} injected"))
            .unwrap_or_default()
    );
    let progress = Progress::default();
    let halt = Halt::new();
    let started = Instant::now();
    let (result, stopped) = std::thread::scope(|scope| {
        let worker = scope.spawn(|| explore(&model, symmetry, threads, &progress, &halt));
        let stopped = watch(options, &model, symmetry, &progress, &halt, started, || {
            worker.is_finished()
        });
        (worker.join(), stopped)
    });
    let found = match result {
        Ok(Ok(found)) => Ok(found),
        Ok(Err(error)) => Err(error.to_string()),
        Err(_) => Err("the search panicked".to_owned()),
    };
    let record = match &found {
        Ok(found) => record(&model, symmetry, found, stopped),
        Err(why) => {
            let partial = partial(&progress, started);
            record(&model, symmetry, &partial, Some(why.clone()))
        }
    };
    present(&record, options)
}

/// Polls the run every 100 ms until `done`: progress once a second on standard error, the
/// record rewritten after every level, and the halt set when a budget or the time runs out.
/// Returns what stopped the run, if anything did.
fn watch(
    options: &Options,
    model: &SequentialModel,
    symmetry: bool,
    progress: &Progress,
    halt: &Halt,
    started: Instant,
    done: impl Fn() -> bool,
) -> Option<String> {
    let mut stopped = None;
    let mut shown = Duration::ZERO;
    let mut levels = 0;
    while !done() {
        std::thread::sleep(Duration::from_millis(100));
        let elapsed = started.elapsed();
        if elapsed >= shown + Duration::from_secs(1) {
            shown = elapsed;
            report_progress(progress, elapsed);
        }
        let level = progress.levels.load(Relaxed);
        if level != levels {
            levels = level;
            if let Some(file) = &options.write {
                let found = partial(progress, started);
                let why = Some(format!("running: {levels} levels done"));
                let _ = write(file, &record(model, symmetry, &found, why));
            }
        }
        if stopped.is_none() {
            let over_time = options.stop.timeout.is_some_and(|limit| elapsed >= limit);
            stopped = if over_time {
                Some("the time limit".to_owned())
            } else {
                let states = progress.states.load(Relaxed);
                let resident = status_bytes("VmRSS:");
                options
                    .stop
                    .budget
                    .exceeded(resident, states)
                    .map(|e| e.to_string())
            };
            if stopped.is_some() {
                halt.set();
            }
        }
    }
    stopped
}

fn report_progress(progress: &Progress, elapsed: Duration) {
    let pairs = progress.pairs();
    let states = progress.states.load(Relaxed);
    eprintln!(
        "covering: level {}, {} states ({} in this level), {} transitions, pairs {} same / {} \
         different / {} not scene-specific, {:.0} states/s, {:.1} s, {:.2} GiB resident",
        progress.levels.load(Relaxed),
        states,
        progress.frontier.load(Relaxed),
        progress.transitions.load(Relaxed),
        pairs.count(Scope::Same),
        pairs.count(Scope::Different),
        pairs.count(Scope::Unscoped),
        states as f64 / elapsed.as_secs_f64().max(1e-9),
        elapsed.as_secs_f64(),
        status_bytes("VmRSS:").unwrap_or(0) as f64 / GIB as f64
    );
}

/// What the progress holds, as an incomplete result.
fn partial(progress: &Progress, started: Instant) -> Found {
    progress.found(false, started.elapsed())
}

fn record(
    model: &SequentialModel,
    symmetry: bool,
    found: &Found,
    stopped: Option<String>,
) -> Record {
    Record {
        bounds: model.bounds(),
        symmetry,
        fault: model.fault(),
        complete: found.complete && stopped.is_none(),
        stopped: stopped.or_else(|| (!found.complete).then(|| "unknown".to_owned())),
        states: found.states,
        concrete: found.concrete,
        arrivals: found.arrivals,
        transitions: found.transitions,
        renamed: found.renamed,
        levels: found.levels,
        seconds: found.elapsed.as_secs_f64(),
        peak_rss_bytes: status_bytes("VmHWM:"),
        counts: Scope::ALL.map(|scope| found.pairs.count(scope)),
        pairs: found.pairs,
    }
}

fn write(file: &Path, record: &Record) -> Result<(), String> {
    let text = serde_json::to_string_pretty(record).map_err(|e| e.to_string())?;
    std::fs::write(file, text + "\n").map_err(|e| format!("{}: {e}", file.display()))
}

fn bounds(record: &Record) -> String {
    let b = record.bounds;
    format!(
        "{} × {} ({} live, {} retired remembered)",
        b.modules, b.scenes, b.live, b.retired
    )
}

fn present(record: &Record, options: &Options) -> Result<bool, String> {
    println!(
        "\n{} states ({} before symmetry reduction), {} arrivals, {} transitions (and {} from \
         renamed states), {} levels, {:.1} s, peak {:.2} GiB resident",
        record.states,
        record.concrete,
        record.arrivals,
        record.transitions,
        record.renamed,
        record.levels,
        record.seconds,
        record.peak_rss_bytes.unwrap_or(0) as f64 / GIB as f64
    );
    println!("\n| scope | pairs of rules |\n|---|---|");
    for (scope, count) in Scope::ALL.iter().zip(record.counts) {
        println!("| {} | {count} |", scope.name());
    }
    println!("| any | {} |", any_scope(&record.pairs));
    println!("\n{}", listing(&record.pairs));
    if let Some(file) = &options.write {
        write(file, record)?;
        println!("written to {}", file.display());
    }
    if let Some(file) = &options.against {
        let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
        let other: Record =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", file.display()))?;
        compare(record, &other, file);
    }
    if let Some(why) = &record.stopped {
        println!(
            "incomplete: stopped by {why}; the pairs above are those found in the states \
             explored"
        );
    }
    Ok(record.complete)
}

/// How many ordered pairs of rules occur in some scope.
fn any_scope(pairs: &Pairs) -> usize {
    let mut rules: Vec<(Rule, Rule)> = pairs.iter().map(|(a, b, _)| (a, b)).collect();
    rules.dedup();
    rules.len()
}

/// One row per ordered pair of rules that occurs, a mark per scope it occurs in.
fn listing(pairs: &Pairs) -> String {
    let mut out = String::from(
        "| first rule | then | same scene | different scenes | not scene-specific |\n|---|---|---|---|---|\n",
    );
    for first in Rule::ALL {
        for then in Rule::ALL {
            let marks = Scope::ALL.map(|s| {
                if pairs.contains(first, then, s) {
                    "✓"
                } else {
                    ""
                }
            });
            if marks.iter().any(|m| !m.is_empty()) {
                let [same, different, unscoped] = marks;
                out += &format!("| {first} | {then} | {same} | {different} | {unscoped} |\n");
            }
        }
    }
    out
}

fn compare(here: &Record, there: &Record, file: &Path) {
    println!(
        "\ncompared with {} ({}{}):",
        file.display(),
        bounds(there),
        if there.complete { "" } else { ", incomplete" }
    );
    for (name, only) in [
        ("here, not there", here.pairs.without(&there.pairs)),
        ("there, not here", there.pairs.without(&here.pairs)),
    ] {
        println!("- {} pairs {name}", only.len());
        for (first, then, scope) in only.iter() {
            println!("  - {first} then {then}, {}", scope.name());
        }
    }
}
