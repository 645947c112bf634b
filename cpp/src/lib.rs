//! The cooperation core behind upstream's C++ RTC interface.
//!
//! Autoware's planning modules are C++ and talk to cooperation through
//! `autoware::rtc_interface::RTCInterface`. This crate is the Rust half of a C++ library with
//! that class's shape (`cpp/include/autoware/rtc_interface/rtc_interface.hpp`): a [`cxx`]
//! bridge whose every function is one call of [`cooperation_adapters::rtc`] on one shared core, a
//! [`Core`] per node. It keeps no rule of its own: every answer is the adapter's, and so the
//! core's. `docs/cpp.md` explains the C++ side and the migration.
//!
//! Nothing here panics or throws into C++: a refusal is an [`Outcome`](bridge::ffi::Outcome)
//! with the adapter's explanation, which the C++ class logs as upstream logs its warnings.
#![deny(unsafe_code)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

// The one place this crate has `unsafe`: the code `cxx::bridge` generates.
#[allow(unsafe_code)]
pub mod bridge;
mod calls;
mod snapshot;
pub mod timing;

pub use calls::{Core, Handle};
