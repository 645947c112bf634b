//! The engine model's configuration: its bounds, and the faults planted in the engine to show
//! that the properties can fail.

use serde::{Deserialize, Serialize};

#[cfg(doc)]
use super::DISTANCES;
use super::TTL_MS;

/// A deliberately wrong engine, for showing that the properties can fail. Each wraps the
/// engine's calls the way a bug in it would behave; nothing of it is compiled into the library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum EngineFault {
    /// An operator's call is answered at the time the core was last told, not the request's
    /// (the rosbridge node's call before the engine).
    CallWithoutCatchUp,
    /// A module's sync is answered at the time the core was last told: its scene's time to live
    /// starts in the past.
    ReportWithoutCatchUp,
    /// A change's publication is taken and never sent: the engine counts it as shown.
    ChangeUnpublished,
    /// A call that changes what the streams show does not say so (no publication asked).
    ChangeUnhinted,
    /// An undecided operator decision is written as `UNKNOWN` (0), not `UNDECIDED`.
    UndecidedAsUnknown,
    /// The factors are listed by identifier, not by distance.
    FactorsByIdentifier,
    /// A steering factor's start and finish distances are swapped.
    StartFinishSwapped,
    /// A step of the clock counts whole, however long (`[COOP-ENGINE-STEP.1]` not applied):
    /// with [`EngineBounds::jumps`], a scene reported just before a jump retires in it.
    StepUncapped,
    /// A refused call is answered with `UNKNOWN` (50000), not `PARAMETER_ERROR`.
    RefusalAsUnknown,
    /// `get_policies` writes `OPTIONAL` as `REQUIRED` and the reverse.
    PolicyConstantsSwapped,
    /// `get_policies` lists the modules in the reverse of their order.
    PoliciesReversed,
    /// `/cooperation/scenes` shows each scene's module decision as its merged decision.
    ScenesShowModuleDecision,
    /// A reading earlier than the last told is ignored until the clock passes the last again
    /// (`[COOP-ENGINE-STEP.1]` not applied to a clock that went back): with
    /// [`EngineBounds::rewinds`], time stalls for the core after the clock goes back.
    BackStalls,
    /// A periodic publication waits for the clock to pass the last one's reading again when
    /// the clock went back before it (the engine before `[COOP-ENGINE-PUBLISH.1]` said
    /// otherwise): with [`EngineBounds::rewinds`], the host is asked at that reading.
    BackHoldsPublications,
    /// The engine asks for the time at the next periodic publication or the step limit, never
    /// at a scene's expiry (the engine before `[COOP-ENGINE-WAKE.1]`): an expired scene is
    /// shown until the next publication.
    ExpiryUnasked,
    /// The engine asks for the time a millisecond before a scene's time to live has passed,
    /// when nothing else falls due: its host calls for nothing.
    ExpiryEarly,
    /// With [`EngineBounds::in_process`], a call in the engine's process is made at the time the
    /// core was last told (`Engine::call`, as the C++ class made its calls before it called
    /// `Engine::call_at`): a report's scene starts its time to live in the past, and a command
    /// can reach a scene whose time to live has passed.
    InProcessWithoutCatchUp,
    /// With [`EngineBounds::in_process`], an auto-mode switch in the engine's process alone is
    /// made at the time the core was last told (reports and commands at their own): the
    /// module's policy changes before the scenes whose time to live had passed expire.
    AutoModeWithoutCatchUp,
}

impl EngineFault {
    /// Every fault.
    pub const ALL: [Self; 18] = [
        Self::CallWithoutCatchUp,
        Self::ReportWithoutCatchUp,
        Self::ChangeUnpublished,
        Self::ChangeUnhinted,
        Self::UndecidedAsUnknown,
        Self::FactorsByIdentifier,
        Self::StartFinishSwapped,
        Self::StepUncapped,
        Self::RefusalAsUnknown,
        Self::PolicyConstantsSwapped,
        Self::PoliciesReversed,
        Self::ScenesShowModuleDecision,
        Self::BackStalls,
        Self::BackHoldsPublications,
        Self::ExpiryUnasked,
        Self::ExpiryEarly,
        Self::InProcessWithoutCatchUp,
        Self::AutoModeWithoutCatchUp,
    ];
}

/// The size of the engine model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct EngineBounds {
    /// Scene identifiers, `1..=scenes`.
    pub scenes: usize,
    /// The clock's last reading, in milliseconds from 0.
    pub horizon_ms: u64,
    /// Reports start at each of [`DISTANCES`] (else all at one distance), and nothing is
    /// published: the configuration that checks the messages' order and fields.
    #[serde(default)]
    pub geometry: bool,
    /// The scenes are an intersection's (velocity factors), not a lane change's (steering).
    #[serde(default)]
    pub velocity: bool,
    /// The clock jumps: a step of the clock counts at most 1 ms ([`JUMP_STEP_MS`]), so every
    /// step of 2 ms or more is a jump (`[COOP-ENGINE-STEP.1]`); otherwise the engine's default
    /// limit, which no step of the model reaches.
    #[serde(default)]
    pub jumps: bool,
    /// The clock can go back, once, by 1 ms (a bag played again, a simulator reset): the core
    /// is told nothing for it, and time counts on from the earlier reading
    /// (`[COOP-ENGINE-STEP.1]`).
    #[serde(default)]
    pub rewinds: bool,
    /// The module's reports and the operator's commands reach the model's RTC interface in the
    /// engine's process, as the C++ class's `updateCooperateStatus` and its `cooperateCommands`
    /// service do (`Engine::call_at`), instead of the module sync and the AD API's
    /// `set_commands`.
    #[serde(default)]
    pub in_process: bool,
}

/// The step limit with [`EngineBounds::jumps`], in milliseconds: the time to live, so that a
/// scene reported at the reading the core was last told of outlives any one step.
pub const JUMP_STEP_MS: u64 = TTL_MS;
