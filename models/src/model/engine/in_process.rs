//! The C++ class's door ([`EngineBounds::in_process`](super::EngineBounds::in_process)): a
//! module's report and an operator's command reaching a planning module's RTC interface in the
//! engine's own process, the way `cooperation-cpp` calls it ([`Engine::call_at`]), rather than
//! through the module sync and the AD API.
//!
//! The same properties judge them as the sync and an operator's AD API call: a scene lives its
//! time to live from its report, a command never applies to a scene whose time to live had
//! passed at the call's time, and the answer is the one the core's own transition gives at
//! that time.

use cooperation::{Command, Input, OperatorDecision, Phase, SceneId};
use cooperation_adapters::engine::{Change, Engine, Now};
use cooperation_adapters::rtc::{self, CooperateCommand, CooperateCommandsRequest, Reply};
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
        let reply = self.call_in_process(next, last.now(), |host| {
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
        let expected = oracle(&last.engine, next.core_ms, &input);
        let agrees = answered == expected.is_ok()
            && result.is_ok() == expected.is_ok()
            && expected
                .as_ref()
                .map_or(true, |state| next.engine.state() == state);
        if !agrees {
            next.broken |= broken::ANSWER;
        }
        Some(answered && result.is_ok())
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
        self.call_in_process(next, now, |host| {
            host.interface(interface)?.update_cooperate_status(&report)
        })
        .is_ok()
    }

    /// `call` made in the engine's process at `now` ([`Engine::call_at`]), or, with
    /// [`EngineFault::InProcessWithoutCatchUp`], at the time the core was last told
    /// ([`Engine::call`]); flagged in `next` if it changed what the streams show without
    /// saying so.
    fn call_in_process<T>(
        &self,
        next: &mut EngineStep,
        now: Now,
        call: impl FnOnce(&mut Host) -> Result<T, RtcError>,
    ) -> Result<T, RtcError> {
        let before = next.engine.state().clone();
        let engine: &mut Engine = &mut next.engine;
        let (result, change): (_, Change) =
            if self.fault == Some(EngineFault::InProcessWithoutCatchUp) {
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
