//! The relay's side facing modules: its calls queued and sent one at a time per module, their
//! answers taken, and the corrections that make a module drive as the core decides
//! (`[COOP-RELAY-FOLLOW.1]`, `[COOP-RELAY-POLICY.1]`).

use cooperation::SceneId;

use super::{
    rtc_command, Call, CallId, Correction, Forward, ModuleAnswer, ModuleRequest, Purpose, Relay,
};
use crate::engine::Now;
use crate::rtc::{AutoModeRequest, CooperateCommandsRequest};

impl Relay {
    pub(super) fn queue(
        &mut self,
        interface: String,
        request: ModuleRequest,
        purpose: Purpose,
    ) -> CallId {
        let id = CallId(self.next_call);
        self.next_call += 1;
        if let Some(link) = self.links.get_mut(&interface) {
            link.fresh = false;
        }
        self.queued.push_back((
            id,
            Call {
                interface,
                request,
                purpose,
            },
        ));
        id
    }

    /// The next call to send, at `now`: the first queued to a module with no call unanswered
    /// (so a module takes the relay's calls in the order they were made).
    pub fn poll_forward(&mut self, now: Now) -> Option<Forward> {
        // A switch of the relay's own that the module has been heard to have taken since it was
        // queued is not sent: each switch overwrites the module's standing decisions for a
        // moment (`[COOP-RELAY-FOLLOW.1]`).
        let links = &self.links;
        self.queued.retain(|(_, call)| {
            let moot = |enable: bool| {
                links
                    .get(&call.interface)
                    .is_some_and(|link| link.auto_mode == Some(enable))
            };
            !(call.purpose == Purpose::Correction
                && matches!(&call.request, ModuleRequest::AutoMode(request) if moot(request.enable)))
        });
        let at = self.queued.iter().position(|(_, call)| {
            !self
                .flights
                .values()
                .any(|(flight, _)| flight.interface == call.interface)
        })?;
        let (id, call) = self.queued.remove(at)?;
        let deadline_ms = i64::try_from(self.deadline_ms).unwrap_or(i64::MAX);
        let deadline = now
            .reading_ns
            .saturating_add(deadline_ms.saturating_mul(1_000_000));
        let forward = Forward {
            call: id,
            interface: call.interface.clone(),
            request: call.request.clone(),
        };
        self.flights.insert(id, (call, deadline));
        Some(forward)
    }

    /// A module's answer to call `call`, at `now`. An answer to a call that ran out of time, or
    /// of the other kind, is not taken (`false`).
    pub fn take_answer(&mut self, call: CallId, answer: &ModuleAnswer, now: Now) -> bool {
        self.engine.handle_timeout(now);
        let Some((flight, _)) = self.flights.remove(&call) else {
            return false;
        };
        let taken = match (&flight.request, answer) {
            (ModuleRequest::Commands(request), ModuleAnswer::Commands(response)) => {
                // One response per command, in order, naming its command's scene.
                let successes: Vec<(SceneId, bool)> =
                    if response.responses.len() == request.commands.len() {
                        request
                            .commands
                            .iter()
                            .zip(&response.responses)
                            .map(|(c, r)| (SceneId::from(c.uuid), r.success && r.uuid == c.uuid))
                            .collect()
                    } else {
                        Vec::new()
                    };
                if let Purpose::Operator(operator) = flight.purpose {
                    if let Some(pending) = self.operators.get_mut(&operator) {
                        pending.commands_answered(call, &successes);
                    }
                }
                true
            }
            (ModuleRequest::AutoMode(request), ModuleAnswer::AutoMode(success)) => {
                if let Purpose::Operator(operator) = flight.purpose {
                    if let Some(pending) = self.operators.get_mut(&operator) {
                        pending.auto_mode_answered(call, *success);
                    }
                }
                if *success {
                    // The module says it switched: its auto-mode status, which may come after
                    // the next status array, is not waited for, so that the switch is not sent
                    // again (each switch overwrites the standing decisions for a moment).
                    if let Some(link) = self.links.get_mut(&flight.interface) {
                        link.auto_mode = Some(request.enable);
                    }
                    self.resend_standing(&flight.interface);
                }
                true
            }
            _ => {
                // An answer of the other kind is no answer: the call runs out of time.
                self.flights.insert(call, (flight, i64::MIN));
                self.handle_timeout(now);
                return false;
            }
        };
        if let Purpose::Operator(operator) = flight.purpose {
            self.finish(operator);
        }
        self.correct(&flight.interface);
        taken
    }

    /// After an auto-mode switch, the interface's standing operator decisions again
    /// (`[COOP-RELAY-POLICY.1]`).
    fn resend_standing(&mut self, interface: &str) {
        let Some(binding) = self.binding(interface).cloned() else {
            return;
        };
        let Some(link) = self.links.get(interface) else {
            return;
        };
        let standing = link.standing(self.state());
        if standing.is_empty() {
            return;
        }
        let commands = standing
            .into_iter()
            .map(|(id, decision)| rtc_command(&binding, id, decision))
            .collect();
        let request = ModuleRequest::Commands(CooperateCommandsRequest {
            stamp: crate::Time::default(),
            commands,
        });
        self.queue(interface.to_owned(), request, Purpose::Correction);
    }

    /// Whether a call to `interface` is queued or unanswered, or an operator's call awaits it.
    pub(super) fn busy(&self, interface: &str) -> bool {
        self.queued.iter().any(|(_, c)| c.interface == interface)
            || self.flights.values().any(|(c, _)| c.interface == interface)
            || self.operators.values().any(|p| p.awaits(interface))
    }

    /// Sends `interface` what makes it drive as the core decides, if it is idle and its newest
    /// status array came after its last answer (`[COOP-RELAY-FOLLOW.1]`).
    pub(super) fn correct(&mut self, interface: &str) {
        if self.busy(interface) {
            return;
        }
        let (Some(link), Some(binding)) = (self.links.get(interface), self.binding(interface))
        else {
            return;
        };
        if !link.fresh {
            return;
        }
        let Some(correction) = link.correction(self.state(), binding) else {
            return;
        };
        let request = match correction {
            Correction::AutoMode(enable) => ModuleRequest::AutoMode(AutoModeRequest { enable }),
            Correction::Commands(commands) => {
                let binding = binding.clone();
                ModuleRequest::Commands(CooperateCommandsRequest {
                    stamp: crate::Time::default(),
                    commands: commands
                        .into_iter()
                        .map(|(id, decision)| rtc_command(&binding, id, decision))
                        .collect(),
                })
            }
        };
        self.queue(interface.to_owned(), request, Purpose::Correction);
    }
}
