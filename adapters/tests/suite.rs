//! The adapters' integration tests, in one test binary so that they are built and linked once:
//! each module is one file or folder of this one, and `wire_hostile.rs`, which counts the
//! process's allocations, stays a binary of its own.

mod api;
mod cdr;
mod common;
mod concurrency;
mod dds;
mod deviations;
mod engine;
mod hostile;
mod relay_factors;
#[path = "rtc/main.rs"]
mod rtc;
#[path = "settings/main.rs"]
mod settings;
#[path = "wire/main.rs"]
mod wire;
