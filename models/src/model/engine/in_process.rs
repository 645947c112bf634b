//! The C++ class's door ([`EngineBounds::in_process`](super::EngineBounds::in_process)): a
//! module's report, an operator's command and an auto-mode switch reaching a planning module's
//! RTC interface in the engine's own process, the way `cooperation-cpp` calls it
//! ([`Engine::call_at`]), rather than through the module sync and the AD API.
//!
//! The same properties judge them as the sync and an operator's AD API call: a scene lives its
//! time to live from its report, a command never applies to a scene whose time to live had
//! passed at the call's time, and the answer (of a command or an auto-mode switch) is the one
//! the core's own transition gives at that time.

use cooperation::{Command, Input, OperatorDecision, Phase, Policy, PolicySetting, SceneId};
use cooperation_adapters::engine::{Change, Engine, Now};
use cooperation_adapters::rtc::{
    self, AutoModeRequest, CooperateCommand, CooperateCommandsRequest, Reply,
};
use cooperation_adapters::rtc::{CooperateCommandsResponse, RtcError, StatusReport};
use cooperation_adapters::{Host, Time};

use super::answers::oracle;
use super::{broken, unhinted, EngineFault, EngineModel, EngineStep, FINISH};

/// The RTC command for `decision`; `None` for a decision an RTC command cannot carry.
const fn rtc_command(decision: OperatorDecision) -> Option<u8> {
    match decision {
        OperatorDecision::Activate => Some(rtc::Command::ACTIVATE),
        OperatorDecision::Deactivate => Some(rtc::Command::DEACTIVATE),
        OperatorDecision::Autonomous | OperatorDecision::Undecided => None,
    }
}

/// Flags in `next` an in-process call answered otherwise than the core's own transition for
/// `input` gives at the call's time: `answered`, whether the reply said success, and `result`,
/// the call's result, must both say what the transition says. Whether the call applied.
fn judge(
    last: &EngineStep,
    next: &mut EngineStep,
    input: &Input,
    answered: bool,
    result: Result<(), RtcError>,
) -> bool {
    let expected = oracle(&last.engine, next.core_ms, input);
    let agrees = answered == expected.is_ok()
        && result.is_ok() == expected.is_ok()
        && expected
            .as_ref()
            .map_or(true, |state| next.engine.state() == state);
    if !agrees {
        next.broken |= broken::ANSWER;
    }
    answered && result.is_ok()
}

impl EngineModel {
    /// An operator's command for `id`, made at `last`'s clock reading through the RTC interface
    /// the model's scenes are reported through, in the engine's process: answered by the engine
    /// in `next` and judged against the core's own transition at that time, as
    /// [`operator_call`](Self::operator_call) judges an AD API call. Whether it was answered
    /// success; `None` for a decision an RTC command cannot carry.
    pub(super) fn in_process_command(
        &self,
        last: &EngineStep,
        next: &mut EngineStep,
        id: SceneId,
        decision: OperatorDecision,
    ) -> Option<bool> {
        let module = if self.bounds.velocity {
            rtc::Module::INTERSECTION
        } else {
            rtc::Module::LANE_CHANGE_LEFT
        };
        let request = CooperateCommandsRequest {
            stamp: Time::default(),
            commands: vec![CooperateCommand {
                uuid: id.into(),
                module: rtc::Module::new(module),
                command: rtc::Command::new(rtc_command(decision)?),
            }],
        };
        let interface = self.reporter.1;
        let reply = self.call_in_process(next, last.now(), false, |host| {
            Ok::<Reply<CooperateCommandsResponse>, RtcError>(
                host.interface(interface)?.cooperate_commands(&request),
            )
        });
        let (result, answered) = match reply {
            Ok(reply) => (
                reply.result.map(drop),
                reply.response.responses.iter().all(|entry| entry.success),
            ),
            Err(refusal) => (Err(refusal), false),
        };
        let input = Input::SetCommands {
            commands: vec![Command { id, decision }],
        };
        Some(judge(last, next, &input, answered, result))
    }

    /// The module's policy set to `policy` through the RTC interface the model's scenes are
    /// reported through, in the engine's process, at `last`'s clock reading, as the C++ class's
    /// `AutoMode` service makes it (auto mode on for an optional policy): answered by the engine
    /// in `next` and judged against the core's own `set_policies` transition at that time, as
    /// [`operator_call`](Self::operator_call) judges an AD API call.
    pub(super) fn in_process_policy(
        &self,
        last: &EngineStep,
        next: &mut EngineStep,
        policy: Policy,
    ) {
        let request = AutoModeRequest {
            enable: policy == Policy::Optional,
        };
        let interface = self.reporter.1;
        let reply = self.call_in_process(next, last.now(), true, |host| {
            Ok::<_, RtcError>(host.interface(interface)?.auto_mode(&request))
        });
        let (result, answered) = match reply {
            Ok(reply) => (reply.result.map(drop), reply.response.success),
            Err(refusal) => (Err(refusal), false),
        };
        let input = Input::SetPolicies {
            policies: vec![PolicySetting {
                module: self.reporter.0,
                policy,
            }],
        };
        judge(last, next, &input, answered, result);
    }

    /// A module's report of `id` (waiting, `safe` or not, from `start` to [`FINISH`]) through
    /// the RTC interface the model's scenes are reported through, in the engine's process, at
    /// `now`, as the C++ class's `updateCooperateStatus` makes it. Whether it was accepted.
    pub(super) fn in_process_report(
        &self,
        next: &mut EngineStep,
        now: Now,
        id: SceneId,
        safe: bool,
        start: f32,
    ) -> bool {
        let report = StatusReport::new(id, safe, Phase::Waiting, start, FINISH);
        let interface = self.reporter.1;
        self.call_in_process(next, now, false, |host| {
            host.interface(interface)?.update_cooperate_status(&report)
        })
        .is_ok()
    }

    /// `call` made in the engine's process at `now` ([`Engine::call_at`]), or, with
    /// [`EngineFault::InProcessWithoutCatchUp`] (or [`EngineFault::AutoModeWithoutCatchUp`],
    /// for an auto-mode switch), at the time the core was last told ([`Engine::call`]);
    /// flagged in `next` if it changed what the streams show without saying so.
    fn call_in_process<T>(
        &self,
        next: &mut EngineStep,
        now: Now,
        auto_mode: bool,
        call: impl FnOnce(&mut Host) -> Result<T, RtcError>,
    ) -> Result<T, RtcError> {
        let before = next.engine.state().clone();
        let engine: &mut Engine = &mut next.engine;
        let late = match self.fault {
            Some(EngineFault::InProcessWithoutCatchUp) => true,
            Some(EngineFault::AutoModeWithoutCatchUp) => auto_mode,
            _ => false,
        };
        let (result, change): (_, Change) = if late {
            engine.call(call)
        } else {
            let at = self.reading(engine, now);
            let (result, change, _) = engine.call_at(at, call);
            (result, change)
        };
        unhinted(next, &before, change);
        result
    }
}
