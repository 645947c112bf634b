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
