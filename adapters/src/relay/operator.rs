//! The relay's side facing operators: an AD API call checked by the core, forwarded to the
//! modules that own its scenes, and answered once they have (`[COOP-RELAY-FORWARD.1]`,
//! `[COOP-RELAY-SUCCESS.1]`).

use std::collections::BTreeMap;

use cooperation::{Decision, Input, OperatorDecision, Policy};

use super::pending::{self, Outcome, Part, Pending};
use super::{
    link, rtc_command, CallId, Link, ModuleRequest, OperatorCall, Purpose, Relay, RelayRefusal,
    EXPRESSIBLE,
};
use crate::engine::Now;
use crate::rtc::{AutoModeRequest, CooperateCommand, CooperateCommandsRequest};
use crate::wire::{self, ResponseStatus};

impl Relay {
    /// An operator's AD API call, made at `now`: its answer at once if it needs no module (a
    /// refusal, `get_policies`, an empty batch), else `None`, and the answer comes from
    /// [`poll_answer`](Self::poll_answer) once the modules have answered
    /// (`[COOP-RELAY-FORWARD.1]`).
    pub fn handle_operator(
        &mut self,
        call: OperatorCall,
        request: &wire::Request,
        now: Now,
    ) -> Option<wire::Response> {
        self.engine.handle_timeout(now);
        match request {
            wire::Request::GetPolicies(request) => Some(wire::Response::GetPolicies(
                wire::get_policies(self.state(), request),
            )),
            wire::Request::SetCommands(request) => {
                self.set_commands(call, request, now).err().map(|status| {
                    wire::Response::SetCommands(wire::SetCooperationCommandsResponse { status })
                })
            }
            wire::Request::SetPolicies(request) => {
                self.set_policies(call, request).err().map(|status| {
                    wire::Response::SetPolicies(wire::SetCooperationPoliciesResponse { status })
                })
            }
        }
    }

    /// Forwards a `set_commands` the core accepts, or says why not (`Err` is the answer).
    fn set_commands(
        &mut self,
        operator: OperatorCall,
        request: &wire::SetCooperationCommandsRequest,
        now: Now,
    ) -> Result<(), ResponseStatus> {
        let commands = request.to_commands().map_err(|m| m.to_status())?;
        let mut trial = self.state().clone();
        let checked = trial.apply(&Input::SetCommands {
            commands: commands.clone(),
        });
        if checked.is_err() || commands.is_empty() {
            return Err(ResponseStatus::for_batch(commands.len(), &checked));
        }
        // [COOP-RELAY-INEXPRESSIBLE.1]
        for (index, command) in commands.iter().enumerate() {
            if !EXPRESSIBLE.contains(&command.decision) {
                return Err(refusal(&RelayRefusal::Inexpressible {
                    index,
                    id: command.id,
                    decision: command.decision,
                }));
            }
        }
        let mut by_interface: BTreeMap<String, Vec<CooperateCommand>> = BTreeMap::new();
        let mut parts = Vec::with_capacity(commands.len());
        for (index, &command) in commands.iter().enumerate() {
            let binding = self
                .engine
                .host()
                .rtc()
                .owner(self.state(), command.id)
                .cloned();
            let Some(binding) = binding else {
                return Err(refusal(&RelayRefusal::NoModule {
                    index,
                    id: command.id,
                }));
            };
            let decision = match command.decision {
                OperatorDecision::Activate => Decision::Activate,
                _ => Decision::Deactivate,
            };
            by_interface
                .entry(binding.name.clone())
                .or_default()
                .push(rtc_command(&binding, command.id, decision));
            parts.push(Part {
                item: command,
                interface: binding.name,
                call: CallId(0),
                outcome: Outcome::Awaited,
            });
        }
        for (interface, commands) in by_interface {
            let request = ModuleRequest::Commands(CooperateCommandsRequest {
                stamp: now.stamp,
                commands,
            });
            let id = self.queue(interface.clone(), request, Purpose::Operator(operator));
            for part in parts.iter_mut().filter(|p| p.interface == interface) {
                part.call = id;
            }
        }
        self.operators.insert(operator, Pending::Commands(parts));
        Ok(())
    }

    /// Forwards a `set_policies` the core accepts as auto-mode switches, or says why not.
    fn set_policies(
        &mut self,
        operator: OperatorCall,
        request: &wire::SetCooperationPoliciesRequest,
    ) -> Result<(), ResponseStatus> {
        let policies = request.to_policies().map_err(|m| m.to_status())?;
        let mut trial = self.state().clone();
        let checked = trial.apply(&Input::SetPolicies {
            policies: policies.clone(),
        });
        if checked.is_err() || policies.is_empty() {
            return Err(ResponseStatus::for_batch(policies.len(), &checked));
        }
        let mut switched = Vec::new();
        for binding in self.engine.host().rtc().bindings() {
            if !policies
                .iter()
                .any(|setting| binding.modules().any(|m| m == setting.module))
            {
                continue;
            }
            // [COOP-RELAY-INEXPRESSIBLE.1]
            let Some(policy) = link::interface_policy(&trial, binding) else {
                return Err(refusal(&RelayRefusal::MixedPolicies {
                    interface: binding.name.clone(),
                }));
            };
            // An interface not heard from is switched when it is (`[COOP-RELAY-FOLLOW.1]`).
            if !self.links.get(&binding.name).is_some_and(Link::heard) {
                continue;
            }
            switched.push((binding.name.clone(), policy == Policy::Optional));
        }
        if switched.is_empty() {
            // No module to tell: the core's alone.
            let len = policies.len();
            let input = Input::SetPolicies { policies };
            let (result, _) = self.engine.call(|host| host.state_mut().apply(&input));
            return Err(ResponseStatus::for_batch(len, &result));
        }
        let parts = switched
            .into_iter()
            .map(|(interface, enable)| {
                let request = ModuleRequest::AutoMode(AutoModeRequest { enable });
                let call = self.queue(interface.clone(), request, Purpose::Operator(operator));
                Part {
                    item: enable,
                    interface,
                    call,
                    outcome: Outcome::Awaited,
                }
            })
            .collect();
        self.operators
            .insert(operator, Pending::Policies(policies, parts));
        Ok(())
    }

    /// The next operator's answer that is ready.
    pub fn poll_answer(&mut self) -> Option<(OperatorCall, wire::Response)> {
        self.answers.pop_front()
    }

    /// Answers an operator's call whose parts are all settled: what the modules took is applied
    /// to the core, and the answer says success only if that is everything
    /// (`[COOP-RELAY-SUCCESS.1]`).
    pub(super) fn finish(&mut self, operator: OperatorCall) {
        if !self.operators.get(&operator).is_some_and(Pending::is_done) {
            return;
        }
        let Some(pending) = self.operators.remove(&operator) else {
            return;
        };
        let response = match pending {
            Pending::Commands(parts) => {
                let mut failures = Vec::new();
                for part in parts.iter().filter(|p| p.outcome == Outcome::Accepted) {
                    let input = Input::SetCommands {
                        commands: vec![part.item],
                    };
                    if let (Err(rejection), _) =
                        self.engine.call(|host| host.state_mut().apply(&input))
                    {
                        failures.push(format!(
                            "the core refused scene {}: {rejection}",
                            part.item.id
                        ));
                    }
                }
                let status = pending::status(&parts, &failures, self.deadline_ms, |c| {
                    format!("scene {}", c.id)
                });
                wire::Response::SetCommands(wire::SetCooperationCommandsResponse { status })
            }
            Pending::Policies(settings, parts) => {
                let rtc = self.engine.host().rtc();
                // A setting applies when every interface of its module took the switch.
                let taken: Vec<cooperation::PolicySetting> = settings
                    .iter()
                    .filter(|setting| {
                        parts.iter().all(|part| {
                            part.outcome == Outcome::Accepted
                                || !rtc.bindings().iter().any(|b| {
                                    b.name == part.interface
                                        && b.modules().any(|m| m == setting.module)
                                })
                        })
                    })
                    .copied()
                    .collect();
                let input = Input::SetPolicies {
                    policies: taken.clone(),
                };
                let mut failures = Vec::new();
                if let (Err(rejection), _) = self.engine.call(|host| host.state_mut().apply(&input))
                {
                    failures.push(format!("the core refused the policies: {rejection}"));
                }
                let status = if failures.is_empty() && taken.len() == settings.len() {
                    ResponseStatus::success()
                } else {
                    pending::status(&parts, &failures, self.deadline_ms, |enable| {
                        format!("auto mode {}", if *enable { "on" } else { "off" })
                    })
                };
                wire::Response::SetPolicies(wire::SetCooperationPoliciesResponse { status })
            }
        };
        self.answers.push_back((operator, response));
    }
}

/// The status of a call the relay refuses.
fn refusal(refusal: &RelayRefusal) -> ResponseStatus {
    ResponseStatus {
        success: false,
        code: ResponseStatus::PARAMETER_ERROR,
        message: refusal.to_string(),
    }
}
