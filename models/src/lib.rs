//! Exhaustive stateright models of the cooperation core.
//!
//! Every model's `next_state` calls the library's [`cooperation::State::apply`], the function the
//! library ships; no rule, guard or table of the specification is restated here. The
//! properties are stated from the specification (the merged-decision table is read from
//! `spec/cooperation.md` itself) and named by its tags.

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

pub mod budget;
pub mod coverage;
pub mod describe;
pub mod diagrams;
pub mod fault;
pub mod ids;
pub mod network;
pub mod rtc;
pub mod run;
pub mod sequential;
pub mod simulate;
pub mod spec;
pub mod trace;
pub mod traceability;
pub mod trivial;
pub mod witnesses;

pub use fault::Fault;
pub use ids::ModelError;
pub use network::{NetBounds, NetworkModel, Views};
pub use rtc::{RtcBounds, RtcFault, RtcModel};
pub use sequential::{Bounds, SequentialModel, Step};
pub use trace::Trace;
