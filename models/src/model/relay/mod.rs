//! The relay model: the relay (`cooperation_adapters::relay`) between an operator and a planning
//! module that speaks upstream's RTC endpoints ([`peer::Upstream`]), the calls between them
//! lost, their answers lost, the module's arrays taken when it publishes.
//!
//! `next_state` makes one move of one party: the module changes its scenes, restarts with new
//! identifiers, or is switched by someone else; the module publishes and the relay takes it;
//! the relay hands out a call, which is delivered, or lost; an answer is taken, or lost; the
//! clock runs to the deadline; the operator calls `set_commands` or `set_policies`, or reads an
//! answer. Every decision is the relay's own code (its `next_state` calls only the relay and
//! the peer); unless a [`RelayFault`] is planted, nothing here changes what the relay does.
//!
//! The properties ([`properties`]) have an oracle of their own: every command the module took
//! (from its answers), what each operator call asked, and the module's own `isActivated`.

mod properties;
mod step;

pub mod peer;

pub use properties::{properties, FOLLOW, SCENES, SHOWN, SUCCESS, SWITCH};
pub use step::{broken, RelayStep};

use std::collections::BTreeSet;

use cooperation::{Config, Decision, Limits, OperatorDecision, Phase, Policy, SceneId};
use cooperation_adapters::engine::{Engine, Options};
use cooperation_adapters::relay::{Forward, ModuleAnswer, ModuleRequest, OperatorCall, Relay};
use cooperation_adapters::rtc::{self, Rtc};
use cooperation_adapters::{wire, Time};
use peer::Upstream;
use serde::{Deserialize, Serialize};
use stateright::{Model, Property};

/// The interface the module speaks through.
pub const INTERFACE: &str = "lane_change_left";
/// Its behaviour, for `set_policies`.
const BEHAVIOR: &str = "lane-change";
/// How long the module has to answer, in milliseconds.
pub const DEADLINE_MS: u64 = 5;

/// A deliberately wrong relay or host, for showing that the properties can fail. Each wraps the
/// relay's calls or messages as a bug in it, or in the host around it, would behave; nothing of
/// it is compiled into the library.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum RelayFault {
    /// An operator's call the modules did not answer in time is answered as a success.
    SuccessOnTimeout,
    /// A commands call is answered by the host itself, every command a success, and never
    /// reaches the module.
    AnsweredForModule,
    /// The commands sent to the module are the opposite of those asked.
    CommandsInverted,
    /// The host stamps arrays when it reads them, so a late array is taken as new: each
    /// publication delivers the one before it.
    LateArrayRestamped,
    /// The host passes an operator decision a module cannot take for one scene (autonomous,
    /// none) on as deactivate, the nearest it can.
    InexpressibleAsDeactivate,
}

impl RelayFault {
    /// Every fault.
    pub const ALL: [Self; 5] = [
        Self::SuccessOnTimeout,
        Self::AnsweredForModule,
        Self::CommandsInverted,
        Self::LateArrayRestamped,
        Self::InexpressibleAsDeactivate,
    ];
}

/// The size of the relay model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RelayBounds {
    /// Scene identifiers, `1..=scenes`, each registered at most once (a restart uses new ones).
    pub scenes: usize,
    /// Operator calls.
    pub operator_calls: u8,
    /// Module moves other than registering: a change of `safe`, running, finishing, aborting,
    /// removal, a restart, a switch by someone else.
    pub module_moves: u8,
    /// Calls and answers lost, together.
    pub losses: u8,
    /// Whether a status array may reach the relay ahead of the auto-mode status published with
    /// it ([`RelayAction::PublishArray`]): they are two topics. It multiplies the states about
    /// 2.4 times.
    pub split: bool,
}

/// An action of the relay model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum RelayAction {
    /// The module registers a scene, waiting, safe or not.
    Register(SceneId, bool),
    /// The module flips a scene's `safe`.
    Flip(SceneId),
    /// The module starts running a scene.
    Run(SceneId),
    /// The module finishes a running scene (succeeded).
    Finish(SceneId),
    /// The module aborts a running scene.
    Abort(SceneId),
    /// The module removes a scene.
    Remove(SceneId),
    /// The planner restarts: its interface is new, built with `enable_rtc = true`.
    Restart,
    /// Someone else switches the module's auto mode.
    Switch(bool),
    /// The module publishes its status array and auto mode; the relay takes them.
    Publish,
    /// The module's status array arrives ahead of its auto-mode status, which comes with the
    /// next publication (they are two topics).
    PublishArray,
    /// The relay hands out its next call, and the module gets it and answers.
    Send,
    /// The relay hands out its next call, and it is lost.
    SendLost,
    /// The answer at this place is taken.
    Answer(usize),
    /// The answer at this place is lost.
    LoseAnswer(usize),
    /// The clock runs to the deadline.
    Expire,
    /// The operator sets a scene's decision.
    Command(SceneId, OperatorDecision),
    /// The operator sets the module's policy.
    Policy(Policy),
}

/// The relay model.
#[derive(Clone, Debug)]
pub struct RelayModel {
    bounds: RelayBounds,
    fault: Option<RelayFault>,
    focus: Option<&'static str>,
    ids: Vec<SceneId>,
}

impl RelayModel {
    /// The model at these bounds.
    ///
    /// # Errors
    /// If `scenes` is not 1 to 3.
    pub fn new(bounds: RelayBounds) -> Result<Self, String> {
        if !(1..=3).contains(&bounds.scenes) {
            return Err("scenes must be 1 to 3".to_owned());
        }
        let ids = (1..=bounds.scenes as u128)
            .map(SceneId::from_u128)
            .collect();
        Ok(Self {
            bounds,
            fault: None,
            focus: None,
            ids,
        })
    }

    /// The same model with `fault` planted.
    #[must_use]
    pub const fn with_fault(mut self, fault: RelayFault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The same model checking only the property named `property` (a search for its
    /// counterexample stops at the first).
    #[must_use]
    pub const fn focus(mut self, property: &'static str) -> Self {
        self.focus = Some(property);
        self
    }

    /// The planted fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<RelayFault> {
        self.fault
    }

    /// The relay's core configuration: every standard interface's module required (upstream's
    /// `enable_rtc = true`), ages far beyond the model's clock.
    fn config() -> Config {
        Config::new(Rtc::standard().policies(true)).with_limits(Limits {
            ttl_ms: 1_000_000,
            max_scenes: 3,
            retired_capacity: 3,
            max_batch: 3,
        })
    }

    /// The module's status array reaches the relay, and with `auto_mode` its auto-mode status
    /// too; without it the module still has something to publish.
    fn publish(&self, next: &mut RelayStep, auto_mode: bool) {
        next.publications += 1;
        let stamp = Time::new(i32::try_from(next.publications).unwrap_or(i32::MAX), 0);
        let mut array = next.module.status_array(stamp);
        if self.fault == Some(RelayFault::LateArrayRestamped) {
            if let Some(previous) = next.last_published.replace(next.module.clone()) {
                array = previous.status_array(stamp);
            }
        }
        let now = next.now();
        // A refused array changes nothing; the relay's refusal is logged by a host.
        drop(next.relay.take_statuses(INTERFACE, &array, now));
        next.array_ahead = !auto_mode;
        if !auto_mode {
            return;
        }
        drop(
            next.relay
                .take_auto_mode(INTERFACE, &next.module.auto_mode_status(), now),
        );
        next.told = Some(next.module.auto_mode);
        next.published_auto = Some(next.module.auto_mode);
        next.dirty = false;
    }

    fn deliver(&self, next: &mut RelayStep, forward: Forward) {
        let answer = match forward.request {
            ModuleRequest::Commands(mut request) => {
                if self.fault == Some(RelayFault::CommandsInverted) {
                    for command in &mut request.commands {
                        command.command = rtc::Command::new(1 - command.command.r#type.min(1));
                    }
                }
                let response = next.module.cooperate_commands(&request);
                for (command, answer) in request.commands.iter().zip(&response.responses) {
                    if answer.success {
                        let decision = if command.command.r#type == rtc::Command::ACTIVATE {
                            Decision::Activate
                        } else {
                            Decision::Deactivate
                        };
                        next.taken.insert((SceneId::from(command.uuid), decision));
                    }
                }
                ModuleAnswer::Commands(response)
            }
            ModuleRequest::AutoMode(request) => {
                next.switching.push((forward.call, request.enable));
                ModuleAnswer::AutoMode(next.module.enable_auto_mode(request.enable))
            }
        };
        next.dirty = true;
        next.answers.push((forward.call, answer));
    }

    fn operator(
        &self,
        next: &mut RelayStep,
        request: &wire::Request,
        asked: Vec<(SceneId, OperatorDecision)>,
    ) {
        let call = u64::from(next.spent.0);
        next.spent.0 += 1;
        let now = next.now();
        match next.relay.handle_operator(OperatorCall(call), request, now) {
            Some(response) => self.answered(next, call, &response, &asked),
            None => next.asked.push((call, asked)),
        }
    }

    /// The oracle's check of an answer: a success only if the module took every command.
    fn answered(
        &self,
        next: &mut RelayStep,
        _call: u64,
        response: &wire::Response,
        asked: &[(SceneId, OperatorDecision)],
    ) {
        let success = response.status().success;
        if success && asked.iter().any(|&(id, asked)| !next.took(id, asked)) {
            next.broken |= broken::SUCCESS;
        }
    }
}

impl RelayModel {
    /// The operator reads every answer the relay has ready.
    fn read(&self, next: &mut RelayStep) {
        while let Some((call, mut response)) = next.relay.poll_answer() {
            if self.fault == Some(RelayFault::SuccessOnTimeout)
                && response.status().code == wire::ResponseStatus::SERVICE_TIMEOUT
            {
                response = wire::Response::SetCommands(wire::SetCooperationCommandsResponse {
                    status: wire::ResponseStatus::success(),
                });
            }
            let Some(at) = next.asked.iter().position(|(asked, _)| *asked == call.0) else {
                continue;
            };
            let (_, asked) = next.asked.remove(at);
            self.answered(next, call.0, &response, &asked);
        }
    }
}

fn unreachable_relay() -> Relay {
    // The standard interfaces' quota fits the default table; `Engine::new` cannot fail here.
    let engine = Engine::new(
        Config::new(Rtc::standard().policies(true)),
        Options::default(),
    );
    match engine {
        Ok(engine) => Relay::new(engine, DEADLINE_MS),
        Err(error) => unreachable!("the standard configuration is refused: {error}"),
    }
}

impl Model for RelayModel {
    type State = RelayStep;
    type Action = RelayAction;

    fn init_states(&self) -> Vec<Self::State> {
        let relay = Engine::new(
            Self::config(),
            Options {
                scene_quota: 0,
                ..Options::default()
            },
        )
        .map_or_else(
            |_| unreachable_relay(),
            |engine| Relay::new(engine, DEADLINE_MS),
        );
        vec![RelayStep {
            relay,
            module: Upstream::new(rtc::Module::LANE_CHANGE_LEFT, true),
            used: BTreeSet::new(),
            dirty: true,
            last_published: None,
            publications: 0,
            answers: Vec::new(),
            asked: Vec::new(),
            taken: BTreeSet::new(),
            lost: 0,
            clock_ms: 0,
            spent: (0, 0, 0),
            broken: 0,
            array_ahead: false,
            published_auto: None,
            told: None,
            switching: Vec::new(),
        }]
    }

    fn actions(&self, state: &Self::State, actions: &mut Vec<Self::Action>) {
        let moves = state.spent.1 < self.bounds.module_moves;
        for &id in &self.ids {
            let listed = state.module.statuses.iter().find(|s| s.id == id);
            match listed {
                None if !state.used.contains(&id) => {
                    actions.push(RelayAction::Register(id, false));
                    actions.push(RelayAction::Register(id, true));
                }
                Some(status) if moves => {
                    actions.push(RelayAction::Flip(id));
                    if status.phase == Phase::Waiting {
                        actions.push(RelayAction::Run(id));
                    }
                    if status.phase == Phase::Running {
                        actions.push(RelayAction::Finish(id));
                        actions.push(RelayAction::Abort(id));
                    }
                    actions.push(RelayAction::Remove(id));
                }
                _ => {}
            }
        }
        if moves {
            actions.push(RelayAction::Restart);
            actions.push(RelayAction::Switch(!state.module.auto_mode));
        }
        let fresh = state.relay.link(INTERFACE).is_some_and(|link| link.fresh);
        let auto = state.relay.link(INTERFACE).and_then(|link| link.auto_mode);
        // A publication that could tell the relay something: the module changed, its auto mode
        // is not the one the relay has, or the relay awaits an array to judge it by.
        if state.dirty || auto != Some(state.module.auto_mode) || (!fresh && state.relay.is_idle())
        {
            actions.push(RelayAction::Publish);
            // Which of the two topics comes first matters only when the auto mode changed.
            if self.bounds.split
                && !state.array_ahead
                && state.published_auto != Some(state.module.auto_mode)
            {
                actions.push(RelayAction::PublishArray);
            }
        }
        let lose = state.spent.2 < self.bounds.losses;
        let mut probe = state.relay.clone();
        if probe.poll_forward(state.now()).is_some() {
            actions.push(RelayAction::Send);
            if lose {
                actions.push(RelayAction::SendLost);
            }
        }
        for at in 0..state.answers.len() {
            actions.push(RelayAction::Answer(at));
            if lose {
                actions.push(RelayAction::LoseAnswer(at));
            }
        }
        // Time matters only to a call that will never be answered.
        if state.lost > 0 {
            actions.push(RelayAction::Expire);
        }
        if state.spent.0 < self.bounds.operator_calls {
            for (id, _) in state.relay.state().scenes() {
                for decision in OperatorDecision::ALL {
                    actions.push(RelayAction::Command(id, decision));
                }
            }
            actions.push(RelayAction::Policy(Policy::Optional));
            actions.push(RelayAction::Policy(Policy::Required));
        }
    }

    fn next_state(&self, last: &Self::State, action: Self::Action) -> Option<Self::State> {
        let mut next = last.clone();
        match action {
            RelayAction::Register(id, safe) => {
                next.module.update(id, safe, Phase::Waiting, false);
                next.used.insert(id);
                next.dirty = true;
            }
            RelayAction::Flip(id)
            | RelayAction::Run(id)
            | RelayAction::Finish(id)
            | RelayAction::Abort(id) => {
                let status = next.module.statuses.iter().find(|s| s.id == id)?;
                let (safe, phase) = match action {
                    RelayAction::Flip(_) => (!status.safe, status.phase),
                    RelayAction::Run(_) => (status.safe, Phase::Running),
                    RelayAction::Finish(_) => (status.safe, Phase::Succeeded),
                    _ => (status.safe, Phase::Aborting),
                };
                let requested = status.requested;
                next.module.update(id, safe, phase, requested);
                next.spent.1 += 1;
                next.dirty = true;
            }
            RelayAction::Remove(id) => {
                next.module.remove(id);
                next.spent.1 += 1;
                next.dirty = true;
            }
            RelayAction::Restart => {
                next.module = Upstream::new(rtc::Module::LANE_CHANGE_LEFT, true);
                next.spent.1 += 1;
                next.dirty = true;
            }
            RelayAction::Switch(enable) => {
                next.module.enable_auto_mode(enable);
                next.spent.1 += 1;
                next.dirty = true;
            }
            RelayAction::Publish => self.publish(&mut next, true),
            RelayAction::PublishArray => self.publish(&mut next, false),
            RelayAction::Send | RelayAction::SendLost => {
                let now = next.now();
                let forward = next.relay.poll_forward(now)?;
                if let ModuleRequest::AutoMode(request) = &forward.request {
                    // With no operator's call waiting, the switch is the relay's own (an
                    // operator's `set_policies` is always sent, `[COOP-RELAY-POLICY.1]`).
                    if next.asked.is_empty() && next.told == Some(request.enable) {
                        next.broken |= broken::NEEDLESS;
                    }
                    next.told = None;
                }
                if action == RelayAction::SendLost {
                    next.spent.2 += 1;
                    next.lost += 1;
                } else if self.fault == Some(RelayFault::AnsweredForModule)
                    && matches!(forward.request, ModuleRequest::Commands(_))
                {
                    if let ModuleRequest::Commands(request) = &forward.request {
                        let response = rtc::CooperateCommandsResponse::answering(request, true);
                        next.answers
                            .push((forward.call, ModuleAnswer::Commands(response)));
                    }
                } else {
                    self.deliver(&mut next, forward);
                }
            }
            RelayAction::Answer(at) => {
                let (call, answer) = next.answers.get(at)?.clone();
                next.answers.remove(at);
                if let Some(place) = next.switching.iter().position(|(of, _)| *of == call) {
                    let (_, enable) = next.switching.remove(place);
                    if answer == ModuleAnswer::AutoMode(true) {
                        next.told = Some(enable);
                    }
                }
                let now = next.now();
                next.relay.take_answer(call, &answer, now);
            }
            RelayAction::LoseAnswer(at) => {
                let (call, _) = next.answers.get(at)?;
                let call = *call;
                next.answers.remove(at);
                next.switching.retain(|(of, _)| *of != call);
                next.spent.2 += 1;
                next.lost += 1;
            }
            RelayAction::Expire => {
                // Every call sent so far is past its deadline.
                next.clock_ms += DEADLINE_MS;
                next.lost = 0;
                let now = next.now();
                next.relay.handle_timeout(now);
            }
            RelayAction::Command(id, decision) => {
                let sent = match (self.fault, decision) {
                    (
                        Some(RelayFault::InexpressibleAsDeactivate),
                        OperatorDecision::Autonomous | OperatorDecision::Undecided,
                    ) => OperatorDecision::Deactivate,
                    _ => decision,
                };
                // The AD API's codes, written here from the message definition
                // (`CooperationDecision.msg`), not through the adapters' conversion under check.
                let code = match sent {
                    OperatorDecision::Deactivate => 1,
                    OperatorDecision::Activate => 2,
                    OperatorDecision::Autonomous => 3,
                    OperatorDecision::Undecided => 4,
                };
                let json = format!(
                    r#"{{"commands": [{{"uuid": {{"uuid": {:?}}}, "cooperator": {{"decision": {code}}}}}]}}"#,
                    id.to_bytes()
                );
                let request = wire::Service::SetCommands.read(json.as_bytes()).ok()?;
                self.operator(&mut next, &request, vec![(id, decision)]);
            }
            RelayAction::Policy(policy) => {
                let code = if policy == Policy::Optional { 1 } else { 2 };
                let json = format!(
                    r#"{{"policies": [{{"behavior": "{BEHAVIOR}", "sequence": "", "policy": {code}}}]}}"#
                );
                let request = wire::Service::SetPolicies.read(json.as_bytes()).ok()?;
                self.operator(&mut next, &request, Vec::new());
            }
        }
        self.read(&mut next);
        Some(next)
    }

    fn properties(&self) -> Vec<Property<Self>> {
        let mut all = properties();
        if let Some(focus) = self.focus {
            all.retain(|property| property.name == focus);
        }
        all
    }
}
