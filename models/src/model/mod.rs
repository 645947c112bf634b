//! The models and the spec oracle: what is checked, and what it is checked against.
//!
//! - [`sequential`]: the core alone, one input at a time, every input of a bounded alphabet in
//!   every reachable state; its properties are the spec's rules, tables and invariants.
//! - [`batch`]: the core's sequences of inputs (`State::apply_all`), all or none, against
//!   `State::apply` input by input.
//! - [`network`]: the planner and operators with messages delayed, reordered, duplicated and
//!   lost between them.
//! - [`rtc`]: the RTC adapter (`cooperation_adapters::rtc`) over the core, call by call.
//! - [`engine`]: the service engine (`cooperation_adapters::engine`) as a host drives it, its clock
//!   running between calls.
//! - [`relay`]: the relay (`cooperation_adapters::relay`) between an operator and a planning
//!   module that behaves as upstream's `rtc_interface`, calls and answers lost.
//! - [`trivial`]: a model with no logic, for the checker's raw throughput.
//! - [`spec`]: the spec as the properties state it, its tables read from its text and its rules
//!   written from its words: an oracle compared with, never used to move a state.
//! - [`fault`]: deliberately wrong behaviours wrapped around the transition (sensitivity tests
//!   only), and the one place a model applies an input.
//! - [`ids`] and [`describe`]: what every model shares: identifiers, errors, inputs in words.

pub mod batch;
pub mod describe;
pub mod engine;
pub mod fault;
pub mod ids;
pub mod network;
pub mod relay;
pub mod rtc;
pub mod sequential;
pub mod spec;
pub mod trivial;
