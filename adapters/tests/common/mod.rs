//! Fixtures shared by the adapters' integration tests: the core's own fixtures, and the RTC
//! interfaces'.
#![allow(dead_code, unreachable_pub)]

#[path = "../../../tests/common/mod.rs"]
mod fixtures;

pub use fixtures::*;

use cooperation::*;
use cooperation_adapters::rtc::{self, Interface, RtcError, StatusReport, Transitions};
pub use cooperation_adapters::Time;

/// Upstream's `updateCooperateStatus` with its positional arguments, the lifecycle state as a
/// number: the number is read as a status message's `state` is ([`rtc::Lifecycle::phase`],
/// refused as `state.type` when no constant has it), and the report goes to
/// [`Interface::update_cooperate_status`].
pub trait UpdateAsUpstream {
    /// The report, its sequence not stated.
    fn update_as_upstream(
        &mut self,
        id: SceneId,
        safe: bool,
        state: u8,
        start_distance: f32,
        finish_distance: f32,
        requested: bool,
    ) -> Result<Transitions, RtcError>;

    /// The report, its sequence stated.
    #[allow(clippy::too_many_arguments)] // Upstream's, in its order, and the sequence.
    fn update_as_upstream_in(
        &mut self,
        id: SceneId,
        sequence: Sequence,
        safe: bool,
        state: u8,
        start_distance: f32,
        finish_distance: f32,
        requested: bool,
    ) -> Result<Transitions, RtcError>;
}

/// The report upstream's arguments make.
pub fn upstream_report(
    id: SceneId,
    sequence: Option<Sequence>,
    safe: bool,
    state: u8,
    (start_distance, finish_distance): (f32, f32),
    requested: bool,
) -> Result<StatusReport, RtcError> {
    let phase = rtc::Lifecycle::new(state)
        .phase()
        .map_err(|e| e.within("state"))?;
    Ok(StatusReport {
        requested,
        sequence,
        ..StatusReport::new(id, safe, phase, start_distance, finish_distance)
    })
}

impl UpdateAsUpstream for Interface<'_> {
    fn update_as_upstream(
        &mut self,
        id: SceneId,
        safe: bool,
        state: u8,
        start_distance: f32,
        finish_distance: f32,
        requested: bool,
    ) -> Result<Transitions, RtcError> {
        let report = upstream_report(
            id,
            None,
            safe,
            state,
            (start_distance, finish_distance),
            requested,
        )?;
        self.update_cooperate_status(&report)
    }

    fn update_as_upstream_in(
        &mut self,
        id: SceneId,
        sequence: Sequence,
        safe: bool,
        state: u8,
        start_distance: f32,
        finish_distance: f32,
        requested: bool,
    ) -> Result<Transitions, RtcError> {
        let report = upstream_report(
            id,
            Some(sequence),
            safe,
            state,
            (start_distance, finish_distance),
            requested,
        )?;
        self.update_cooperate_status(&report)
    }
}

/// The standard RTC interfaces over a core that has every bound module, each with the policy
/// upstream's `enable_rtc` flag stands for, and the default limits (a 10 s TTL, as upstream).
pub fn rtc_setup(enable_rtc: bool) -> (rtc::Rtc, State) {
    let rtc = rtc::Rtc::standard();
    let state = State::new(Config::new(rtc.policies(enable_rtc))).expect("valid configuration");
    (rtc, state)
}

/// A `CooperateCommands` request; each command's module is `NONE`, as a default-constructed
/// upstream message has it.
pub fn rtc_commands(list: &[(SceneId, u8)]) -> rtc::CooperateCommandsRequest {
    rtc::CooperateCommandsRequest {
        stamp: Time::default(),
        commands: list
            .iter()
            .map(|&(id, command)| rtc::CooperateCommand {
                uuid: id.into(),
                module: rtc::Module::default(),
                command: rtc::Command::new(command),
            })
            .collect(),
    }
}

/// Registers scene `n` through the RTC interface `name`, in the first sequence it binds (an
/// avoidance's shift out): safe, waiting, its section starting at `start` and ending at 90 m.
pub fn rtc_register_at(rtc: &mut rtc::Rtc, state: &mut State, name: &str, n: u128, start: f32) {
    let sequence = rtc
        .bindings()
        .iter()
        .find(|binding| binding.name == name)
        .and_then(|binding| binding.sequences.first().copied())
        .expect("bound");
    rtc.interface(state, name)
        .expect("bound")
        .update_as_upstream_in(
            id(n),
            sequence,
            true,
            rtc::Lifecycle::WAITING_FOR_EXECUTION,
            start,
            90.0,
            false,
        )
        .expect("registers");
}
