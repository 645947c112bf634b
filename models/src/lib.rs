//! Exhaustive stateright models of the cooperation core, and the checker's runs of them.
//!
//! Every model's `next_state` calls the library's [`cooperation::State::apply`] (or, for the
//! RTC model, the adapter `cooperation_adapters::rtc`; for the engine model, the service engine
//! `cooperation_adapters::engine`), the code the library ships; no rule, guard or
//! table of the specification is restated to move a state. The properties are stated from the
//! specification (its tables are read from `spec/cooperation.md` itself) and named by its tags.
//!
//! The crate has three parts, one folder each:
//!
//! - [`model`]: the models (sequential, network, RTC, engine, and a trivial one for the checker's own
//!   throughput), what they share, and the spec oracle they are compared with;
//! - [`check`]: running the checker over them (strategy, budgets, progress, counterexamples),
//!   random walks, rule-pair coverage, the pinned state counts, and the traces and summaries
//!   they report;
//! - `src/cli/`: the `cooperation-models` command, which parses options and calls the two.
//!
//! Generated documentation (diagrams, traceability, witnesses, the counts table, the reach
//! table) is written by `cargo xtask`, not by this crate.

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

pub mod check;
pub mod model;

pub use check::trace::Trace;
pub use model::batch::{BatchFault, BatchModel};
pub use model::engine::{EngineBounds, EngineFault, EngineModel};
pub use model::fault::Fault;
pub use model::ids::ModelError;
pub use model::network::{NetBounds, NetworkModel, Views};
pub use model::relay::{RelayBounds, RelayFault, RelayModel};
pub use model::rtc::{RtcBounds, RtcFault, RtcModel};
pub use model::sequential::{Bounds, SequentialModel, Step};
