//! The core's integration tests, in one test binary so that they are built and linked once:
//! each module is one file of this folder, and `tests/allocations.rs`, which counts the
//! process's allocations, stays a binary of its own.

mod apply_all;
mod common;
mod definitions;
mod guard_order;
mod hostile;
mod invariants;
mod properties;
mod rules;
mod seed;
mod spec_sync;
mod spec_tables;
