//! What the engine answers and publishes besides the factors, read back into the spec oracle's
//! form ([`spec::responses`]): a call's `ResponseStatus`, `get_policies`'s answer, and the
//! `/cooperation/scenes` topic, each through a planted fault if the model has one; and an
//! operator's call judged against the core's own transition at its time.

use cooperation::{Input, Rejection, State};
use cooperation_adapters::engine::{Engine, Reply, Request};
use cooperation_adapters::wire::{self, Response, ResponseStatus};
use cooperation_adapters::Time;

use super::{broken, spec, EngineFault, EngineModel, EngineStep};
use crate::model::spec::responses::{self, PolicyEntry, SceneRow, Status};

/// A `ResponseStatus` as the oracle reads it.
fn status(written: &ResponseStatus) -> Status {
    Status {
        success: written.success,
        code: written.code,
        message: written.message.clone(),
    }
}

impl EngineModel {
    /// The status of an operator's call's reply (through a planted fault, if there is one);
    /// `None` if the reply is not an AD API service's.
    pub(super) fn answered_status(&self, reply: &Reply) -> Option<Status> {
        let Reply::Ad(response) = reply else {
            return None;
        };
        let mut answered = status(response.status());
        if self.fault == Some(EngineFault::RefusalAsUnknown) && !answered.success {
            answered.code = ResponseStatus::UNKNOWN;
        }
        Some(answered)
    }

    /// What `get_policies` answers in `state`, asked at the time the core was last told (so
    /// that asking tells the core no time), through a planted fault if there is one; `None` if
    /// the engine answers it with another service's response.
    #[must_use]
    pub fn policies_answer(&self, state: &EngineStep) -> Option<(Status, Vec<PolicyEntry>)> {
        let mut engine = state.engine.clone();
        let request = Request::Ad(wire::Request::GetPolicies(Default::default()));
        let at = engine.told(Time::default());
        let Reply::Ad(Response::GetPolicies(answer)) = engine.handle(request, at).reply else {
            return None;
        };
        let mut entries: Vec<PolicyEntry> = answer
            .policies
            .iter()
            .map(|p| (p.behavior.clone(), p.sequence.clone(), p.policy))
            .collect();
        match self.fault {
            Some(EngineFault::PolicyConstantsSwapped) => {
                for entry in &mut entries {
                    entry.2 = match entry.2 {
                        responses::policy::OPTIONAL => responses::policy::REQUIRED,
                        responses::policy::REQUIRED => responses::policy::OPTIONAL,
                        other => other,
                    };
                }
            }
            Some(EngineFault::PoliciesReversed) => entries.reverse(),
            _ => {}
        }
        Some((status(&answer.status), entries))
    }

    /// What `/cooperation/scenes` shows in `state` (short of its ages), through a planted fault
    /// if there is one.
    #[must_use]
    pub fn scenes_shown(&self, state: &EngineStep) -> Vec<SceneRow> {
        let publication = state.engine.publication(Time::default());
        let mut rows: Vec<SceneRow> = publication
            .scenes
            .scenes
            .iter()
            .map(|scene| SceneRow {
                uuid: scene.uuid.uuid.to_vec(),
                merged: scene.merged.decision,
                awaits_operator: scene.awaits_operator,
                requested: scene.requested,
                policy: scene.policy,
            })
            .collect();
        if self.fault == Some(EngineFault::ScenesShowModuleDecision) {
            for (row, (_, scene)) in rows.iter_mut().zip(state.engine.state().scenes()) {
                row.merged = match scene.module_decision() {
                    cooperation::Decision::Deactivate => 1,
                    cooperation::Decision::Activate => 2,
                };
            }
        }
        rows
    }
}

/// What the core's own transition answers to `input` at the request's time: the core of
/// `before` told the time since it was last told (up to `core_ms`, the core's time at the
/// request by the model's count), then given `input`. The state it leaves, or the rejection.
pub(super) fn oracle(before: &Engine, core_ms: u64, input: &Input) -> Result<State, Rejection> {
    let mut state = before.state().clone();
    let elapsed_ms = core_ms.saturating_sub(before.host().told_ms());
    if elapsed_ms > 0 {
        state.apply(&Input::Tick { elapsed_ms })?;
    }
    state.apply(input).map(|_| state)
}

impl EngineModel {
    /// An operator's `request` (the core's `input`), made at `last`'s clock reading: answered
    /// by the engine in `next`, and judged against the core's own transition at that time: the
    /// status, field by field, is the one `[COOP-API-STATUS.1]` states for the transition's
    /// result, and an applied call leaves the core the transition leaves. Whether it was
    /// answered success.
    pub(super) fn operator_call(
        &self,
        last: &EngineStep,
        next: &mut EngineStep,
        request: wire::Request,
        input: &Input,
    ) -> bool {
        let len = match input {
            Input::SetCommands { commands } => commands.len(),
            Input::SetPolicies { policies } => policies.len(),
            _ => 1,
        };
        let reply = self.handle(next, Request::Ad(request), last.now());
        let expected = oracle(&last.engine, next.core_ms, input);
        let status = spec::responses::batch_status(len, expected.as_ref().map(|_| ()));
        let agrees = self.answered_status(&reply) == Some(status)
            && expected
                .as_ref()
                .map_or(true, |state| next.engine.state() == state);
        if !agrees {
            next.broken |= broken::ANSWER;
        }
        reply.success()
    }
}
