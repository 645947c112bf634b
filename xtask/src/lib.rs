//! The repository's own tasks (`cargo xtask`): the documentation generated from the code and the
//! checker, written and checked.
//!
//! - [`diagrams`]: the lifecycle and merged-decision diagrams in `spec/cooperation.md`.
//! - [`traceability`]: `docs/traceability.md`, every spec tag to its code, properties and tests.
//! - [`witnesses`]: `docs/witnesses.md`, the checker's shortest paths to the design page's
//!   scenarios.
//! - [`counts`]: `docs/counts.md`, every pinned state count, and the check that no other page
//!   repeats one.
//! - [`names`]: the check that every `Type::item` the pages name is defined in the sources.
//! - [`reach`]: the reach table of `docs/reach.md`, measured by running the checker, and
//!   the check that it agrees with the pins.

pub mod counts;
pub mod diagrams;
pub mod names;
pub mod reach;
pub mod traceability;
pub mod witnesses;
