//! The relay: the service engine over planning modules that speak upstream's RTC endpoints.
//!
//! Beside a stock Autoware stack the planning modules keep their own RTC interfaces (upstream's
//! `rtc_interface`, or this project's C++ class): each publishes its scenes on
//! `/planning/cooperate_status/<name>` and its auto mode on `/planning/auto_mode_status/<name>`,
//! and serves `/planning/cooperate_commands/<name>` and `/planning/enable_auto_mode/<name>`. The
//! relay is the sans-IO core of a node that sits between those endpoints and the AD API, in the
//! shape the engine has ([`Engine`]):
//!
//! - [`Relay::take_statuses`] and [`Relay::take_auto_mode`]: a module's messages, each status
//!   array its report into the core through the RTC adapter (`[COOP-RELAY-REPORT.1]`).
//! - [`Relay::handle_operator`]: an AD API call. The core checks it first; what it accepts is
//!   forwarded to the owning modules, and applied to the core only as far as they take it
//!   (`[COOP-RELAY-FORWARD.1]`, `[COOP-RELAY-SUCCESS.1]`); the answer comes from
//!   [`Relay::poll_answer`] once every module answered or its deadline passed.
//! - [`Relay::poll_forward`] hands out the calls to send to modules, one at a time per module;
//!   [`Relay::take_answer`] takes a module's answer.
//! - [`Relay::handle_timeout`]: time between messages (deadlines, scenes ageing out).
//!
//! Between calls the relay compares what each module last said of its scenes with what the core
//! decides and sends what makes them agree (`[COOP-RELAY-FOLLOW.1]`): an auto-mode switch, then
//! the standing operator decisions it overwrote (`[COOP-RELAY-POLICY.1]`). Nothing here restates
//! a rule of the core: every change is an input to the core through the adapters.

mod error;
pub mod factors;
mod link;
mod pending;

pub use error::{ArrayError, ArrayTaken, RelayRefusal};
pub use link::{Correction, Link, Seen};

use std::collections::{BTreeMap, VecDeque};
use std::hash::{Hash, Hasher};

use cooperation::{Decision, Input, OperatorDecision, Phase, Policy, SceneId, State};

use crate::engine::{Engine, Now, Publication};
use crate::rtc::{
    self, AutoModeRequest, AutoModeStatus, Binding, CooperateCommand, CooperateCommandsRequest,
    CooperateCommandsResponse, CooperateStatusArray, RtcError, StatusReport,
};
use crate::wire::{self, ResponseStatus};
use crate::{Host, Time};
use pending::{Outcome, Part, Pending};

/// How long a module has to answer a forwarded call unless the host says otherwise, in
/// milliseconds.
pub const DEADLINE_MS: u64 = 1_000;

/// The longest deadline a host may give modules, in milliseconds (a node's `--deadline-ms`).
pub const MAX_DEADLINE_MS: u64 = 60_000;

/// How much longer than the modules' deadline a host waits for the relay's answer to an
/// operator's call, in milliseconds, before it answers the call itself with a refusal. The relay
/// answers every call by the deadline ([`Relay::handle_timeout`]); this covers the relay's turn
/// and its publication, and a relay thread that has stopped turning.
pub const ANSWER_SLACK_MS: u64 = 2_000;

/// The longest a host waits for the relay's answer to an operator's call when modules have
/// `deadline_ms` to answer: the deadline and [`ANSWER_SLACK_MS`].
#[must_use]
pub const fn answer_wait_ms(deadline_ms: u64) -> u64 {
    deadline_ms.saturating_add(ANSWER_SLACK_MS)
}

/// The operator decisions an upstream RTC interface can take for one scene, and so the only
/// ones the relay forwards (`[COOP-RELAY-INEXPRESSIBLE.1]`).
pub const EXPRESSIBLE: [OperatorDecision; 2] =
    [OperatorDecision::Deactivate, OperatorDecision::Activate];

/// One call to a module, numbered by the relay.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct CallId(pub u64);

/// One operator's call, numbered by the host: a number is not given to a second call while the
/// first awaits its answer (the second would take its place).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub struct OperatorCall(pub u64);

/// A call to a module's RTC interface.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum ModuleRequest {
    /// `/planning/cooperate_commands/<name>`.
    Commands(CooperateCommandsRequest),
    /// `/planning/enable_auto_mode/<name>`.
    AutoMode(AutoModeRequest),
}

/// A module's answer to a [`ModuleRequest`] of the same kind.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub enum ModuleAnswer {
    /// The answer of `cooperate_commands`.
    Commands(CooperateCommandsResponse),
    /// The answer of `enable_auto_mode`: whether it was done.
    AutoMode(bool),
}

/// A call for the host to send.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub struct Forward {
    /// Its number, to give back with the answer.
    pub call: CallId,
    /// The interface it goes to.
    pub interface: String,
    /// The request.
    pub request: ModuleRequest,
}

/// Why a call is sent.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Purpose {
    /// Part of an operator's call.
    Operator(OperatorCall),
    /// The relay's own, to make the module drive as the core decides.
    Correction,
}

#[derive(Clone, PartialEq, Eq, Hash, Debug)]
struct Call {
    interface: String,
    request: ModuleRequest,
    purpose: Purpose,
}

/// The engine, each module interface's link, and the calls on their way.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Relay {
    engine: Engine,
    deadline_ms: u64,
    links: BTreeMap<String, Link>,
    /// Calls not handed out yet, in order.
    queued: VecDeque<(CallId, Call)>,
    /// Calls handed out, with their deadlines as readings in nanoseconds.
    flights: BTreeMap<CallId, (Call, i64)>,
    operators: BTreeMap<OperatorCall, Pending>,
    answers: VecDeque<(OperatorCall, wire::Response)>,
    next_call: u64,
}

impl Relay {
    /// A relay of every interface `engine` binds, each module given `deadline_ms` to answer.
    #[must_use]
    pub fn new(engine: Engine, deadline_ms: u64) -> Self {
        let links = engine
            .host()
            .rtc()
            .bindings()
            .iter()
            .map(|binding| (binding.name.clone(), Link::default()))
            .collect();
        Self {
            engine,
            deadline_ms,
            links,
            queued: VecDeque::new(),
            flights: BTreeMap::new(),
            operators: BTreeMap::new(),
            answers: VecDeque::new(),
            next_call: 0,
        }
    }

    /// The engine, to query.
    #[must_use]
    pub const fn engine(&self) -> &Engine {
        &self.engine
    }

    /// The core, to query.
    #[must_use]
    pub const fn state(&self) -> &State {
        self.engine.state()
    }

    /// The link of `interface`, to query.
    #[must_use]
    pub fn link(&self, interface: &str) -> Option<&Link> {
        self.links.get(interface)
    }

    /// The streams' messages, if a publication is due ([`Engine::poll_publication`]).
    pub fn poll_publication(&mut self, now: Now) -> Option<Publication> {
        self.engine.poll_publication(now)
    }

    /// Milliseconds from `now` until the host should call [`handle_timeout`](Self::handle_timeout)
    /// at the latest: the engine's timeout ([`Engine::until_timeout_ms`]) or the nearest
    /// deadline of a call to a module, whichever comes first (a deadline rounded up, so that it
    /// has passed then).
    #[must_use]
    pub fn until_timeout_ms(&self, now: Now) -> u64 {
        let deadline = self
            .flights
            .values()
            .map(|(_, deadline)| *deadline)
            .min()
            .map_or(u64::MAX, |deadline| {
                let left = deadline.saturating_sub(now.reading_ns).max(0);
                u64::try_from(left).unwrap_or(0).div_ceil(1_000_000)
            });
        self.engine.until_timeout_ms(now).min(deadline)
    }

    /// Whether nothing is on its way: no call queued or unanswered, no operator waiting.
    #[must_use]
    pub fn is_idle(&self) -> bool {
        self.queued.is_empty() && self.flights.is_empty() && self.operators.is_empty()
    }

    fn binding(&self, interface: &str) -> Option<&Binding> {
        self.engine
            .host()
            .rtc()
            .bindings()
            .iter()
            .find(|binding| binding.name == interface)
    }

    /// A status array of `interface` (`[COOP-RELAY-REPORT.1]`): each status reported through
    /// the interface's RTC adapter, each scene of the interface the array no longer lists
    /// removed. A late or repeated array, or one with an undefined constant, is refused whole;
    /// a status the adapter refuses is listed with its reason, and the others still count.
    ///
    /// # Errors
    /// [`ArrayError`]; nothing of the array reached the core (the core was still told the
    /// time).
    pub fn take_statuses(
        &mut self,
        interface: &str,
        array: &CooperateStatusArray,
        now: Now,
    ) -> Result<ArrayTaken, ArrayError> {
        self.engine.handle_timeout(now);
        let link = self
            .links
            .get(interface)
            .ok_or_else(|| ArrayError::UnknownInterface {
                name: interface.to_owned(),
            })?;
        let parsed = array.parse().map_err(|error| ArrayError::Constant {
            interface: interface.to_owned(),
            error,
        })?;
        if let Some(newest) = link.newest.filter(|&newest| array.stamp <= newest) {
            return Err(ArrayError::Late {
                interface: interface.to_owned(),
                stamp: array.stamp,
                newest,
            });
        }
        let mut taken = ArrayTaken::default();
        for (status, message) in parsed.iter().zip(&array.statuses) {
            let retired = self.state().retirement(status.id).is_some();
            if retired && status.phase.is_terminal() {
                // Upstream lists a finished scene until its module removes it.
                continue;
            }
            let Ok(report) = message.report() else {
                continue;
            };
            if let (Err(error), _) = self
                .engine
                .call(|host| report_sampled(host, interface, &report))
            {
                taken.refused.push((status.id, error));
            }
        }
        let listed: Vec<SceneId> = parsed.iter().map(|status| status.id).collect();
        let gone: Vec<SceneId> = {
            let rtc = self.engine.host().rtc();
            let state = self.engine.state();
            state
                .scenes()
                .map(|(id, _)| id)
                .filter(|id| !listed.contains(id))
                .filter(|&id| rtc.owner(state, id).is_some_and(|b| b.name == interface))
                .collect()
        };
        for id in gone {
            let (removed, _) = self
                .engine
                .call(|host| host.interface(interface)?.remove_cooperate_status(id));
            if removed.is_ok() {
                taken.removed.push(id);
            }
        }
        let idle = !self.busy(interface);
        if let Some(link) = self.links.get_mut(interface) {
            link.newest = Some(array.stamp);
            link.seen = parsed.iter().map(|s| (s.id, Seen::of(s))).collect();
            link.fresh |= idle;
        }
        self.correct(interface);
        Ok(taken)
    }

    /// The auto-mode status of `interface`.
    ///
    /// # Errors
    /// [`ArrayError::UnknownInterface`].
    pub fn take_auto_mode(
        &mut self,
        interface: &str,
        status: &AutoModeStatus,
        now: Now,
    ) -> Result<(), ArrayError> {
        self.engine.handle_timeout(now);
        let link = self
            .links
            .get_mut(interface)
            .ok_or_else(|| ArrayError::UnknownInterface {
                name: interface.to_owned(),
            })?;
        link.auto_mode = Some(status.is_auto_mode);
        self.correct(interface);
        Ok(())
    }

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

    fn queue(&mut self, interface: String, request: ModuleRequest, purpose: Purpose) -> CallId {
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

    /// Time between messages: calls past their deadline are unanswered, the core is told the
    /// time, and every idle module is corrected.
    pub fn handle_timeout(&mut self, now: Now) {
        self.engine.handle_timeout(now);
        let expired: Vec<CallId> = self
            .flights
            .iter()
            .filter(|(_, (_, deadline))| *deadline <= now.reading_ns)
            .map(|(&id, _)| id)
            .collect();
        for id in expired {
            let Some((flight, _)) = self.flights.remove(&id) else {
                continue;
            };
            if let Purpose::Operator(operator) = flight.purpose {
                if let Some(pending) = self.operators.get_mut(&operator) {
                    pending.expire(id);
                }
                self.finish(operator);
            }
        }
        let names: Vec<String> = self.links.keys().cloned().collect();
        for name in names {
            self.correct(&name);
        }
    }

    /// The next operator's answer that is ready.
    pub fn poll_answer(&mut self) -> Option<(OperatorCall, wire::Response)> {
        self.answers.pop_front()
    }

    /// Whether a call to `interface` is queued or unanswered, or an operator's call awaits it.
    fn busy(&self, interface: &str) -> bool {
        self.queued.iter().any(|(_, c)| c.interface == interface)
            || self.flights.values().any(|(c, _)| c.interface == interface)
            || self.operators.values().any(|p| p.awaits(interface))
    }

    /// Sends `interface` what makes it drive as the core decides, if it is idle and its newest
    /// status array came after its last answer (`[COOP-RELAY-FOLLOW.1]`).
    fn correct(&mut self, interface: &str) {
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

    /// Answers an operator's call whose parts are all settled: what the modules took is applied
    /// to the core, and the answer says success only if that is everything
    /// (`[COOP-RELAY-SUCCESS.1]`).
    fn finish(&mut self, operator: OperatorCall) {
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

impl Hash for Relay {
    /// Everything that decides what the relay does next, but not the engine's revision counter,
    /// which only labels publications.
    fn hash<H: Hasher>(&self, hasher: &mut H) {
        let state = self.engine.state();
        let rtc = self.engine.host().rtc();
        state.hash(hasher);
        self.engine.host().told_ms().hash(hasher);
        // The reading the core was last told of: the next step of the clock counts from it.
        self.engine.told(Time::default()).reading_ns.hash(hasher);
        for id in state
            .scenes()
            .map(|(id, _)| id)
            .chain(state.retired_by_id().map(|(id, _)| id))
        {
            rtc.owner(state, id).map(|b| b.name.as_str()).hash(hasher);
        }
        self.deadline_ms.hash(hasher);
        self.links.hash(hasher);
        self.queued.hash(hasher);
        self.flights.hash(hasher);
        self.operators.hash(hasher);
        for (operator, response) in &self.answers {
            operator.hash(hasher);
            response.status().hash(hasher);
        }
        self.next_call.hash(hasher);
    }
}

/// Reports `report` through `interface`. An array is a sample of the module's statuses: a
/// waiting or new scene the array shows succeeded or aborting ran in between, the only way there
/// upstream and here, so it is reported running first (`[COOP-RELAY-REPORT.1]`).
fn report_sampled(host: &mut Host, interface: &str, report: &StatusReport) -> Result<(), RtcError> {
    let unstated = report.sequence.is_none() && host.state().scene(report.id).is_none();
    let first = host
        .rtc()
        .bindings()
        .iter()
        .find(|binding| binding.name == interface)
        .filter(|binding| binding.sequences.len() > 1)
        .and_then(|binding| binding.sequences.first().cloned());
    let stated;
    let report = match first {
        // Upstream's status carries no sequence: a new scene of an interface that binds several
        // is its first's (avoidance: the shift out) (`[COOP-RELAY-REPORT.1]`).
        Some(sequence) if unstated => {
            stated = report.in_sequence(sequence);
            &stated
        }
        _ => report,
    };
    let phase = host.state().scene(report.id).map(cooperation::Scene::phase);
    let new = phase.is_none() && host.state().retirement(report.id).is_none();
    let waiting = new || phase == Some(Phase::Waiting);
    if waiting && matches!(report.phase, Phase::Succeeded | Phase::Aborting) {
        let running = StatusReport {
            phase: Phase::Running,
            ..*report
        };
        let mut trial = host.clone();
        trial
            .interface(interface)?
            .update_cooperate_status(&running)?;
        trial
            .interface(interface)?
            .update_cooperate_status(report)?;
        *host = trial;
        return Ok(());
    }
    host.interface(interface)?
        .update_cooperate_status(report)
        .map(drop)
}

/// An RTC command for scene `id` of `binding`'s interface.
fn rtc_command(binding: &Binding, id: SceneId, decision: Decision) -> CooperateCommand {
    CooperateCommand {
        uuid: id.into(),
        module: rtc::Module::new(binding.module_type.value()),
        command: rtc::Command::new(match decision {
            Decision::Activate => rtc::Command::ACTIVATE,
            Decision::Deactivate => rtc::Command::DEACTIVATE,
        }),
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
