//! Running a check: the checker's configuration, live progress, the property table, and the
//! shortest counterexample of each violated property.

use std::io::Write;
use std::time::{Duration, Instant};

use stateright::report::{ReportData, ReportDiscovery, Reporter};
use stateright::{Checker, DiscoveryClassification, Expectation, HasDiscoveries, Model};

use core::fmt::Debug;
use core::hash::Hash;

use stateright::{Property, Representative};

use crate::sequential::SequentialModel;
use crate::trace::Trace;

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
}

impl Checkable for crate::NetworkModel {
    fn focus(self, property: &'static str) -> Self {
        Self::focus(self, property)
    }

    fn trace(&self, property: &'static str, actions: Vec<crate::network::NetAction>) -> Trace {
        Trace::Network {
            bounds: self.bounds(),
            fault: self.fault(),
            property: property.to_owned(),
            actions,
        }
    }
}

impl Checkable for SequentialModel {
    fn focus(self, property: &'static str) -> Self {
        Self::focus(self, property)
    }

    fn trace(&self, property: &'static str, actions: Vec<usize>) -> Trace {
        let inputs = actions
            .iter()
            .filter_map(|a| self.alphabet().get(*a).cloned())
            .collect();
        Trace::Sequential {
            bounds: self.bounds(),
            fault: self.fault(),
            property: property.to_owned(),
            inputs,
        }
    }
}

/// How to search.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Depth first; applies symmetry reduction when asked.
    Dfs,
    /// Breadth first; ignores symmetry (stateright's BFS does).
    Bfs,
}

/// A check's settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Settings {
    /// Worker threads.
    pub threads: usize,
    /// Search order.
    pub strategy: Strategy,
    /// Whether to reduce by renaming identifiers (DFS only).
    pub symmetry: bool,
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
    /// The shortest counterexample of a violated `always` property.
    pub counterexample: Option<Trace>,
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
    /// Whether the search ran to completion.
    pub complete: bool,
    /// Every property's outcome, in the model's order.
    pub outcomes: Vec<Outcome>,
}

impl Report {
    /// Whether every property is satisfied and the search completed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.complete && self.outcomes.iter().all(|o| o.holds)
    }

    /// The property table, one line per property.
    #[must_use]
    pub fn table(&self) -> String {
        let mut out = String::from("| result | kind | property |\n|---|---|---|\n");
        for outcome in &self.outcomes {
            let (kind, result) = match (&outcome.expectation, outcome.holds) {
                (Expectation::Sometimes, true) => ("sometimes", "reached"),
                (Expectation::Sometimes, false) => ("sometimes", "UNREACHED"),
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

/// Checks `model` to completion, reporting progress to `progress`, then finds the shortest
/// counterexample of each violated property by a breadth-first search for it alone.
pub fn check<M>(model: &M, settings: Settings, progress: &mut (impl Write + Send)) -> Report
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    check_for(model, settings, None, progress)
}

/// [`check`], giving up after `limit` (the report then says the search did not complete, and
/// what it reached by then).
pub fn check_for<M>(
    model: &M,
    settings: Settings,
    limit: Option<Duration>,
    progress: &mut (impl Write + Send),
) -> Report
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    let start = Instant::now();
    let builder = model.clone().checker().threads(settings.threads.max(1));
    let builder = match limit {
        Some(limit) => builder.timeout(limit),
        None => builder,
    };
    let builder = if settings.symmetry {
        builder.symmetry()
    } else {
        builder
    };
    let mut reporter = Progress::new(&mut *progress);
    let checker = match settings.strategy {
        Strategy::Dfs => {
            Box::new(builder.spawn_dfs().join_and_report(&mut reporter)) as Box<dyn Checker<M>>
        }
        Strategy::Bfs => Box::new(builder.spawn_bfs().join_and_report(&mut reporter)),
    };
    // The checker's own clock at its final report: the search alone, without the wait for the
    // reporter's next one-second tick that `join_and_report` adds.
    let searched = reporter
        .last
        .map_or_else(|| start.elapsed(), |(duration, _)| duration);
    let discoveries = checker.discoveries();
    let outcomes = model
        .properties()
        .into_iter()
        .map(|property: Property<M>| {
            let found = discoveries.contains_key(property.name);
            let holds = match property.expectation {
                Expectation::Sometimes => found,
                Expectation::Always | Expectation::Eventually => !found,
            };
            let counterexample = (!holds
                && !matches!(property.expectation, Expectation::Sometimes))
            .then(|| shortest(model, property.name))
            .flatten();
            Outcome {
                name: property.name,
                expectation: property.expectation,
                holds,
                counterexample,
            }
        })
        .collect();
    Report {
        unique: checker.unique_state_count(),
        generated: checker.state_count(),
        depth: checker.max_depth(),
        elapsed: searched,
        // A time limit also ends the search with `is_done()`; a search that ran for the whole
        // limit is counted as stopped, not complete.
        complete: checker.is_done() && limit.map_or(true, |limit| searched < limit),
        outcomes,
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
    first_discovery(model, property, HasDiscoveries::AnyFailures, |found| {
        matches!(found, DiscoveryClassification::Counterexample)
    })
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
    first_discovery(model, property, HasDiscoveries::Any, |found| {
        matches!(found, DiscoveryClassification::Example)
    })
}

/// A one-thread breadth-first search for one property, stopping as `finish` says, returning the
/// discovery's trace if it is of the wanted kind.
fn first_discovery<M>(
    model: &M,
    property: &'static str,
    finish: HasDiscoveries,
    wanted: fn(&DiscoveryClassification) -> bool,
) -> Option<Trace>
where
    M: Checkable,
    M::State: Hash + Debug + Clone + PartialEq + Send + Sync + Representative,
    M::Action: Debug + Clone + PartialEq + Send + Sync,
{
    let checker = model
        .clone()
        .focus(property)
        .checker()
        .finish_when(finish)
        .spawn_bfs()
        .join();
    let path = checker.discovery(property)?;
    wanted(&checker.discovery_classification(property))
        .then(|| model.trace(property, path.into_actions()))
}
