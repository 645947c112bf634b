//! The network model: the planner and two operators as separate parties, with status and
//! command messages in flight that are delayed, reordered, duplicated and lost.
//!
//! The planner holds the library's [`State`] and applies owner inputs and delivered commands
//! through [`State::apply`] (or a [`Fault`] wrapper around it); the operators only hold
//! what they were last told. Which messages exist and when they can be sent, delivered,
//! duplicated or lost is the environment, modelled here; what a message does to the planner is
//! the library's, and nothing of it is restated.

use std::sync::OnceLock;

use cooperation::{
    Behavior, Command, Config, CooperationStatus, Decision, Geometry, Input, Limits, Module,
    OperatorDecision, Phase, Policy, Rejection, Rule, SceneId, State, Transition,
};
use serde::{Deserialize, Serialize};
use stateright::{Model, Property, Representative};

use crate::budget::Halt;
use crate::describe::{describe, short};
use crate::ids::{index, ModelError, MAX_SCENES};
use crate::Fault;

/// How many operators act at once.
pub const OPERATORS: usize = 2;
/// How many status messages can be in flight to each operator.
pub const STATUSES_IN_FLIGHT: usize = 1;
/// How many command messages can be in flight, from both operators together.
pub const COMMANDS_IN_FLIGHT: usize = 2;

const MODULE: Module = Module::new(Behavior::LaneChange);

/// The size of the network model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct NetBounds {
    /// Scene identifiers, `1..=scenes`, all of one lane-change module.
    pub scenes: usize,
}

/// A scene as a status message tells of it: its identifier (taken from the planner's
/// `CooperationStatus` list), with the incarnation of the identifier when it was sent (a history
/// annotation: how many times that identifier had become live).
///
/// The decisions a status also carries are left out of the network model: which scene a
/// command reaches, and when, is what this model is about, and the decisions' semantics are
/// checked exhaustively by the sequential model. Leaving them out keeps the model small enough
/// to check to completion.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Seen {
    /// The scene.
    pub id: SceneId,
    /// The identifier's incarnation then.
    pub incarnation: u8,
}

/// A status list from the planner to an operator.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct StatusMessage {
    /// The planner's statuses when it was sent.
    pub seen: Vec<Seen>,
    /// The planner has not changed since it was sent.
    pub fresh: bool,
}

/// A command from an operator to the planner, built from the operator's view.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct CommandMessage {
    /// The command.
    pub command: Command,
    /// The incarnation of the identifier in the view it was built from.
    pub incarnation: u8,
}

/// An action of the network model.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum NetAction {
    /// A scene owner's input, by position in the owner alphabet.
    Owner(usize),
    /// The planner sends its statuses to an operator.
    Publish(usize),
    /// An operator receives the status message at this position of its channel.
    Receive(usize, usize),
    /// An operator sends a command for a scene in its view.
    Send(usize, SceneId, OperatorDecision),
    /// The planner receives the command message at this position of an operator's channel.
    Deliver(usize, usize),
    /// An operator receives a duplicate of the status message at this position: it gets the
    /// statuses and the message stays in flight.
    ReceiveDuplicate(usize, usize),
    /// The network duplicates a command message.
    DuplicateCommand(usize, usize),
    /// The network loses a status message.
    LoseStatus(usize, usize),
    /// The network loses a command message.
    LoseCommand(usize, usize),
}

/// A state of the network model.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize)]
pub struct NetStep {
    /// The planner's state.
    pub core: State,
    /// The rule the planner's last input fired or was rejected by.
    pub last: Option<Rule>,
    /// What each operator was last told.
    pub views: [Vec<Seen>; OPERATORS],
    /// Whether each operator's view was sent after the planner's last change.
    pub fresh: [bool; OPERATORS],
    /// Status messages in flight to each operator (a multiset, sorted).
    pub statuses: [Vec<StatusMessage>; OPERATORS],
    /// Command messages in flight from each operator (a multiset, sorted).
    pub commands: [Vec<CommandMessage>; OPERATORS],
    /// How many times each identifier became live (saturating).
    pub incarnation: [u8; MAX_SCENES],
    /// Sticky flags of broken step properties.
    pub broken: u8,
}

impl Representative for NetStep {
    /// No reduction: the operators' channels are ordered by position, not symmetric.
    fn representative(&self) -> Self {
        self.clone()
    }
}

const SPILLED: u8 = 1;
const STALE_TOUCHED_NEW: u8 = 1 << 1;
const SECOND_EFFECT: u8 = 1 << 2;
const REJECTION_CHANGED: u8 = 1 << 3;

/// The network model.
#[derive(Clone, Debug)]
pub struct NetworkModel {
    bounds: NetBounds,
    fault: Option<Fault>,
    focus: Option<&'static str>,
    halt: Halt,
    config: Config,
    ids: Vec<SceneId>,
    owner: Vec<Input>,
}

impl NetworkModel {
    /// The model at these bounds.
    ///
    /// # Errors
    /// If `scenes` is not 1 to 8.
    pub fn new(bounds: NetBounds) -> Result<Self, ModelError> {
        if !(1..=MAX_SCENES).contains(&bounds.scenes) {
            return Err(ModelError::Bounds(format!(
                "scenes must be 1 to {MAX_SCENES}"
            )));
        }
        let config = Config {
            policies: [(MODULE, Policy::Optional)].into(),
            limits: Limits {
                ttl_ms: 1,
                max_scenes: bounds.scenes,
                retired_capacity: bounds.scenes,
                max_batch: 2,
            },
        };
        let ids: Vec<SceneId> = (1..=bounds.scenes as u128)
            .map(SceneId::from_u128)
            .collect();
        let geometry = Geometry::velocity(0.0);
        let mut owner = Vec::new();
        for &id in &ids {
            let decision = Decision::Deactivate;
            owner.push(Input::Register {
                id,
                module: MODULE,
                decision,
                requested: false,
                geometry,
            });
            for phase in [Phase::Running, Phase::Succeeded] {
                let decision = Decision::Activate;
                owner.push(Input::Update {
                    id,
                    module: MODULE,
                    phase,
                    decision,
                    requested: false,
                    geometry,
                });
            }
        }
        Ok(Self {
            bounds,
            fault: None,
            focus: None,
            halt: Halt::new(),
            config,
            ids,
            owner,
        })
    }

    /// The same model with a deliberately wrong behaviour injected.
    #[must_use]
    pub fn with_fault(mut self, fault: Fault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The same model checking only the named property.
    #[must_use]
    pub fn focus(mut self, property: &'static str) -> Self {
        self.focus = Some(property);
        self
    }

    /// The same model, stopped by `halt` (see [`crate::budget`]).
    #[must_use]
    pub fn with_halt(mut self, halt: Halt) -> Self {
        self.halt = halt;
        self
    }

    /// The bounds.
    #[must_use]
    pub const fn bounds(&self) -> NetBounds {
        self.bounds
    }

    /// The injected fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// The planner's transition: `State::apply` on a copy, or the faulty wrapper around it.
    fn transition(&self, core: &State, input: &Input) -> (State, Result<Transition, Rejection>) {
        crate::fault::transition(self.fault, core, input)
    }

    /// The initial state: nothing registered, nothing sent.
    ///
    /// # Errors
    /// If the configuration is refused (never).
    pub fn initial(&self) -> Result<NetStep, ModelError> {
        let core =
            State::new(self.config.clone()).map_err(|e| ModelError::Bounds(e.to_string()))?;
        Ok(NetStep {
            core,
            last: None,
            views: Default::default(),
            fresh: [false; OPERATORS],
            statuses: Default::default(),
            commands: Default::default(),
            incarnation: [0; MAX_SCENES],
            broken: 0,
        })
    }

    /// Every step of a path of actions, the initial state first (actions that are not enabled
    /// are skipped, as the checker would never take them).
    ///
    /// # Errors
    /// If the model cannot start.
    pub fn replay(&self, actions: &[NetAction]) -> Result<Vec<NetStep>, ModelError> {
        let mut steps = vec![self.initial()?];
        for action in actions {
            let next = steps
                .last()
                .and_then(|last| self.next_state(last, action.clone()));
            steps.extend(next);
        }
        Ok(steps)
    }

    /// One action in words.
    #[must_use]
    pub fn describe(&self, action: &NetAction) -> String {
        match action {
            NetAction::Owner(i) => self
                .owner
                .get(*i)
                .map_or_else(|| format!("owner input {i}"), describe),
            NetAction::Publish(k) => format!("planner sends its statuses to operator {}", k + 1),
            NetAction::Receive(k, m) => format!("operator {} receives status message {m}", k + 1),
            NetAction::Send(k, id, decision) => {
                format!(
                    "operator {} sends set_commands [{} {decision}]",
                    k + 1,
                    short(*id)
                )
            }
            NetAction::Deliver(k, m) => {
                format!("planner receives operator {}'s command message {m}", k + 1)
            }
            NetAction::ReceiveDuplicate(k, m) => {
                format!(
                    "operator {} receives a duplicate of status message {m}",
                    k + 1
                )
            }
            NetAction::DuplicateCommand(k, m) => format!(
                "network duplicates operator {}'s command message {m}",
                k + 1
            ),
            NetAction::LoseStatus(k, m) => {
                format!("network loses status message {m} to operator {}", k + 1)
            }
            NetAction::LoseCommand(k, m) => {
                format!("network loses operator {}'s command message {m}", k + 1)
            }
        }
    }

    /// The planner's statuses as an operator would see them now.
    fn snapshot(&self, step: &NetStep) -> Vec<Seen> {
        let mut statuses = Vec::new();
        step.core.statuses_into(&mut statuses);
        statuses
            .into_iter()
            .map(|status: CooperationStatus| {
                let incarnation = index(status.id)
                    .and_then(|i| step.incarnation.get(i))
                    .copied()
                    .unwrap_or(0);
                Seen {
                    id: status.id,
                    incarnation,
                }
            })
            .collect()
    }

    /// Applies a planner input and records what changed.
    fn planner(
        &self,
        from: &NetStep,
        next: &mut NetStep,
        input: &Input,
    ) -> Result<Transition, Rejection> {
        let (core, result) = self.transition(&from.core, input);
        next.last = Some(match &result {
            Ok(transition) => transition.rule,
            Err(rejection) => rejection.rule(),
        });
        if result.is_err() && core != from.core {
            next.broken |= REJECTION_CHANGED;
        }
        if core != from.core {
            for id in &self.ids {
                let became_live = core.scene(*id).is_some() && from.core.scene(*id).is_none();
                if let (true, Some(count)) = (
                    became_live,
                    index(*id).and_then(|i| next.incarnation.get_mut(i)),
                ) {
                    *count = count.saturating_add(1).min(3);
                }
            }
            // Whatever was sent before this change no longer describes the planner.
            next.fresh = [false; OPERATORS];
            for channel in &mut next.statuses {
                for message in channel.iter_mut() {
                    message.fresh = false;
                }
                channel.sort();
            }
        }
        next.core = core;
        result
    }
}

impl Model for NetworkModel {
    type State = NetStep;
    type Action = NetAction;

    fn init_states(&self) -> Vec<NetStep> {
        self.initial().into_iter().collect()
    }

    fn actions(&self, step: &NetStep, actions: &mut Vec<NetAction>) {
        if self.halt.is_set() {
            return;
        }
        actions.extend((0..self.owner.len()).map(NetAction::Owner));
        let room = step.commands.iter().map(Vec::len).sum::<usize>() < COMMANDS_IN_FLIGHT;
        for k in 0..OPERATORS {
            let statuses = step.statuses.get(k).map_or(0, Vec::len);
            let commands = step.commands.get(k).map_or(0, Vec::len);
            if statuses < STATUSES_IN_FLIGHT {
                actions.push(NetAction::Publish(k));
            }
            for m in 0..statuses {
                actions.push(NetAction::Receive(k, m));
                actions.push(NetAction::ReceiveDuplicate(k, m));
                actions.push(NetAction::LoseStatus(k, m));
            }
            if room {
                // Operator 1 approves, operator 2 holds back: two operators acting at once
                // disagree.
                let decision = if k == 0 {
                    OperatorDecision::Activate
                } else {
                    OperatorDecision::Deactivate
                };
                for seen in step.views.get(k).into_iter().flatten() {
                    actions.push(NetAction::Send(k, seen.id, decision));
                }
            }
            for m in 0..commands {
                actions.push(NetAction::Deliver(k, m));
                actions.push(NetAction::LoseCommand(k, m));
                if room {
                    actions.push(NetAction::DuplicateCommand(k, m));
                }
            }
        }
    }

    fn within_boundary(&self, _: &NetStep) -> bool {
        !self.halt.is_set()
    }

    fn next_state(&self, from: &NetStep, action: NetAction) -> Option<NetStep> {
        let mut next = from.clone();
        next.last = None;
        match action {
            NetAction::Owner(i) => {
                let input = self.owner.get(i)?;
                let _ = self.planner(from, &mut next, input);
            }
            NetAction::Publish(k) => {
                let message = StatusMessage {
                    seen: self.snapshot(from),
                    fresh: true,
                };
                let channel = next.statuses.get_mut(k)?;
                channel.push(message);
                channel.sort();
            }
            NetAction::Receive(k, m) => {
                let channel = next.statuses.get_mut(k)?;
                (m < channel.len()).then_some(())?;
                let message = channel.remove(m);
                *next.views.get_mut(k)? = message.seen;
                *next.fresh.get_mut(k)? = message.fresh;
            }
            NetAction::Send(k, id, decision) => {
                let incarnation = from.views.get(k)?.iter().find(|s| s.id == id)?.incarnation;
                let channel = next.commands.get_mut(k)?;
                channel.push(CommandMessage {
                    command: Command { id, decision },
                    incarnation,
                });
                channel.sort();
            }
            NetAction::Deliver(k, m) => {
                let channel = next.commands.get_mut(k)?;
                (m < channel.len()).then_some(())?;
                let message = channel.remove(m);
                let input = Input::SetCommands {
                    commands: vec![message.command],
                };
                let result = self.planner(from, &mut next, &input);
                observe_delivery(from, &mut next, &message, &input, &result, self);
            }
            NetAction::ReceiveDuplicate(k, m) => {
                let message = from.statuses.get(k)?.get(m)?.clone();
                *next.views.get_mut(k)? = message.seen;
                *next.fresh.get_mut(k)? = message.fresh;
            }
            NetAction::DuplicateCommand(k, m) => {
                let channel = next.commands.get_mut(k)?;
                let copy = *channel.get(m)?;
                channel.push(copy);
                channel.sort();
            }
            NetAction::LoseStatus(k, m) => {
                let channel = next.statuses.get_mut(k)?;
                (m < channel.len()).then_some(())?;
                channel.remove(m);
            }
            NetAction::LoseCommand(k, m) => {
                let channel = next.commands.get_mut(k)?;
                (m < channel.len()).then_some(())?;
                channel.remove(m);
            }
        }
        Some(next)
    }

    fn format_action(&self, action: &NetAction) -> String {
        self.describe(action)
    }

    fn properties(&self) -> Vec<Property<Self>> {
        let mut all = properties();
        if let Some(focus) = self.focus {
            all.retain(|p| p.name == focus);
        }
        all
    }
}

/// The step properties of a delivered command, recorded as sticky flags.
fn observe_delivery(
    from: &NetStep,
    next: &mut NetStep,
    message: &CommandMessage,
    input: &Input,
    result: &Result<Transition, Rejection>,
    model: &NetworkModel,
) {
    let id = message.command.id;
    // Only the named scene's operator decision may change.
    let spilled = from.core.scenes().any(|(other, old)| {
        let new = next.core.scene(other);
        let operator_moved =
            new.map(cooperation::Scene::operator_decision) != Some(old.operator_decision());
        let rest_moved = match new {
            None => true,
            Some(new) => {
                new.phase() != old.phase()
                    || new.module_decision() != old.module_decision()
                    || new.age_ms() != old.age_ms()
            }
        };
        rest_moved || (operator_moved && other != id)
    }) || from.core.scene_count() != next.core.scene_count();
    if spilled {
        next.broken |= SPILLED;
    }
    // A command built from a view of an earlier incarnation never changes a later one.
    let changed = from
        .core
        .scene(id)
        .map(cooperation::Scene::operator_decision)
        != next
            .core
            .scene(id)
            .map(cooperation::Scene::operator_decision)
        || (from.core.scene(id).is_none() && next.core.scene(id).is_some());
    let current = index(id)
        .and_then(|i| next.incarnation.get(i))
        .copied()
        .unwrap_or(0);
    if changed && current != message.incarnation {
        next.broken |= STALE_TOUCHED_NEW;
    }
    // Applying it again at once has no second effect.
    if result.is_ok() {
        let (again, _) = model.transition(&next.core, input);
        if again != next.core {
            next.broken |= SECOND_EFFECT;
        }
    }
}

type Condition = fn(&NetworkModel, &NetStep) -> bool;

fn unbroken<const FLAG: u8>(_: &NetworkModel, step: &NetStep) -> bool {
    step.broken & FLAG == 0
}

/// A view sent after the planner's last change is exactly the planner's statuses.
fn fresh_views_are_current(model: &NetworkModel, step: &NetStep) -> bool {
    let current = model.snapshot(step);
    step.views
        .iter()
        .zip(step.fresh)
        .all(|(view, fresh)| !fresh || *view == current)
}

fn invariants_hold(_: &NetworkModel, step: &NetStep) -> bool {
    step.core.check_invariants().is_ok()
}

/// Witness: with nothing in flight, both operators see the planner as it is.
fn views_converge(model: &NetworkModel, step: &NetStep) -> bool {
    let current = model.snapshot(step);
    let quiet = step.statuses.iter().all(Vec::is_empty) && step.commands.iter().all(Vec::is_empty);
    quiet && !current.is_empty() && step.views.iter().all(|view| *view == current)
}

/// Witness: a command is in flight for a scene that has completed.
fn completes_with_command_in_flight(_: &NetworkModel, step: &NetStep) -> bool {
    step.commands.iter().flatten().any(|m| {
        step.core
            .retirement(m.command.id)
            .is_some_and(|r| r.reason == cooperation::RetireReason::Succeeded)
    })
}

/// Witness: a new scene is live while a command for another one is in flight.
fn registers_with_command_in_flight(_: &NetworkModel, step: &NetStep) -> bool {
    step.commands.iter().flatten().any(|m| {
        step.core.scenes().any(|(id, _)| id != m.command.id)
            && index(m.command.id)
                .and_then(|i| step.incarnation.get(i))
                .is_some_and(|n| *n > 0)
    })
}

/// Witness: both operators have a command in flight.
fn two_operators_at_once(_: &NetworkModel, step: &NetStep) -> bool {
    step.commands.iter().all(|channel| !channel.is_empty())
}

/// Witness: a command reaches the planner after its scene retired, and is refused.
fn late_command_refused(_: &NetworkModel, step: &NetStep) -> bool {
    step.last == Some(Rule::CommandRetired)
}

/// Every property of the network model.
#[must_use]
pub fn properties() -> Vec<Property<NetworkModel>> {
    static ALL: OnceLock<Vec<(bool, &'static str, Condition)>> = OnceLock::new();
    ALL.get_or_init(|| {
        vec![
            (true, "COOP-CMD-APPLY.1 (network): a command affects only the scene it names", unbroken::<SPILLED>),
            (true, "COOP-REG-RETIRED.1 (network): a command built from a stale status never touches a newer scene", unbroken::<STALE_TOUCHED_NEW>),
            (true, "COOP-CMD-APPLY.1 (network): a duplicated command has no second effect", unbroken::<SECOND_EFFECT>),
            (true, "spec §4 (network): a rejected input changes nothing", unbroken::<REJECTION_CHANGED>),
            (true, "COOP-OUT-STATUS.1 (network): a view sent since the planner's last change is its current status", fresh_views_are_current),
            (true, "COOP-INV-* (network): State::check_invariants holds", invariants_hold),
            (false, "witness: the operators' views converge once messages stop", views_converge),
            (false, "witness: a scene completes while a command for it is in flight", completes_with_command_in_flight),
            (false, "witness: a new scene registers while a command for another is in flight", registers_with_command_in_flight),
            (false, "witness: two operators have commands in flight at once", two_operators_at_once),
            (false, "witness: a command arrives after its scene retired and is refused", late_command_refused),
        ]
    })
    .iter()
    .map(|&(always, name, condition)| {
        if always {
            Property::always(name, condition)
        } else {
            Property::sometimes(name, condition)
        }
    })
    .collect()
}
