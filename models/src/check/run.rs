//! Running a check: the checker's configuration, live progress, the property table, and the
//! shortest counterexample of each violated property.

use std::io::Write;
use std::time::{Duration, Instant};

use crate::check::budget::{status_bytes, Budget, Exceeded, Halt};

use stateright::report::{ReportData, ReportDiscovery, Reporter};
use stateright::{Checker, DiscoveryClassification, Expectation, HasDiscoveries, Model};

use core::fmt::Debug;
use core::hash::Hash;

use stateright::{Property, Representative};

use crate::check::trace::Trace;
use crate::model::sequential::SequentialModel;

/// A model this runner can check: it can narrow itself to one property (for the shortest
/// counterexample) and turn a path of actions into a trace a person and a test can replay.
pub trait Checkable: Model + Clone + Send + Sync + 'static
where
    Self::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    Self::Action: Debug + Clone + PartialEq + Send + Sync,
{
    /// The same model checking only the named property.
    #[must_use]
    fn focus(self, property: &'static str) -> Self;

    /// The trace of these actions from the initial state, for the named property.
    fn trace(&self, property: &'static str, actions: Vec<Self::Action>) -> Trace;

    /// The same model, stopped by `halt`: once it is set, the model offers no action and
    /// counts every state outside its boundary.
    #[must_use]
    fn with_halt(self, halt: Halt) -> Self;

    /// The same model returning every successor in canonical form, so that breadth-first
    /// search reduces by symmetry (`model::sequential`'s `canonical`); `None` if the model has
    /// no canonical form.
    fn canonical(self) -> Option<Self> {
        None
    }
}

impl Checkable for crate::NetworkModel {
    fn focus(self, property: &'static str) -> Self {
        Self::focus(self, property)
    }

    fn with_halt(self, halt: Halt) -> Self {
        Self::with_halt(self, halt)
    }

    fn trace(
        &self,
        property: &'static str,
        actions: Vec<crate::model::network::NetAction>,
    ) -> Trace {
        Trace::Network {
            bounds: self.bounds(),
            operators: self.operators(),
            views: self.views(),
            fault: self.fault(),
            planner: self.planner(),
            property: property.to_owned(),
            actions,
        }
    }
}

impl Checkable for SequentialModel {
    fn focus(self, property: &'static str) -> Self {
        Self::focus(self, property)
    }

    /// On the default table only (`SequentialModel::with_canonical_states`).
    fn canonical(self) -> Option<Self> {
        let model = self.with_canonical_states(true);
        model.canonical_states().then_some(model)
    }

    fn with_halt(self, halt: Halt) -> Self {
        Self::with_halt(self, halt)
    }

    fn trace(&self, property: &'static str, actions: Vec<usize>) -> Trace {
        let inputs = self.raw_inputs(&actions);
        Trace::Sequential {
            bounds: self.bounds(),
            table: self.table(),
            fault: self.fault(),
            property: property.to_owned(),
            inputs,
        }
    }
}

impl Checkable for crate::RtcModel {
    fn focus(self, property: &'static str) -> Self {
        Self::focus(self, property)
    }

    fn with_halt(self, halt: Halt) -> Self {
        Self::with_halt(self, halt)
    }

    fn trace(&self, property: &'static str, actions: Vec<usize>) -> Trace {
        Trace::Rtc {
            bounds: self.bounds(),
            fault: self.fault(),
            property: property.to_owned(),
            calls: actions
                .iter()
                .filter_map(|a| self.alphabet().get(*a).cloned())
                .collect(),
        }
    }
}

/// How to search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Depth first; applies symmetry reduction when asked.
    Dfs,
    /// Breadth first; reduces by symmetry through canonical states (stateright's BFS ignores
    /// its own symmetry reduction), where the model has them.
    Bfs,
}

/// A check's settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Settings {
    /// Worker threads.
    pub threads: usize,
    /// Search order.
    pub strategy: Strategy,
    /// Whether to reduce by renaming identifiers: depth first through the checker's symmetry
    /// reduction, breadth first by canonical states ([`Checkable::canonical`]; a model without
    /// them is searched unreduced, and the command line turns symmetry off for it).
    pub symmetry: bool,
}

/// When a check stops before it has explored everything.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stop {
    /// Go on after the first violated `always` property, to collect every violation (the
    /// default is to stop at the first).
    pub keep_going: bool,
    /// The memory and state budget.
    pub budget: Budget,
    /// The time limit, if any.
    pub timeout: Option<Duration>,
    /// Explore only paths of at most this many steps from an initial state, if set: a search
    /// that ends within the bound is complete to that depth, not beyond. Use one thread where
    /// the count matters: with more, a state first reached by a longer path may be cut off at
    /// the bound, so the states explored can vary between runs.
    pub depth: Option<usize>,
}

impl Stop {
    /// Stop at the first violation, within the default budget, with no time limit.
    #[must_use]
    pub fn first_violation() -> Self {
        Self {
            keep_going: false,
            budget: Budget::default(),
            timeout: None,
            depth: None,
        }
    }

    /// Collect every violation, within the default budget, with no time limit.
    #[must_use]
    pub fn every_violation() -> Self {
        Self {
            keep_going: true,
            ..Self::first_violation()
        }
    }
}

/// Why a search ended before it explored every state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// It explored every state.
    Complete,
    /// It stopped at the first violated `always` property.
    Violation,
    /// It used up its budget or its time.
    Exceeded(Exceeded),
}

/// What one property came to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// The property's name.
    pub name: &'static str,
    /// `always` or `sometimes`.
    pub expectation: Expectation,
    /// Whether the property is satisfied: an `always` without counterexample, a `sometimes`
    /// with an example.
    pub holds: bool,
    /// A counterexample of a violated `always` property: the shortest, unless searching for it
    /// would outgrow the budget, then the one the search found.
    pub counterexample: Option<Trace>,
    /// Whether the counterexample is the shortest one.
    pub shortest: bool,
}

/// The result of a complete check.
#[derive(Clone, Debug)]
pub struct Report {
    /// Distinct states (after symmetry reduction, when on).
    pub unique: usize,
    /// States generated, duplicates included.
    pub generated: usize,
    /// The deepest path.
    pub depth: usize,
    /// Wall time of the search (the counterexample searches after it not included).
    pub elapsed: Duration,
    /// Whether the search ran to completion (to [`Stop::depth`] steps, when that is set).
    pub complete: bool,
    /// The depth bound the search kept to, if any ([`Stop::depth`]).
    pub depth_bound: Option<usize>,
    /// How the search ended.
    pub ended: Ended,
    /// The process's peak resident memory, in bytes, where the system tells it.
    pub peak_bytes: Option<u64>,
    /// Every property's outcome, in the model's order.
    pub outcomes: Vec<Outcome>,
}

impl Report {
    /// Whether every property is satisfied and the search completed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.complete && self.outcomes.iter().all(|o| o.holds)
    }

    /// How many properties are satisfied, violated and, after an incomplete search, unknown.
    #[must_use]
    pub fn tally(&self) -> String {
        let sometimes = |o: &&Outcome| matches!(o.expectation, Expectation::Sometimes);
        let count = |f: &dyn Fn(&&Outcome) -> bool| self.outcomes.iter().filter(f).count();
        let satisfied = count(&|o| o.holds && (self.complete || sometimes(o)));
        let violated = count(&|o| !o.holds && !sometimes(o));
        let unreached = count(&|o| self.complete && !o.holds && sometimes(o));
        let unknown = self.outcomes.len() - satisfied - violated - unreached;
        let mut line = format!(
            "{satisfied} of {} properties satisfied, {violated} violated",
            self.outcomes.len()
        );
        if unreached > 0 {
            line += &format!(", {unreached} unreached");
        }
        if unknown > 0 {
            line += &format!(", {unknown} unknown (the search is incomplete)");
        }
        line
    }

    /// The property table, one line per property. After an incomplete search, a property with
    /// no discovery is "unknown": nothing is known of the states not explored.
    #[must_use]
    pub fn table(&self) -> String {
        let mut out = String::from("| result | kind | property |\n|---|---|---|\n");
        for outcome in &self.outcomes {
            let (kind, result) = match (&outcome.expectation, outcome.holds) {
                (Expectation::Sometimes, true) => ("sometimes", "reached"),
                (Expectation::Sometimes, false) if !self.complete => ("sometimes", "unknown"),
                (Expectation::Sometimes, false) => ("sometimes", "UNREACHED"),
                (_, true) if !self.complete => ("always", "unknown"),
                (_, true) => ("always", "holds"),
                (_, false) => ("always", "VIOLATED"),
            };
            out += &format!("| {result} | {kind} | {} |\n", outcome.name);
        }
        out
    }
}

/// Prints progress to a writer once a second: states, unique states, depth and rate.
pub struct Progress<W: Write> {
    writer: W,
    last: Option<(Duration, usize)>,
}

impl<W: Write> Progress<W> {
    /// Progress lines go to `writer`.
    pub const fn new(writer: W) -> Self {
        Self { writer, last: None }
    }
}

impl<W: Write, M: Model> Reporter<M> for Progress<W> {
    fn report_checking(&mut self, data: ReportData) {
        let (then, before) = self.last.unwrap_or_default();
        let seconds = (data.duration - then).as_secs_f64().max(1e-9);
        let rate = (data.unique_states.saturating_sub(before)) as f64 / seconds;
        let status = if data.done { "done" } else { "checking" };
        let _ = writeln!(
            self.writer,
            "{status}: states={}, unique={}, depth={}, {:.0} unique/s, {:.1} s",
            data.total_states,
            data.unique_states,
            data.max_depth,
            rate,
            data.duration.as_secs_f64()
        );
        self.last = Some((data.duration, data.unique_states));
    }

    fn report_discoveries(
        &mut self,
        _: &M,
        _: std::collections::BTreeMap<&'static str, ReportDiscovery<M>>,
    ) {
    }
}

/// Checks `model` to completion, collecting every violation, reporting progress to
/// `progress`, then finds the shortest counterexample of each violated property by a
/// breadth-first search for it alone.
pub fn check<M>(model: &M, settings: Settings, progress: &mut (impl Write + Send)) -> Report
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    check_for(model, settings, Stop::every_violation(), progress)
}

/// [`check`], ending as `stop` says: at the first violation unless it says to keep going, and
/// when the budget or the time runs out (the report then says the search did not complete,
/// why, and what it found by then).
pub fn check_for<M>(
    model: &M,
    settings: Settings,
    stop: Stop,
    progress: &mut (impl Write + Send),
) -> Report
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    let start = Instant::now();
    let halt = Halt::new();
    // Breadth first with symmetry: the model returns canonical states, for the search and the
    // shortest counterexamples alike.
    let canonical = (settings.symmetry && settings.strategy == Strategy::Bfs)
        .then(|| model.clone().canonical())
        .flatten();
    let model = canonical.as_ref().unwrap_or(model);
    let builder = model
        .clone()
        .with_halt(halt.clone())
        .checker()
        .threads(settings.threads.max(1));
    let builder = if stop.keep_going {
        builder
    } else {
        builder.finish_when(HasDiscoveries::AnyFailures)
    };
    let builder = if settings.symmetry && settings.strategy == Strategy::Dfs {
        builder.symmetry()
    } else {
        builder
    };
    // stateright counts the initial state as depth 1 and expands no state at the target depth.
    let builder = match stop.depth {
        Some(steps) => builder.target_max_depth(steps.saturating_add(1)),
        None => builder,
    };
    let checker = match settings.strategy {
        Strategy::Dfs => Box::new(builder.spawn_dfs()) as Box<dyn Checker<M> + Send + Sync>,
        Strategy::Bfs => Box::new(builder.spawn_bfs()),
    };
    let mut reporter = Progress::new(&mut *progress);
    let exceeded = watch(checker.as_ref(), &stop, &halt, start, &mut reporter);
    let searched = start.elapsed();
    halt.release();
    let (unique, generated, depth) = (
        checker.unique_state_count(),
        checker.state_count(),
        checker.max_depth(),
    );
    let found: std::collections::HashMap<&'static str, Vec<M::Action>> = checker
        .discoveries()
        .into_iter()
        .map(|(name, path)| (name, path.into_actions()))
        .collect();
    // The search's memory goes back before the counterexample searches start.
    drop(checker);
    let budget = Budget {
        memory_bytes: stop
            .budget
            .memory_bytes
            .max(status_bytes("VmRSS:").unwrap_or(0) + stop.budget.memory_bytes / 4),
        ..stop.budget
    };
    let outcomes = model
        .properties()
        .into_iter()
        .map(|property: Property<M>| {
            let path = found.get(property.name);
            let holds = match property.expectation {
                Expectation::Sometimes => path.is_some(),
                Expectation::Always | Expectation::Eventually => path.is_none(),
            };
            // The shortest counterexample if a search for it alone fits the budget, else the
            // one the search found.
            let violated = path.filter(|_| !matches!(property.expectation, Expectation::Sometimes));
            let shortest = violated.and_then(|_| shortest_within(model, property.name, budget));
            let found = shortest.is_some();
            let counterexample = shortest
                .or_else(|| violated.map(|actions| model.trace(property.name, actions.clone())));
            Outcome {
                name: property.name,
                expectation: property.expectation,
                holds,
                counterexample,
                shortest: found,
            }
        })
        .collect::<Vec<_>>();
    let violated = outcomes
        .iter()
        .any(|o| !o.holds && !matches!(o.expectation, Expectation::Sometimes));
    let ended = match exceeded {
        Some(exceeded) => Ended::Exceeded(exceeded),
        // Stopped at the first failure: the search may not have seen every state.
        None if violated && !stop.keep_going => Ended::Violation,
        None => Ended::Complete,
    };
    Report {
        unique,
        generated,
        depth,
        elapsed: searched,
        complete: ended == Ended::Complete,
        depth_bound: stop.depth,
        ended,
        peak_bytes: status_bytes("VmHWM:"),
        outcomes,
    }
}

/// Polls the running search once a second: reports progress, and halts it when it outgrows
/// the budget or the time. Returns once the search has ended, with what it exceeded.
fn watch<M: Model>(
    checker: &(dyn Checker<M> + Send + Sync),
    stop: &Stop,
    halt: &Halt,
    start: Instant,
    reporter: &mut impl Reporter<M>,
) -> Option<Exceeded> {
    let mut exceeded = None;
    let tick = Duration::from_millis(100);
    let mut next_report = start;
    loop {
        let done = checker.is_done();
        let now = Instant::now();
        if done || now >= next_report {
            reporter.report_checking(ReportData {
                total_states: checker.state_count(),
                unique_states: checker.unique_state_count(),
                max_depth: checker.max_depth(),
                duration: start.elapsed(),
                done,
            });
            next_report = now + Duration::from_secs(1);
        }
        if done {
            return exceeded;
        }
        if exceeded.is_none() {
            let over_time = stop.timeout.is_some_and(|limit| start.elapsed() >= limit);
            exceeded = if over_time {
                Some(Exceeded::Time)
            } else {
                let resident = status_bytes("VmRSS:");
                stop.budget.exceeded(resident, checker.unique_state_count())
            };
            if exceeded.is_some() {
                halt.set();
            }
        }
        std::thread::sleep(tick);
    }
}

/// The shortest path breaking the named `always` property: a one-thread breadth-first search
/// for that property alone, stopping at the first counterexample.
#[must_use]
pub fn shortest<M>(model: &M, property: &'static str) -> Option<Trace>
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    shortest_within(model, property, Budget::default())
}

/// [`shortest`], given up (`None`) if it would outgrow `budget`.
#[must_use]
pub fn shortest_within<M>(model: &M, property: &'static str, budget: Budget) -> Option<Trace>
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    first_discovery(
        model,
        property,
        HasDiscoveries::AnyFailures,
        budget,
        |found| matches!(found, DiscoveryClassification::Counterexample),
    )
}

/// The shortest path reaching the named `sometimes` property (a witness): a one-thread
/// breadth-first search for that property alone, stopping at the first example.
#[must_use]
pub fn witness<M>(model: &M, property: &'static str) -> Option<Trace>
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    first_discovery(
        model,
        property,
        HasDiscoveries::Any,
        Budget::default(),
        |found| matches!(found, DiscoveryClassification::Example),
    )
}

/// A one-thread breadth-first search for one property, stopping as `finish` says, returning the
/// discovery's trace if it is of the wanted kind.
fn first_discovery<M>(
    model: &M,
    property: &'static str,
    finish: HasDiscoveries,
    budget: Budget,
    wanted: fn(&DiscoveryClassification) -> bool,
) -> Option<Trace>
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    let halt = Halt::new();
    let checker = model
        .clone()
        .focus(property)
        .with_halt(halt.clone())
        .checker()
        .finish_when(finish)
        .spawn_bfs();
    let stop = Stop {
        keep_going: true,
        budget,
        timeout: None,
        depth: None,
    };
    let mut quiet = Progress::new(std::io::sink());
    watch(&checker, &stop, &halt, Instant::now(), &mut quiet);
    halt.release();
    let path = checker.discovery(property)?;
    wanted(&checker.discovery_classification(property))
        .then(|| model.trace(property, path.into_actions()))
}
