//! The engine model: the service engine (`cooperation_adapters::engine`) as a host drives it, with
//! the host's clock running between calls.
//!
//! `next_state` makes one call of the engine the way a host does ([`EngineAction`]): a module's
//! sync (a status or a removal), an operator's `set_commands` or `set_policies`, the host's
//! timeout ([`Engine::handle_timeout`]) and its publication poll
//! ([`Engine::poll_publication`]), each at the clock's reading; or the clock moves on by one
//! millisecond with nothing told; or the host, having told the time, waits as long as the engine
//! asks ([`Engine::until_timeout_ms`]) and tells it again. Requests are the doors' own types,
//! answered by the engine; unless an [`EngineFault`] is planted for a sensitivity test, nothing
//! here decides an answer.
//!
//! The properties ([`properties`]) are stated from the specification's time rules and the
//! streams' promise, with an oracle of their own: the time each scene was last reported (a
//! history annotation), what the last publication carried, and the core's own transition
//! ([`State::apply`]) for what an operator's call should have answered at its time.

mod answers;
mod config;
mod in_process;
mod properties;
mod step;
mod wake;
mod written;

pub use config::{EngineBounds, EngineFault, JUMP_STEP_MS};
pub use properties::{
    properties, ANSWER, HINTED, LIFETIME, MESSAGES, PERIODIC, POLICIES, PUBLISH, SCENES, STEP,
    TIME, WAKE,
};
pub use step::{content, now_at, EngineStep};
pub use written::written;

use std::hash::Hash;

use cooperation::{
    Behavior, Command, Config, Input, Limits, Module, OperatorDecision, Policy, PolicySetting,
    SceneId, State,
};
use cooperation_adapters::engine::{self, Engine, Now, Reply, Request};
use cooperation_adapters::rtc::{self, CooperateStatus};
use cooperation_adapters::sync::{SyncRequest, SyncStatus};
use cooperation_adapters::wire;

use crate::model::spec;
use serde::{Deserialize, Serialize};
use stateright::{Model, Property};

/// The steering module: a lane change, reported through `lane_change_left`.
const STEERING: (Module, &str) = (Module::new(Behavior::LaneChange), "lane_change_left");
/// The velocity module: an intersection, reported through `intersection`.
const VELOCITY: (Module, &str) = (Module::new(Behavior::Intersection), "intersection");
/// A module configured beside the two above, that no scene is reported for: `get_policies`
/// lists three modules, one policy of each kind whichever the operator sets.
const BYSTANDER: Module = Module::new(Behavior::Crosswalk);
/// The distances a report's start takes with [`EngineBounds::geometry`]: those the order rule
/// treats specially (`[COOP-OUT-ORDER.1]`: NaN of either sign, ±0, both infinities).
pub const DISTANCES: [f32; 6] = [
    f32::NAN,
    -f32::NAN,
    -0.0,
    0.0,
    f32::INFINITY,
    f32::NEG_INFINITY,
];
/// A report's start distance without [`EngineBounds::geometry`].
const START: f32 = 10.0;
/// Every report's finish distance: never a start distance, so that the two are told apart.
const FINISH: f32 = 50.0;
/// Each scene's time to live, in milliseconds.
pub const TTL_MS: u64 = 1;
/// The interval of periodic publications, in milliseconds.
pub const PUBLISH_EVERY_MS: u64 = 2;

/// An action of the engine model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EngineAction {
    /// The clock moves on one millisecond, nothing told.
    Wait,
    /// The clock goes back one millisecond, nothing told (with [`EngineBounds::rewinds`], once).
    Back,
    /// The host's timeout: the engine is told the time.
    Tick,
    /// The host polls for a publication and sends what it gets.
    Publish,
    /// The host, having told the time, waits as long as the engine asks
    /// ([`Engine::until_timeout_ms`]) and tells it the time again (its timeout).
    Sleep,
    /// A module's sync reports the scene (waiting), safe or not, starting at the distance of
    /// this position of [`DISTANCES`] (with [`EngineBounds::geometry`]).
    Report(SceneId, bool, usize),
    /// A module's sync removes the scene.
    Remove(SceneId),
    /// An operator's `set_commands` for the scene.
    Command(SceneId, OperatorDecision),
    /// An operator's `set_policies` for the module.
    Policy(Policy),
}

/// Sticky flags of broken step properties.
pub mod broken {
    /// A command applied to a scene whose time to live had passed at the request's time.
    pub const STALE_COMMAND: u8 = 1;
    /// An operator's call was answered otherwise than the core's transition at its time.
    pub const ANSWER: u8 = 2;
    /// A call changed what the streams show without asking for a publication.
    pub const UNHINTED: u8 = 4;
    /// A host that waited as long as the engine asked told the time at another reading than
    /// the earliest expiry, periodic publication or step limit.
    pub const WAKE: u8 = 8;
}

/// The engine model.
#[derive(Clone, Debug)]
pub struct EngineModel {
    bounds: EngineBounds,
    fault: Option<EngineFault>,
    focus: Option<&'static str>,
    config: Config,
    ids: Vec<SceneId>,
    /// The module and the interface its scenes are reported through.
    reporter: (Module, &'static str),
    /// The spec's merged-decision table, read from its text.
    merge: spec::MergeTable,
}

impl EngineModel {
    /// The model at these bounds.
    ///
    /// # Errors
    /// If `scenes` is not 1 to 4, or the spec's merge table does not read.
    pub fn new(bounds: EngineBounds) -> Result<Self, String> {
        if !(1..=4).contains(&bounds.scenes) {
            return Err("scenes must be 1 to 4".to_owned());
        }
        let merge = spec::MergeTable::from_spec(spec::SPEC).map_err(|e| e.to_string())?;
        let (reporter, other) = if bounds.velocity {
            (VELOCITY, STEERING)
        } else {
            (STEERING, VELOCITY)
        };
        let config = Config {
            policies: [
                (reporter.0, Policy::Required),
                (other.0, Policy::Optional),
                (BYSTANDER, Policy::Required),
            ]
            .into(),
            limits: Limits {
                ttl_ms: TTL_MS,
                max_scenes: bounds.scenes,
                retired_capacity: bounds.scenes,
                max_batch: 2,
            },
        };
        let ids = (1..=bounds.scenes as u128)
            .map(SceneId::from_u128)
            .collect();
        Ok(Self {
            bounds,
            fault: None,
            focus: None,
            config,
            ids,
            reporter,
            merge,
        })
    }

    /// The same model with `fault` planted.
    #[must_use]
    pub const fn with_fault(mut self, fault: EngineFault) -> Self {
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

    /// The factors the engine's streams write for `state`'s core (through a planted message
    /// fault, if there is one), as the spec's oracle reads them.
    #[must_use]
    pub fn messages(&self, state: &EngineStep) -> Vec<spec::messages::Factor> {
        let steering = !self.bounds.velocity;
        let mut factors = written(&state.engine.publication(state.now().stamp), steering);
        match self.fault {
            Some(EngineFault::UndecidedAsUnknown) => {
                for factor in &mut factors {
                    if factor.cooperator == spec::messages::decision::UNDECIDED {
                        factor.cooperator = 0;
                    }
                }
            }
            Some(EngineFault::FactorsByIdentifier) => {
                factors.sort_by(|a, b| a.uuid.cmp(&b.uuid));
            }
            Some(EngineFault::StartFinishSwapped) => {
                for factor in &mut factors {
                    factor.distances.reverse();
                }
            }
            _ => {}
        }
        factors
    }

    /// Whether the model's scenes are steering scenes (else velocity).
    #[must_use]
    pub const fn steering(&self) -> bool {
        !self.bounds.velocity
    }

    /// The model's bounds.
    #[must_use]
    pub const fn bounds(&self) -> EngineBounds {
        self.bounds
    }

    /// The planted fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<EngineFault> {
        self.fault
    }

    /// The configuration the engine's core is built with.
    #[must_use]
    pub const fn config(&self) -> &Config {
        &self.config
    }

    /// The spec's merged-decision table.
    #[must_use]
    pub const fn merge(&self) -> &spec::MergeTable {
        &self.merge
    }

    /// The step limit the engine is built with (unless a fault says otherwise).
    const fn max_step_ms(&self) -> u64 {
        if self.bounds.jumps {
            JUMP_STEP_MS
        } else {
            engine::MAX_STEP_MS
        }
    }

    /// Counts the step to the clock's reading in `next`'s core time, as `[COOP-ENGINE-STEP.1]`
    /// says the core is told it: at most the step limit; a reading not after the latest told
    /// is no time, and the next step counts from it.
    fn tell(&self, next: &mut EngineStep) {
        if next.clock_ms > next.read_ms {
            let step_ms = next.clock_ms - next.read_ms;
            next.core_ms = next.core_ms.saturating_add(step_ms.min(self.max_step_ms()));
        }
        next.read_ms = next.clock_ms;
    }

    /// The reading the host polls for a publication at in `state`: the clock's, unless
    /// [`EngineFault::BackHoldsPublications`] has it the last publication's while the clock
    /// reads earlier.
    fn polled_at(&self, state: &EngineStep) -> Now {
        let now = state.now();
        match (self.fault, state.engine.last_publication_ms()) {
            (Some(EngineFault::BackHoldsPublications), Some(published_ms))
                if now.reading_ns < published_ms.saturating_mul(1_000_000) =>
            {
                now_at(u64::try_from(published_ms).unwrap_or(0))
            }
            _ => now,
        }
    }

    /// Whether the host finds a publication due in `state`: asked at the clock's reading, or
    /// through a planted fault.
    #[must_use]
    pub fn due(&self, state: &EngineStep) -> bool {
        state.engine.publication_due(self.polled_at(state))
    }

    /// The reading a call at `now` tells `engine`: `now`, unless [`EngineFault::BackStalls`]
    /// has it ignore a reading earlier than the last it was told.
    fn reading(&self, engine: &Engine, now: Now) -> Now {
        let told = engine.told(now.stamp);
        if self.fault == Some(EngineFault::BackStalls) && now.reading_ns < told.reading_ns {
            told
        } else {
            now
        }
    }

    fn position(&self, id: SceneId) -> Option<usize> {
        self.ids.iter().position(|&known| known == id)
    }

    /// A request at `now`, through the planted fault if there is one; what the engine answered,
    /// flagged in `next` if it changed what the streams show without saying so.
    fn handle(&self, next: &mut EngineStep, request: Request, now: Now) -> Reply {
        let before = next.engine.state().clone();
        let engine = &mut next.engine;
        let late = match self.fault {
            Some(EngineFault::CallWithoutCatchUp) => matches!(request, Request::Ad(_)),
            Some(EngineFault::ReportWithoutCatchUp) => matches!(request, Request::Sync(_)),
            _ => false,
        };
        let at = if late {
            engine.told(now.stamp)
        } else {
            self.reading(engine, now)
        };
        let mut handled = engine.handle(request, at);
        if self.fault == Some(EngineFault::ChangeUnpublished) && handled.change.publish {
            drop(engine.poll_publication(now));
        }
        if self.fault == Some(EngineFault::ChangeUnhinted) {
            handled.change.publish = false;
        }
        unhinted(next, &before, handled.change);
        handled.reply
    }
}

/// A sync through `interface` of one status of `id`, waiting, `safe` or not, from `start` to
/// [`FINISH`].
fn report(interface: &str, id: SceneId, safe: bool, start: f32) -> SyncRequest {
    let status = CooperateStatus {
        uuid: id.into(),
        safe,
        state: rtc::Lifecycle::new(rtc::Lifecycle::WAITING_FOR_EXECUTION),
        start_distance: start,
        finish_distance: FINISH,
        ..CooperateStatus::default()
    };
    SyncRequest {
        interface: interface.to_owned(),
        statuses: vec![SyncStatus::from(&status)],
        sequences: Vec::new(),
        removed: Vec::new(),
    }
}

impl Model for EngineModel {
    type State = EngineStep;
    type Action = EngineAction;

    fn init_states(&self) -> Vec<Self::State> {
        let mut engine = Engine::new(
            self.config.clone(),
            engine::Options {
                scene_quota: 0,
                publish_every_ms: PUBLISH_EVERY_MS,
                max_step_ms: if self.fault == Some(EngineFault::StepUncapped) {
                    u64::MAX
                } else {
                    self.max_step_ms()
                },
            },
        )
        .unwrap_or_else(|_| unreachable_engine());
        // The host's first reading: the engine's time 0.
        engine.handle_timeout(now_at(0));
        vec![EngineStep {
            engine,
            clock_ms: 0,
            reported_ms: vec![None; self.ids.len()],
            read_ms: 0,
            core_ms: 0,
            reported_core_ms: vec![None; self.ids.len()],
            published: None,
            published_at_ms: None,
            went_back: false,
            rewinds: self.bounds.rewinds,
            broken: 0,
        }]
    }

    fn actions(&self, state: &Self::State, actions: &mut Vec<Self::Action>) {
        if state.clock_ms < self.bounds.horizon_ms {
            actions.push(EngineAction::Wait);
        }
        if self.bounds.rewinds && !state.went_back && state.clock_ms > 0 {
            actions.push(EngineAction::Back);
        }
        actions.push(EngineAction::Tick);
        if state.clock_ms == state.read_ms
            && state.clock_ms.saturating_add(self.asked_wait(state)) <= self.bounds.horizon_ms
        {
            actions.push(EngineAction::Sleep);
        }
        if !self.bounds.geometry && self.due(state) {
            actions.push(EngineAction::Publish);
        }
        let starts = if self.bounds.geometry {
            DISTANCES.len()
        } else {
            1
        };
        for &id in &self.ids {
            for start in 0..starts {
                actions.push(EngineAction::Report(id, false, start));
                actions.push(EngineAction::Report(id, true, start));
            }
            actions.push(EngineAction::Remove(id));
            actions.push(EngineAction::Command(id, OperatorDecision::Activate));
            actions.push(EngineAction::Command(id, OperatorDecision::Deactivate));
        }
        actions.push(EngineAction::Policy(Policy::Optional));
        actions.push(EngineAction::Policy(Policy::Required));
    }

    fn next_state(&self, last: &Self::State, action: Self::Action) -> Option<Self::State> {
        let mut next = last.clone();
        let now = last.now();
        if action == EngineAction::Sleep {
            let wait = self.asked_wait(last);
            if wait != self.due_in(last) {
                next.broken |= broken::WAKE;
            }
            next.clock_ms = next.clock_ms.saturating_add(wait);
        }
        if !matches!(
            action,
            EngineAction::Wait | EngineAction::Back | EngineAction::Publish
        ) {
            self.tell(&mut next);
        }
        match action {
            EngineAction::Wait => next.clock_ms += 1,
            EngineAction::Back => {
                next.clock_ms = next.clock_ms.checked_sub(1)?;
                next.went_back = true;
            }
            EngineAction::Tick | EngineAction::Sleep => {
                let before = next.engine.state().clone();
                let at = self.reading(&next.engine, next.now());
                let mut change = next.engine.handle_timeout(at);
                if self.fault == Some(EngineFault::ChangeUnhinted) {
                    change.publish = false;
                }
                unhinted(&mut next, &before, change);
            }
            EngineAction::Publish => {
                next.engine.poll_publication(self.polled_at(last))?;
                next.published = Some(content(next.engine.state()));
                next.published_at_ms = Some(last.clock_ms);
            }
            EngineAction::Report(id, safe, start) => {
                let start = if self.bounds.geometry {
                    DISTANCES.get(start).copied()?
                } else {
                    START
                };
                let accepted = if self.bounds.in_process {
                    self.in_process_report(&mut next, now, id, safe, start)
                } else {
                    let request = report(self.reporter.1, id, safe, start);
                    let reply = self.handle(&mut next, Request::Sync(request), now);
                    let Reply::Sync(response) = reply else {
                        return None;
                    };
                    response.results.first().is_some_and(|r| r.success)
                };
                if let (true, Some(at)) = (accepted, self.position(id)) {
                    if let Some(slot) = next.reported_ms.get_mut(at) {
                        *slot = Some(last.clock_ms);
                    }
                    if let Some(slot) = next.reported_core_ms.get_mut(at) {
                        *slot = Some(next.core_ms);
                    }
                }
            }
            EngineAction::Remove(id) => {
                let request = SyncRequest {
                    removed: vec![id.into()],
                    statuses: Vec::new(),
                    ..report(self.reporter.1, id, false, START)
                };
                let reply = self.handle(&mut next, Request::Sync(request), now);
                let Reply::Sync(response) = reply else {
                    return None;
                };
                if let (true, Some(at)) = (response.success, self.position(id)) {
                    if let Some(slot) = next.reported_ms.get_mut(at) {
                        *slot = None;
                    }
                    if let Some(slot) = next.reported_core_ms.get_mut(at) {
                        *slot = None;
                    }
                }
            }
            EngineAction::Command(id, decision) => {
                let applied = if self.bounds.in_process {
                    self.in_process_command(last, &mut next, id, decision)?
                } else {
                    let commands = [Command { id, decision }];
                    let request = wire::Request::SetCommands(commands.iter().copied().collect());
                    let input = Input::SetCommands {
                        commands: commands.to_vec(),
                    };
                    self.operator_call(last, &mut next, request, &input)
                };
                if applied {
                    // The scene's age in the core's time at the request's.
                    let age = self
                        .position(id)
                        .and_then(|at| last.reported_core_ms.get(at).copied().flatten())
                        .map(|reported| next.core_ms.saturating_sub(reported));
                    if age.map_or(true, |age| age > self.config.limits.ttl_ms) {
                        next.broken |= broken::STALE_COMMAND;
                    }
                }
            }
            EngineAction::Policy(policy) if self.bounds.in_process => {
                self.in_process_policy(last, &mut next, policy);
            }
            EngineAction::Policy(policy) => {
                let settings = [PolicySetting {
                    module: self.reporter.0,
                    policy,
                }];
                let request = wire::Request::SetPolicies(settings.iter().copied().collect());
                let input = Input::SetPolicies {
                    policies: settings.to_vec(),
                };
                self.operator_call(last, &mut next, request, &input);
            }
        }
        Some(next)
    }

    fn properties(&self) -> Vec<Property<Self>> {
        let mut all = properties();
        if self.bounds.horizon_ms <= self.config.limits.ttl_ms {
            all.retain(|property| property.name != properties::STALE_WITNESS);
        }
        if !self.bounds.jumps {
            all.retain(|property| property.name != properties::JUMP_WITNESS);
        }
        if self.bounds.rewinds {
            // On a clock that went back, a scene's time to live is counted in the core's time
            // only (`[COOP-ENGINE-STEP.1]`: the replayed stretch counts again), which the step
            // property checks; on the clock it would have been shorter.
            all.retain(|property| property.name != properties::LIFETIME);
        } else {
            all.retain(|property| property.name != properties::REWIND_WITNESS);
        }
        if let Some(focus) = self.focus {
            all.retain(|property| property.name == focus);
        }
        all
    }
}

/// Flags a call that changed what the streams carry ([`content`]) from what they carried of
/// the core `before` without saying so in its `change`.
fn unhinted(next: &mut EngineStep, before: &State, change: engine::Change) {
    if change.revision.is_some()
        && !change.publish
        && content(next.engine.state()) != content(before)
    {
        next.broken |= broken::UNHINTED;
    }
}

/// The model's configuration is one the core accepts; were it not, no state could be built.
#[allow(clippy::panic)]
fn unreachable_engine() -> Engine {
    panic!("the engine model's configuration is refused by the core")
}
