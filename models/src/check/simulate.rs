//! Swarm simulation: random walks through the sequential model at sizes no exhaustive search
//! reaches (8 modules, 64 identifiers, 32 live, a retired set that forgets), with every property
//! of the model checked in every state a walk visits.
//!
//! A walk is a function of the model and its seed alone: it draws its inputs from its own
//! generator (SplitMix64) seeded with the walk's number, and reads no clock and no shared state.
//! So seeds are the unit of work: any set of seeds gives the same walks on any machine and with
//! any number of threads, disjoint seed ranges on separate machines make one distributed run,
//! and a violating walk is found again from its seed and replays from its saved trace.

use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use cooperation::{Input, Rule};
use stateright::{Expectation, Model, Property};

use crate::check::trace::Trace;
use crate::model::ids::ModelError;
use crate::model::sequential::{SequentialModel, Step};

/// Which walks to take.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Swarm {
    /// One walk per seed.
    pub seeds: Range<u64>,
    /// Inputs per walk.
    pub depth: usize,
    /// Worker threads; each takes every `threads`-th seed.
    pub threads: usize,
}

/// A walk's input generator: SplitMix64, small, fast and the same everywhere.
struct Generator(u64);

impl Generator {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number below `n` (`n` at least 1); the bias of the remainder is below 2^-50 for any
    /// alphabet this model has.
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// A violated `always` property: the walk that broke it, and the path to the first state that
/// breaks it, which replays (`cooperation-models replay`).
#[derive(Clone, Debug)]
pub struct Violation {
    /// The property.
    pub property: &'static str,
    /// The walk's seed.
    pub seed: u64,
    /// The inputs from the initial state to the violating one.
    pub trace: Trace,
}

/// What the walks found.
#[derive(Clone, Debug, Default)]
pub struct Findings {
    /// Walks completed (a walk that found a violation counts).
    pub walks: u64,
    /// States visited, the initial states included.
    pub states: u64,
    /// How often each rule of [`Rule::ALL`] fired, in that order.
    pub fired: Vec<u64>,
    /// The `sometimes` properties some walk reached, by name.
    pub reached: Vec<&'static str>,
    /// The most scenes live at once in any state visited.
    pub most_live: usize,
    /// Steps after which the core remembered fewer retired identifiers than before it although
    /// it had retired one (it forgot the oldest to make room).
    pub forgetting: u64,
    /// The violation of the walk with the lowest seed among those that found one, if any.
    pub violation: Option<Violation>,
    /// Wall time.
    pub elapsed: Duration,
}

impl Findings {
    fn merge(&mut self, other: Self) {
        self.walks += other.walks;
        self.states += other.states;
        if self.fired.len() < other.fired.len() {
            self.fired.resize(other.fired.len(), 0);
        }
        for (mine, theirs) in self.fired.iter_mut().zip(other.fired) {
            *mine += theirs;
        }
        for name in other.reached {
            if !self.reached.contains(&name) {
                self.reached.push(name);
            }
        }
        self.most_live = self.most_live.max(other.most_live);
        self.forgetting += other.forgetting;
        self.violation = match (self.violation.take(), other.violation) {
            (Some(a), Some(b)) => Some(if b.seed < a.seed { b } else { a }),
            (a, b) => a.or(b),
        };
    }

    /// How often `rule` fired.
    #[must_use]
    pub fn fired(&self, rule: Rule) -> u64 {
        Rule::ALL
            .iter()
            .position(|r| *r == rule)
            .and_then(|i| self.fired.get(i))
            .copied()
            .unwrap_or(0)
    }
}

/// Live progress, shared by the workers: walks and states so far.
#[derive(Debug, Default)]
pub struct Progress {
    /// Walks completed.
    pub walks: AtomicU64,
    /// States visited.
    pub states: AtomicU64,
}

/// Takes the walks of `swarm` through `model`, checking every property of the model in every
/// state visited; stops early (every worker, after its current walk) once a walk violates an
/// `always` property. `progress` is updated after every walk, for a caller that reports it.
///
/// # Errors
/// If the model's initial state cannot be built (never, for valid bounds).
pub fn run(
    model: &SequentialModel,
    swarm: &Swarm,
    progress: &Progress,
) -> Result<Findings, ModelError> {
    let started = Instant::now();
    let properties = model.properties();
    let stop = AtomicBool::new(false);
    let threads = swarm.threads.max(1);
    let results = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for worker in 0..threads {
            let (properties, stop, results) = (&properties, &stop, &results);
            scope.spawn(move || {
                let mut found = Findings {
                    fired: vec![0; Rule::ALL.len()],
                    ..Findings::default()
                };
                let seeds = swarm.seeds.clone().skip(worker).step_by(threads);
                let mut outcome = Ok(());
                for seed in seeds {
                    if stop.load(Ordering::Relaxed) {
                        break;
                    }
                    let before = found.states;
                    outcome = walk(model, properties, seed, swarm.depth, &mut found);
                    progress.walks.fetch_add(1, Ordering::Relaxed);
                    progress
                        .states
                        .fetch_add(found.states - before, Ordering::Relaxed);
                    if outcome.is_err() || found.violation.is_some() {
                        stop.store(true, Ordering::Relaxed);
                        break;
                    }
                }
                if let Ok(mut all) = results.lock() {
                    all.push(outcome.map(|()| found));
                }
            });
        }
    });
    let mut total = Findings {
        fired: vec![0; Rule::ALL.len()],
        ..Findings::default()
    };
    let all = results.into_inner().unwrap_or_default();
    for found in all {
        total.merge(found?);
    }
    total.elapsed = started.elapsed();
    Ok(total)
}

/// One walk: `depth` inputs drawn from the model's alphabet by the seed's generator, every
/// property evaluated in every state. A stalled step (its core and history are its
/// predecessor's) is evaluated for the rules' reachability only: every other property reads the
/// core and the history, and was evaluated on the predecessor (the argument of
/// `docs/models.md`, *Reductions*).
fn walk(
    model: &SequentialModel,
    properties: &[Property<SequentialModel>],
    seed: u64,
    depth: usize,
    found: &mut Findings,
) -> Result<(), ModelError> {
    let mut generator = Generator(seed);
    let alphabet = model.alphabet();
    let mut step = model
        .initial()
        .map_err(|e| ModelError::Bounds(e.to_string()))?;
    let mut inputs = Vec::with_capacity(depth);
    found.walks += 1;
    loop {
        found.states += 1;
        found.most_live = found.most_live.max(step.core.scene_count());
        if let Some(property) = evaluate(model, properties, &step, found) {
            found.violation = Some(Violation {
                property,
                seed,
                trace: Trace::Sequential {
                    bounds: model.bounds(),
                    table: model.table(),
                    fault: model.fault(),
                    property: property.to_owned(),
                    inputs,
                },
            });
            return Ok(());
        }
        if inputs.len() >= depth {
            return Ok(());
        }
        let Some(input) = choose(&mut generator, alphabet) else {
            return Ok(());
        };
        let next = model.step(&step, input);
        if let Some(slot) = next
            .last
            .and_then(|rule| Rule::ALL.iter().position(|r| *r == rule))
            .and_then(|i| found.fired.get_mut(i))
        {
            *slot += 1;
        }
        if forgot(&step, &next) {
            found.forgetting += 1;
        }
        inputs.push(input.clone());
        step = next;
    }
}

/// One tick in this many inputs of a walk, on average: rare, yet often enough for scenes whose
/// owner stopped updating them to expire.
pub const TICK_EVERY: usize = 256;

/// The next input: time passes with probability `1 / TICK_EVERY`, else any input of the
/// alphabet, uniformly. The alphabet has one tick among thousands of inputs at large bounds, so
/// drawn uniformly a scene would almost never expire; with a tick every few hundred inputs,
/// scenes whose owner did not update them in time do (the TTL is one tick).
fn choose<'a>(generator: &mut Generator, alphabet: &'a [Input]) -> Option<&'a Input> {
    if generator.below(TICK_EVERY) == 0 {
        if let Some(tick) = alphabet.iter().rfind(|i| matches!(i, Input::Tick { .. })) {
            return Some(tick);
        }
    }
    alphabet.get(generator.below(alphabet.len()))
}

/// Evaluates the properties on `step`: records the `sometimes` ones it reaches, and gives the
/// first `always` one it violates.
fn evaluate(
    model: &SequentialModel,
    properties: &[Property<SequentialModel>],
    step: &Step,
    found: &mut Findings,
) -> Option<&'static str> {
    for property in properties {
        match property.expectation {
            Expectation::Always => {
                if !step.stalled && !(property.condition)(model, step) {
                    return Some(property.name);
                }
            }
            Expectation::Sometimes | Expectation::Eventually => {
                if !found.reached.contains(&property.name) && (property.condition)(model, step) {
                    found.reached.push(property.name);
                }
            }
        }
    }
    None
}

/// Whether the step from `from` to `to` retired an identifier and forgot an older one.
fn forgot(from: &Step, to: &Step) -> bool {
    let retired = |step: &Step| step.core.retired_oldest_first().count();
    let newly = to.core.scene_count() < from.core.scene_count() || retired(to) > retired(from);
    newly
        && from
            .core
            .retired_oldest_first()
            .any(|(id, _)| to.core.retirement(id).is_none())
}
