//! `simulate`: the swarm of random walks of `cooperation_models::check::simulate`, with live progress,
//! how often each rule fired, every property's outcome, and a violating walk's trace saved.

use std::time::{Duration, Instant};

use cooperation::Rule;
use cooperation_models::check::simulate::{self, Findings, Progress, Swarm};
use stateright::{Expectation, Model};

use crate::{checks, Options};

/// Inputs per walk unless `--depth` says otherwise.
pub(crate) const DEPTH: usize = 1_000;

/// Above this many live scenes a scene table uses its hashed index (the library's `SMALL`).
const SMALL_TABLE: usize = 16;

pub(crate) fn run(options: &Options) -> Result<bool, String> {
    let model = checks::model(options)?;
    let swarm = Swarm {
        seeds: options.seeds.clone(),
        depth: options.stop.depth.unwrap_or(DEPTH),
        threads: options.settings.threads,
    };
    let bounds = model.bounds();
    println!(
        "swarm: {} modules, {} scene identifiers, at most {} live, {} retired remembered; {} \
         inputs in every state; seeds {}..{}, {} inputs a walk, {} thread(s){}",
        bounds.modules,
        bounds.scenes,
        bounds.live,
        bounds.retired,
        model.alphabet().len(),
        swarm.seeds.start,
        swarm.seeds.end,
        swarm.depth,
        swarm.threads,
        model
            .fault()
            .map(|f| format!(", fault {f:?} injected"))
            .unwrap_or_default()
    );
    let progress = Progress::default();
    let found = std::thread::scope(|scope| {
        let worker = scope.spawn(|| simulate::run(&model, &swarm, &progress));
        let started = Instant::now();
        let mut shown = Duration::ZERO;
        while !worker.is_finished() {
            std::thread::sleep(Duration::from_millis(100));
            let elapsed = started.elapsed();
            if elapsed >= shown + Duration::from_secs(1) {
                shown = elapsed;
                report_progress(&progress, elapsed);
            }
        }
        worker.join()
    })
    .map_err(|_| "a simulation worker panicked".to_owned())?
    .map_err(|e| e.to_string())?;
    present(&model, &found, options)
}

fn report_progress(progress: &Progress, elapsed: Duration) {
    use std::sync::atomic::Ordering::Relaxed;
    let (walks, states) = (progress.walks.load(Relaxed), progress.states.load(Relaxed));
    eprintln!(
        "simulating: walks={walks}, states={states}, {:.0} states/s, {:.1} s",
        states as f64 / elapsed.as_secs_f64().max(1e-9),
        elapsed.as_secs_f64()
    );
}

fn present(
    model: &cooperation_models::SequentialModel,
    found: &Findings,
    options: &Options,
) -> Result<bool, String> {
    let seconds = found.elapsed.as_secs_f64().max(1e-9);
    println!(
        "\n{} walks, {} states in {:.1} s: {:.1} walks/s, {:.0} states/s",
        found.walks,
        found.states,
        found.elapsed.as_secs_f64(),
        found.walks as f64 / seconds,
        found.states as f64 / seconds
    );
    println!(
        "most scenes live at once: {} (more than {SMALL_TABLE}: the hashed scene index); \
         registrations refused at the scene limit: {}; retirements that forgot an identifier: {}",
        found.most_live,
        found.fired(Rule::RegisterFull),
        found.forgetting
    );
    println!("\n| rule | fired |\n|---|---|");
    for rule in Rule::ALL {
        println!("| {} | {} |", rule.tag(), found.fired(rule));
    }
    println!("\n| result | kind | property |\n|---|---|---|");
    let violated = found.violation.as_ref().map(|v| v.property);
    for property in model.properties() {
        let (result, kind) = match property.expectation {
            Expectation::Always if violated == Some(property.name) => ("VIOLATED", "always"),
            Expectation::Always => ("holds", "always"),
            _ if found.reached.contains(&property.name) => ("reached", "sometimes"),
            _ => ("not reached", "sometimes"),
        };
        println!("| {result} | {kind} | {} |", property.name);
    }
    let Some(violation) = &found.violation else {
        println!(
            "\nno property violated in {} walks (random walks: a sample of the space, not all \
             of it)",
            found.walks
        );
        return Ok(true);
    };
    println!(
        "\nstopped at the first violation: walk {} (`--seeds {}..{}` takes it again), {} steps:",
        violation.seed,
        violation.seed,
        violation.seed + 1,
        violation.trace.len()
    );
    print!("{}", violation.trace.render().map_err(|e| e.to_string())?);
    let file = checks::save(&options.out, &violation.trace)?;
    println!(
        "saved as {} (`cooperation-models replay` replays it)",
        file.display()
    );
    Ok(false)
}
