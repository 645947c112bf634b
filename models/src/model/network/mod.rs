//! The network model: the planner and one or two operators as separate parties, with status
//! and command messages in flight that are delayed, reordered, duplicated and lost.
//!
//! The planner holds the library's [`State`] and applies owner inputs and delivered commands
//! through [`State::apply`] (or a [`Fault`] wrapper around it); the operators only hold
//! what they were last told. Which messages exist and when they can be sent, delivered,
//! duplicated or lost is the environment, modelled here; what a message does to the planner is
//! the library's, and nothing of it is restated.
//!
//! What a status message tells an operator is the model's [`Views`]: which scenes exist (their
//! identifiers), or their whole statuses as the library reports them, decisions included.
//!
//! [`NetworkModel::through_engine`] makes the planner a node instead: the service engine, fed
//! reports as a module's sync and commands as `set_commands` requests, publishing when it says
//! a publication is due, its statuses read back from the factors it writes (`engine.rs`).

mod describe;
mod engine;
mod properties;
mod views;

pub use engine::{Planner, PlannerKind};
pub use properties::{properties, reported};
pub use views::Views;

use cooperation::{
    Behavior, Command, Config, CooperationStatus, Input, Limits, Module, OperatorDecision, Policy,
    Rejection, Rule, SceneId, State, Transition,
};
use serde::{Deserialize, Serialize};
use stateright::{Model, Property, Representative};
use std::borrow::Cow;

use describe::owner_inputs;
use properties::{observe_delivery, observe_owner, observe_publish, REJECTION_CHANGED};

use crate::check::budget::Halt;
use crate::model::ids::{index, ModelError, MAX_SMALL_SCENES};
use crate::Fault;

/// The most operators that act at once, and how many do unless the model says otherwise
/// ([`NetworkModel::with_operators`]).
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
/// annotation: how many times that identifier had become live), and, with [`Views::Statuses`],
/// the status itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Seen {
    /// The scene.
    pub id: SceneId,
    /// The identifier's incarnation then.
    pub incarnation: u8,
    /// The library's status of the scene when it was sent, with [`Views::Statuses`]; `None`
    /// with [`Views::Identifiers`].
    pub status: Option<CooperationStatus>,
}

/// A status list from the planner to an operator.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct StatusMessage {
    /// The planner's statuses when it was sent.
    pub seen: Vec<Seen>,
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
    /// The planner's engine publishes, a publication being due
    /// ([`NetworkModel::through_engine`]): every acting operator's channel gets the message,
    /// in place of one still unread (a topic keeps its last message for each subscriber).
    PublishAll,
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
    /// The planner's engine, whose core `core` copies ([`NetworkModel::through_engine`]).
    #[serde(skip)]
    pub planner: Option<Planner>,
    /// The rule the planner's last input fired or was rejected by.
    pub last: Option<Rule>,
    /// What each operator was last told.
    pub views: [Vec<Seen>; OPERATORS],
    /// Status messages in flight to each operator (a multiset, sorted).
    pub statuses: [Vec<StatusMessage>; OPERATORS],
    /// Command messages in flight from each operator (a multiset, sorted).
    pub commands: [Vec<CommandMessage>; OPERATORS],
    /// How many times each identifier became live (saturating).
    pub incarnation: [u8; MAX_SMALL_SCENES],
    /// Sticky flags of broken step properties.
    pub broken: u8,
}

impl Representative for NetStep {
    /// No reduction: the operators' channels are ordered by position, not symmetric.
    fn representative(&self) -> Self {
        self.clone()
    }
}

/// The network model.
#[derive(Clone, Debug)]
pub struct NetworkModel {
    bounds: NetBounds,
    operators: usize,
    views: Views,
    fault: Option<Fault>,
    focus: Option<&'static str>,
    halt: Halt,
    config: Config,
    ids: Vec<SceneId>,
    owner: Vec<Input>,
    planner: PlannerKind,
}

impl NetworkModel {
    /// The model at these bounds.
    ///
    /// # Errors
    /// If `scenes` is not 1 to 8.
    pub fn new(bounds: NetBounds) -> Result<Self, ModelError> {
        if !(1..=MAX_SMALL_SCENES).contains(&bounds.scenes) {
            return Err(ModelError::Bounds(format!(
                "scenes must be 1 to {MAX_SMALL_SCENES}"
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
        let owner = owner_inputs(&ids, Views::Identifiers);
        Ok(Self {
            bounds,
            operators: OPERATORS,
            views: Views::Identifiers,
            fault: None,
            focus: None,
            halt: Halt::new(),
            config,
            ids,
            owner,
            planner: PlannerKind::Core,
        })
    }

    /// The same model with `operators` operators (1 or 2; 2 unless said).
    ///
    /// # Errors
    /// If `operators` is not 1 or 2.
    pub fn with_operators(mut self, operators: usize) -> Result<Self, ModelError> {
        if !(1..=OPERATORS).contains(&operators) {
            return Err(ModelError::Bounds(format!(
                "operators must be 1 to {OPERATORS}"
            )));
        }
        self.operators = operators;
        Ok(self)
    }

    /// The same model telling operators `views` (identifiers unless said). With
    /// [`Views::Statuses`], an owner can also abort a scene, so that statuses can say a scene
    /// is not cancellable.
    #[must_use]
    pub fn with_views(mut self, views: Views) -> Self {
        self.views = views;
        self.owner = owner_inputs(&self.ids, views);
        self
    }

    /// The same model with the planner a node: the service engine, reports sent as a planning
    /// module's sync, commands as `set_commands` requests, statuses published when the engine
    /// says one is due and read back from the factors it writes (`engine.rs`). A fault of
    /// the core ([`with_fault`](Self::with_fault)) cannot be planted in the engine's core: such
    /// a model has no initial state ([`initial`](Self::initial) says why).
    #[must_use]
    pub const fn through_engine(self) -> Self {
        self.with_planner(PlannerKind::Engine {
            written_fault: None,
        })
    }

    /// The same model with `planner` as its planner.
    #[must_use]
    pub const fn with_planner(mut self, planner: PlannerKind) -> Self {
        self.planner = planner;
        self
    }

    /// What the planner is.
    #[must_use]
    pub const fn planner(&self) -> PlannerKind {
        self.planner
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

    /// The same model, stopped by `halt` (see [`crate::check::budget`]).
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

    /// How many operators act.
    #[must_use]
    pub const fn operators(&self) -> usize {
        self.operators
    }

    /// What status messages tell the operators.
    #[must_use]
    pub const fn views(&self) -> Views {
        self.views
    }

    /// The injected fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// The planner's transition: `State::after` (`State::apply` on a copy, made only for an
    /// accepted input), or the faulty wrapper around `apply`.
    fn transition<'a>(
        &self,
        core: &'a State,
        input: &Input,
    ) -> (Cow<'a, State>, Result<Transition, Rejection>) {
        crate::model::fault::transition(self.fault, core, input)
    }

    /// The initial state: nothing registered, nothing sent.
    ///
    /// # Errors
    /// If the configuration is refused (never).
    pub fn initial(&self) -> Result<NetStep, ModelError> {
        let core =
            State::new(self.config.clone()).map_err(|e| ModelError::Bounds(e.to_string()))?;
        let planner = if self.planner != PlannerKind::Core {
            if let Some(fault) = self.fault {
                return Err(ModelError::Bounds(format!(
                    "{fault:?} is a fault of the core's transition, which the engine calls itself: \
                     it cannot be planted through the engine"
                )));
            }
            Some(Planner::new(self.config.clone()).map_err(ModelError::Bounds)?)
        } else {
            None
        };
        Ok(NetStep {
            core,
            planner,
            last: None,
            views: Default::default(),
            statuses: Default::default(),
            commands: Default::default(),
            incarnation: [0; MAX_SMALL_SCENES],
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

    /// The planner's statuses as an operator would see them now: the library's, or with the
    /// engine, those its factors carry (as [`Self::written`] reads them).
    fn snapshot(&self, step: &NetStep) -> Vec<Seen> {
        match &step.planner {
            Some(planner) => self.written(step, &planner.publication()),
            None => {
                let mut statuses = Vec::new();
                step.core.statuses_into(&mut statuses);
                let statuses = statuses
                    .into_iter()
                    .map(|s: CooperationStatus| (s.id, Some(s)));
                self.seen(step, statuses)
            }
        }
    }

    /// Statuses as a message tells of them, with each identifier's incarnation.
    fn seen(
        &self,
        step: &NetStep,
        statuses: impl Iterator<Item = (SceneId, Option<CooperationStatus>)>,
    ) -> Vec<Seen> {
        statuses
            .map(|(id, status)| {
                let incarnation = index(id)
                    .and_then(|i| step.incarnation.get(i))
                    .copied()
                    .unwrap_or(0);
                Seen {
                    id,
                    incarnation,
                    status: status.filter(|_| self.views == Views::Statuses),
                }
            })
            .collect()
    }

    /// The views of the operators that act (the model's first [`Self::operators`]).
    fn views_of<'a>(&self, step: &'a NetStep) -> impl Iterator<Item = &'a Vec<Seen>> {
        step.views.iter().take(self.operators)
    }

    /// The commands operator `k` can send from its view: with identifier views, operator 1
    /// approves and operator 2 holds back (two operators acting at once disagree); with status
    /// views, an operator acts on each scene it sees cancellable, deciding the opposite of the
    /// operator decision it sees.
    fn commands_from(&self, k: usize, view: &[Seen], actions: &mut Vec<NetAction>) {
        for seen in view {
            let decision = match (self.views, seen.status) {
                (Views::Identifiers, _) if k == 0 => OperatorDecision::Activate,
                (Views::Identifiers, _) => OperatorDecision::Deactivate,
                (Views::Statuses, Some(status)) if status.cancellable => {
                    match status.operator_decision {
                        OperatorDecision::Activate => OperatorDecision::Deactivate,
                        _ => OperatorDecision::Activate,
                    }
                }
                (Views::Statuses, _) => continue,
            };
            actions.push(NetAction::Send(k, seen.id, decision));
        }
    }

    /// Applies a planner input and records what changed.
    fn apply_core(
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
        self.settle(from, next, core.into_owned(), result.is_err());
        result
    }

    /// Records the planner's core after a call, `refused` or not: a refusal that changed it,
    /// and the identifiers that became live.
    fn settle(&self, from: &NetStep, next: &mut NetStep, core: State, refused: bool) {
        if refused && core != from.core {
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
        }
        next.core = core;
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
        if step.planner.as_ref().is_some_and(Planner::due) {
            actions.push(NetAction::PublishAll);
        }
        let room = step.commands.iter().map(Vec::len).sum::<usize>() < COMMANDS_IN_FLIGHT;
        for k in 0..self.operators {
            let statuses = step.statuses.get(k).map_or(0, Vec::len);
            let commands = step.commands.get(k).map_or(0, Vec::len);
            if statuses < STATUSES_IN_FLIGHT && step.planner.is_none() {
                actions.push(NetAction::Publish(k));
            }
            for m in 0..statuses {
                actions.push(NetAction::Receive(k, m));
                actions.push(NetAction::ReceiveDuplicate(k, m));
                actions.push(NetAction::LoseStatus(k, m));
            }
            if let (true, Some(view)) = (room, step.views.get(k)) {
                self.commands_from(k, view, actions);
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
                if from.planner.is_some() {
                    self.report_through(from, &mut next, input)?;
                } else {
                    let _ = self.apply_core(from, &mut next, input);
                }
                observe_owner(from, &mut next);
            }
            NetAction::PublishAll => {
                let publication = next.planner.as_mut()?.poll()?;
                let message = StatusMessage {
                    seen: self.written(from, &publication),
                };
                observe_publish(self, from, &mut next, &message);
                for channel in next.statuses.iter_mut().take(self.operators) {
                    channel.clear();
                    channel.push(message.clone());
                }
            }
            NetAction::Publish(k) => {
                let message = StatusMessage {
                    seen: self.snapshot(from),
                };
                observe_publish(self, from, &mut next, &message);
                let channel = next.statuses.get_mut(k)?;
                channel.push(message);
                channel.sort();
            }
            NetAction::Receive(k, m) => {
                let channel = next.statuses.get_mut(k)?;
                (m < channel.len()).then_some(())?;
                let message = channel.remove(m);
                *next.views.get_mut(k)? = message.seen;
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
                let (applied, second) = if from.planner.is_some() {
                    self.command_through(from, &mut next, message.command)?
                } else {
                    let input = Input::SetCommands {
                        commands: vec![message.command],
                    };
                    let applied = self.apply_core(from, &mut next, &input).is_ok();
                    (
                        applied,
                        applied && *self.transition(&next.core, &input).0 != next.core,
                    )
                };
                observe_delivery(from, &mut next, &message, applied, second);
            }
            NetAction::ReceiveDuplicate(k, m) => {
                let message = from.statuses.get(k)?.get(m)?.clone();
                *next.views.get_mut(k)? = message.seen;
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
        all.retain(|p| properties::applies(self, p.name));
        if let Some(focus) = self.focus {
            all.retain(|p| p.name == focus);
        }
        all
    }
}
