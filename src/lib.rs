//! The Autoware AD API **cooperation** feature (request to cooperate): scenes, module and
//! operator decisions, per-module cooperation policies and the merged decision the planner
//! drives with, as one specified state machine.
//!
//! The normative specification is `spec/cooperation.md`; every rule there has a tag, and
//! [`State::apply`], the only function that changes the state, names the rule that fired.
//! The same function is model-checked exhaustively by the `cooperation-models` crate.
//!
//! The core is sans-IO: it reads no clock (time arrives as [`Input::Tick`]), makes no
//! identifiers (they arrive in [`Input::Register`]), draws no random numbers and does no I/O.
//! It holds no lock and speaks no protocol: the AD API's messages and `ResponseStatus` codes,
//! TIER IV's RTC interface, the settings file and a lock for callers on several threads are the
//! `cooperation-adapters` crate's, the ring around this one. The model checker's hooks
//! (`State::relabel`, `State::with_table_layout`, `TableLayout`) are public with the
//! `verification` feature only.
//!
//! # Example
//!
//! A lane change whose module sees an obstacle, overridden by the operator (the design
//! page's sequence):
//!
//! ```
//! use cooperation::*;
//!
//! let lane_change = Module::new(Behavior::LaneChange);
//! let mut state = State::new(Config::new([(lane_change, Policy::Optional)]))?;
//!
//! // The module opens a scene and decides not to change lanes.
//! let id = SceneId::from_u128(0x5678);
//! let geometry = Geometry::steering(Direction::Left, 30.0, 60.0);
//! let register = Input::Register { id, module: lane_change, report: Report::new(Decision::Deactivate, geometry) };
//! assert_eq!(state.apply(&register)?.rule, Rule::RegisterNew);
//! assert_eq!(state.merged_decision(id), Some(Decision::Deactivate));
//!
//! // The operator overrides it (the AD API's `set_commands`).
//! let command = Command { id, decision: OperatorDecision::Activate };
//! assert_eq!(state.apply(&Input::SetCommands { commands: vec![command] })?.rule, Rule::CommandApply);
//! assert_eq!(state.merged_decision(id), Some(Decision::Activate));
//!
//! // A command for an identifier nobody registered is refused, and changes nothing.
//! let before = state.clone();
//! let stray = Command { id: SceneId::from_u128(0x9999), decision: OperatorDecision::Activate };
//! let rejection = state.apply(&Input::SetCommands { commands: vec![stray] }).unwrap_err();
//! assert_eq!(rejection.rule(), Rule::CommandUnknown);
//! assert_eq!(rejection.to_string(), "no command applied: command 0 (scene 00000000-0000-0000-0000-000000009999): unknown scene");
//! assert_eq!(state, before);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

mod decision;
mod detail;
mod geometry;
mod id;
mod input;

mod module;
mod output;
mod phase;
mod rejection;
mod rule;
mod state;
mod table;

pub use decision::{merge, Decision, OperatorDecision, Policy};
pub use detail::Detail;
pub use geometry::{
    Direction, Distance, FactorKind, Geometry, Pose, SteeringStatus, VelocityStatus,
};
pub use id::{InvalidSceneId, SceneId};
pub use input::{Command, Described, Input, PolicySetting, Report};

pub use module::{Behavior, Extension, InvalidName, Module, NameProblem, Sequence};
pub use output::{
    CooperatingFactor, CooperationStatus, FactorLists, SteeringFactor, VelocityFactor,
};
pub use phase::Phase;
pub use rejection::{CommandFailure, CommandOutcome, Rejection, RetireReason, Retirement};
pub use rule::Rule;
pub use state::{
    Config, ConfigError, Invariant, Limits, Scene, SequenceRejection, State, Transition, Violation,
};
#[cfg(feature = "verification")]
pub use table::TableLayout;

pub mod guide {
    //! Guides for the library's users, with examples that compile and run as doctests.

    #[doc = include_str!("../docs/guide-planner.md")]
    pub mod planner {}

    #[doc = include_str!("../docs/guide-operator.md")]
    pub mod operator {}
}

/// The README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
