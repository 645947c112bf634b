//! The checker's runs of the models, and what they report.
//!
//! - [`run`]: a check (strategy, threads, symmetry), its progress, stops (first violation,
//!   depth, time) and report, with every property's verdict and shortest counterexamples.
//! - [`budget`]: the memory, state and time budget that halts a search that would outgrow the
//!   machine, so that it stops with a report instead of dying.
//! - [`pins`]: every pinned state count, the one table the tests assert and the docs show.
//! - [`simulate`]: random walks of the sequential model by seed, every property checked.
//! - [`coverage`]: rule-pair coverage over the sequential model's reachable states.
//! - [`trace`]: a counterexample or witness as replayable JSON and as Markdown and Mermaid.
//! - [`summary`]: one check's outcome as `check --summary` prints it.

pub mod budget;
pub mod coverage;
pub mod pins;
pub mod run;
pub mod simulate;
pub mod summary;
pub mod trace;

use stateright::{Checker, Expectation, Model};

/// Checks `model` to completion breadth first on two threads: the properties that fail
/// (always-properties with a counterexample, sometimes-properties without a witness) and the
/// unique state count. The tests of the engine and relay models use it; a model focused on one
/// property stops at its first counterexample.
///
/// # Panics
/// If the search did not end (it has no budget).
#[allow(clippy::panic)]
pub fn failing<M>(model: M) -> (Vec<&'static str>, usize)
where
    M: Model + Send + Sync + 'static,
    M::State: Clone + std::fmt::Debug + std::hash::Hash + PartialEq + Send + Sync + 'static,
    M::Action: Clone + std::fmt::Debug + PartialEq + Send + Sync + 'static,
{
    let properties = model.properties();
    let checker = model.checker().threads(2).spawn_bfs().join();
    if !checker.is_done() {
        panic!("the search did not end");
    }
    let failing = properties
        .iter()
        .filter(|property| {
            let found = checker.discovery(property.name).is_some();
            match property.expectation {
                Expectation::Always | Expectation::Eventually => found,
                Expectation::Sometimes => !found,
            }
        })
        .map(|property| property.name)
        .collect();
    (failing, checker.unique_state_count())
}
