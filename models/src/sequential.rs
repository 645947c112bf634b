//! The sequential model: one state, inputs one at a time, every interleaving of owner inputs,
//! commands, policy changes and time over a bounded set of identifiers and modules.
//!
//! `next_state` calls the library's transition, [`State::after`] (the by-value form of
//! `State::apply`), through [`SequentialModel::transition`], which is exactly that unless a
//! [`Fault`] is injected for a sensitivity test; then it records what it observed in history variables ([`Ghost`]): the rule that fired, and sticky flags for
//! transition properties (a property of a step, not of a state). A flag is only ever set when a
//! property is violated, so in a correct run the flags add no states.

use std::hash::{Hash, Hasher};
use std::sync::{Arc, OnceLock};

use cooperation::{
    Behavior, Command, Config, Decision, Geometry, Input, Limits, Module, OperatorDecision, Phase,
    Policy, PolicySetting, Rejection, Rule, SceneId, Sequence, State, Transition,
};
use stateright::{Model, Property, Representative};

use crate::fault::Fault;
use crate::spec::{MergeTable, TableError, SPEC};

/// The modules a model draws from, with their default policies: the first `modules` of these.
pub const MODULES: [(Module, Policy); 4] = [
    (Module::new(Behavior::LaneChange), Policy::Optional),
    (
        Module::with_sequence(Behavior::Avoidance, Sequence::Change),
        Policy::Required,
    ),
    (Module::new(Behavior::Intersection), Policy::Optional),
    (Module::new(Behavior::Crosswalk), Policy::Required),
];

/// A module that is never configured: inputs naming it explore the "no policy" rejections.
pub const STRANGER: Module = Module::new(Behavior::RunOut);

/// The size of a model: how many modules and identifiers, and the core's limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Bounds {
    /// Configured modules (1 to 4), alternately optional and required by default.
    pub modules: usize,
    /// Scene identifiers, `1..=scenes`.
    pub scenes: usize,
    /// The live-scene limit (`max_scenes`).
    pub live: usize,
    /// The retired capacity.
    pub retired: usize,
}

impl Bounds {
    /// `modules` modules and `scenes` identifiers, at most `scenes - 1` live (so the scene limit
    /// is reachable), and room to remember every retired identifier.
    #[must_use]
    pub fn new(modules: usize, scenes: usize) -> Self {
        Self {
            modules,
            scenes,
            live: scenes.saturating_sub(1).max(1),
            retired: scenes,
        }
    }
}

/// Bounds the model cannot be built with.
#[derive(Debug)]
pub enum ModelError {
    /// A bound is out of range.
    Bounds(String),
    /// The spec's table could not be read.
    Table(TableError),
}

impl core::fmt::Display for ModelError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Bounds(why) => write!(f, "bad bounds: {why}"),
            Self::Table(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for ModelError {}

/// The sequential model of the cooperation core.
#[derive(Clone, Debug)]
pub struct SequentialModel {
    bounds: Bounds,
    fault: Option<Fault>,
    focus: Option<&'static str>,
    config: Config,
    alphabet: Vec<Input>,
    table: MergeTable,
}

/// Each model state: the core's state plus history variables.
///
/// Fingerprinted by the core's content, the rule, the history and `stalled`, except that when
/// the retired capacity covers every identifier (`order_matters` is false) the order in which
/// identifiers retired is left out: no identifier is ever forgotten then, so the order is
/// unobservable.
#[derive(Clone, serde::Serialize)]
pub struct Step {
    /// The library's state.
    pub core: Arc<State>,
    /// The rule the last input fired or was rejected by; `None` initially.
    pub last: Option<Rule>,
    /// History the transition properties need.
    pub ghost: Ghost,
    /// The last input changed nothing (core and history are the predecessor's).
    pub stalled: bool,
    /// Whether the retirement order can matter (the retired set can fill up).
    pub order_matters: bool,
    /// Values derived from `core` and `ghost`, computed once and shared by every step with the
    /// same core and history (a stalled step shares its predecessor's).
    #[serde(skip)]
    derived: Arc<Derived>,
}

/// What is derived from a step's core and history: the core's fingerprint contribution, and
/// (when symmetry reduction asks for it) the canonical renaming.
struct Derived {
    core_hash: u64,
    /// The canonical form, or `None` when the step is canonical already (a `Some(self)` would
    /// be a reference cycle).
    canonical: OnceLock<Option<Step>>,
}

impl Step {
    fn new(
        core: Arc<State>,
        last: Option<Rule>,
        ghost: Ghost,
        stalled: bool,
        order_matters: bool,
    ) -> Self {
        let derived = Arc::new(Derived {
            core_hash: core_hash(&core, order_matters),
            canonical: OnceLock::new(),
        });
        Self {
            core,
            last,
            ghost,
            stalled,
            order_matters,
            derived,
        }
    }

    /// The step for an input that changed nothing: same core and history, shared derivations.
    fn stalled_after(from: &Self, rule: Rule) -> Self {
        Self {
            last: Some(rule),
            stalled: true,
            ..from.clone()
        }
    }
}

/// The core's content as the fingerprint sees it (see [`Step`]). A fixed-seed foldhash: about
/// five times cheaper per byte than the SipHash the checker fingerprints with, and as
/// deterministic, so a run's counts never depend on the process.
fn core_hash(core: &State, order_matters: bool) -> u64 {
    use std::hash::BuildHasher;
    let mut state = foldhash::quality::FixedState::with_seed(0x636f_6f70).build_hasher();
    core.limits().hash(&mut state);
    core.policies().for_each(|setting| setting.hash(&mut state));
    core.scene_count().hash(&mut state);
    core.scenes().for_each(|scene| scene.hash(&mut state));
    if order_matters {
        core.retired().for_each(|retired| retired.hash(&mut state));
    } else {
        core.retirements()
            .for_each(|retired| retired.hash(&mut state));
    }
    state.finish()
}

impl PartialEq for Step {
    fn eq(&self, other: &Self) -> bool {
        self.core == other.core
            && self.last == other.last
            && self.ghost == other.ghost
            && self.stalled == other.stalled
            && self.order_matters == other.order_matters
    }
}

impl Eq for Step {}

impl Hash for Step {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.derived.core_hash.hash(state);
        self.last.hash(state);
        self.ghost.hash(state);
        self.stalled.hash(state);
    }
}

impl core::fmt::Debug for Step {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Step")
            .field("core", &self.core)
            .field("last", &self.last)
            .field("ghost", &self.ghost)
            .field("stalled", &self.stalled)
            .finish_non_exhaustive()
    }
}

impl Representative for Step {
    /// Identifiers renamed `1, 2, …` in the order of everything known about them, so that all
    /// states equal up to renaming share one representative. The sort key is each identifier's
    /// whole signature, so the representative is canonical.
    fn representative(&self) -> Self {
        match self.derived.canonical.get_or_init(|| self.canonical()) {
            Some(canonical) => Self {
                last: self.last,
                stalled: self.stalled,
                ..canonical.clone()
            },
            None => self.clone(),
        }
    }
}

impl Step {
    fn canonical(&self) -> Option<Self> {
        let core = &self.core;
        let position = |id: SceneId| {
            if self.order_matters {
                core.retired().position(|(o, _)| o == id)
            } else {
                None
            }
        };
        // Every identifier's signature; identifiers nothing is known of sort last.
        let mut signed: [_; MAX_SCENES] = core::array::from_fn(|i| {
            let id = SceneId::from_u128(i as u128 + 1);
            let signature = (
                core.scene(id),
                core.retirement(id),
                self.ghost.owner(id),
                self.ghost.was_retired(id),
                position(id),
            );
            let unknown = signature == (None, None, None, false, None);
            ((unknown, signature), i)
        });
        signed.sort_unstable();
        let mut names = [0; MAX_SCENES];
        for (new, (_, old)) in signed.iter().enumerate() {
            if let Some(name) = names.get_mut(*old) {
                *name = new;
            }
        }
        if names.iter().enumerate().all(|(old, new)| old == *new) {
            return None;
        }
        let rename = |id: SceneId| {
            index(id)
                .and_then(|i| names.get(i))
                .map_or(id, |n| SceneId::from_u128(*n as u128 + 1))
        };
        let core = self.core.relabel(rename)?;
        let mut ghost = Ghost {
            broken: self.ghost.broken,
            ..Ghost::default()
        };
        for (old, new) in names.iter().enumerate() {
            if let (Some(slot), Some(owner)) =
                (ghost.owners.get_mut(*new), self.ghost.owners.get(old))
            {
                *slot = *owner;
            }
            if self.ghost.retired_ever & (1 << old) != 0 {
                ghost.retired_ever |= 1 << new;
            }
        }
        Some(Self::new(
            Arc::new(core),
            self.last,
            ghost,
            self.stalled,
            self.order_matters,
        ))
    }
}

/// The most identifiers a model can have.
pub const MAX_SCENES: usize = 8;

/// History variables: what the properties about steps need to remember. Indexed by identifier
/// number minus one (the model's identifiers are `1..=scenes`), so they never allocate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize)]
pub struct Ghost {
    /// The module each identifier was first live under.
    pub owners: [Option<Module>; MAX_SCENES],
    /// Every identifier ever retired, as a bit set.
    pub retired_ever: u8,
    /// Sticky flags: which step properties some step so far has broken.
    pub broken: Broken,
}

/// The model's index of an identifier: its number minus one.
#[must_use]
pub fn index(id: SceneId) -> Option<usize> {
    let number = id.to_u128();
    usize::try_from(number)
        .ok()
        .and_then(|n| n.checked_sub(1))
        .filter(|n| *n < MAX_SCENES)
}

impl Ghost {
    fn was_retired(&self, id: SceneId) -> bool {
        index(id).is_some_and(|i| self.retired_ever & (1 << i) != 0)
    }

    fn owner(&self, id: SceneId) -> Option<Module> {
        index(id).and_then(|i| self.owners.get(i).copied().flatten())
    }
}

/// A set of broken step properties (see the `BROKEN_*` constants' docs in the source).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
pub struct Broken(u16);

impl Broken {
    /// A rejected input changed the state.
    pub const REJECTION_CHANGED: Self = Self(1);
    /// An input other than an applied command batch changed an operator decision.
    pub const OPERATOR_BY_OTHER: Self = Self(1 << 1);
    /// An applied command batch changed something besides the operator decisions it names.
    pub const COMMAND_SPILLED: Self = Self(1 << 2);
    /// An applied command batch left a named scene without the command's decision.
    pub const COMMAND_MISSED: Self = Self(1 << 3);
    /// An applied policy batch changed a scene or a module it does not name.
    pub const POLICY_SPILLED: Self = Self(1 << 4);
    /// An applied policy batch left a named module without the setting's policy.
    pub const POLICY_MISSED: Self = Self(1 << 5);
    /// An input other than an applied policy batch changed a policy.
    pub const POLICY_BY_OTHER: Self = Self(1 << 6);
    /// A batch naming a retired identifier changed the state.
    pub const RETIRED_COMMAND: Self = Self(1 << 7);
    /// A live identifier's module differs from the one it was first live under.
    pub const ID_MOVED: Self = Self(1 << 8);
    /// An identifier that had retired is live again.
    pub const REVIVED: Self = Self(1 << 9);
    /// A retirement record changed.
    pub const TERMINAL_LEFT: Self = Self(1 << 10);
    /// A retired identifier was forgotten while the retired set had room, or before an older one.
    pub const FORGOT_EARLY: Self = Self(1 << 11);

    /// Whether `flag` is among these.
    #[must_use]
    pub const fn contains(self, flag: Self) -> bool {
        self.0 & flag.0 != 0
    }

    fn set(&mut self, flag: Self, when: bool) {
        if when {
            self.0 |= flag.0;
        }
    }
}

impl SequentialModel {
    /// The model at these bounds.
    ///
    /// # Errors
    /// If a bound is out of range or the spec's table cannot be read.
    pub fn new(bounds: Bounds) -> Result<Self, ModelError> {
        let Bounds {
            modules,
            scenes,
            live,
            retired,
        } = bounds;
        if !(1..=MODULES.len()).contains(&modules) {
            return Err(ModelError::Bounds(format!(
                "modules must be 1 to {}",
                MODULES.len()
            )));
        }
        if !(1..=MAX_SCENES).contains(&scenes) {
            return Err(ModelError::Bounds(format!(
                "scenes must be 1 to {MAX_SCENES}"
            )));
        }
        if live == 0 || retired == 0 {
            return Err(ModelError::Bounds(
                "the live and retired limits must be at least 1".into(),
            ));
        }
        let config = Config {
            policies: MODULES.iter().take(modules).copied().collect(),
            limits: Limits {
                ttl_ms: 1,
                max_scenes: live,
                retired_capacity: retired,
                max_batch: 2,
            },
        };
        let ids: Vec<SceneId> = (1..=scenes as u128).map(SceneId::from_u128).collect();
        let table = MergeTable::from_spec(SPEC).map_err(ModelError::Table)?;
        let alphabet = alphabet(&config, &ids);
        Ok(Self {
            bounds,
            fault: None,
            focus: None,
            config,
            alphabet,
            table,
        })
    }

    /// The same model with a deliberately wrong behaviour injected (sensitivity tests only).
    #[must_use]
    pub fn with_fault(mut self, fault: Fault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The same model checking only the named property (for the shortest counterexample).
    #[must_use]
    pub fn focus(mut self, property: &'static str) -> Self {
        self.focus = Some(property);
        self
    }

    /// The bounds.
    #[must_use]
    pub const fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// The injected fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// The core's configuration in this model.
    #[must_use]
    pub const fn config(&self) -> &Config {
        &self.config
    }

    /// Every input the model tries in every state.
    #[must_use]
    pub fn alphabet(&self) -> &[Input] {
        &self.alphabet
    }

    /// The transition under check: the library's `State::after` (the by-value form of
    /// `State::apply`), or the faulty wrapper around `apply`. Gives the next state (the very
    /// same allocation when the library rejects the input) and the result.
    pub fn transition(
        &self,
        core: &Arc<State>,
        input: &Input,
    ) -> (Arc<State>, Result<Transition, Rejection>) {
        match self.fault {
            None => match core.after(input) {
                Ok((next, transition)) => (Arc::new(next), Ok(transition)),
                Err(rejection) => (Arc::clone(core), Err(rejection)),
            },
            Some(fault) => {
                let mut next = State::clone(core);
                let result = fault.apply(&mut next, input);
                (Arc::new(next), result)
            }
        }
    }

    /// The merged decision under check: `State::merged_decision`, or the faulty wrapper.
    #[must_use]
    pub fn merged_decision(&self, core: &State, id: SceneId) -> Option<Decision> {
        match self.fault {
            None => core.merged_decision(id),
            Some(fault) => fault.merged_decision(core, id),
        }
    }

    /// The state the model starts in.
    ///
    /// # Errors
    /// If the configuration is refused (never, for valid bounds).
    pub fn initial(&self) -> Result<Step, cooperation::ConfigError> {
        let core = Arc::new(State::new(self.config.clone())?);
        let order_matters = self.bounds.retired < self.bounds.scenes;
        Ok(Step::new(
            core,
            None,
            Ghost::default(),
            false,
            order_matters,
        ))
    }

    /// Every step of a path of inputs, the initial state first.
    ///
    /// # Errors
    /// If the configuration is refused (never, for valid bounds).
    pub fn replay(&self, inputs: &[Input]) -> Result<Vec<Step>, ModelError> {
        let first = self
            .initial()
            .map_err(|e| ModelError::Bounds(e.to_string()))?;
        let mut steps = vec![first];
        for input in inputs {
            let next = steps.last().map(|last| self.step(last, input));
            steps.extend(next);
        }
        Ok(steps)
    }

    /// The next step: apply `input`, then record what happened.
    #[must_use]
    pub fn step(&self, from: &Step, input: &Input) -> Step {
        let (core, result) = self.transition(&from.core, input);
        let rule = match &result {
            Ok(transition) => transition.rule,
            Err(rejection) => rejection.rule(),
        };
        // The very same state back means nothing can have changed, history included.
        if Arc::ptr_eq(&core, &from.core) {
            return Step::stalled_after(from, rule);
        }
        let ghost = observe(from, input, &result, &core);
        if *core == *from.core && ghost == from.ghost {
            return Step::stalled_after(from, rule);
        }
        Step::new(core, Some(rule), ghost, false, from.order_matters)
    }
}

/// Every input over the model's identifiers and modules: registrations, updates to every phase
/// with either decision (and one of the wrong kind), removals, commands (single, duplicate,
/// paired, empty, over the limit), policies (single, duplicate, empty, over the limit), time.
fn alphabet(config: &Config, ids: &[SceneId]) -> Vec<Input> {
    let modules: Vec<Module> = config.policies.keys().copied().collect();
    let first = modules.first().copied().unwrap_or(STRANGER);
    let velocity = Geometry::velocity(0.0);
    let over_limit = config.limits.max_batch + 1;
    let mut inputs = Vec::new();
    for &id in ids {
        for &module in modules.iter().chain([&STRANGER]) {
            for decision in Decision::ALL {
                inputs.push(Input::Register {
                    id,
                    module,
                    decision,
                    requested: false,
                    geometry: velocity,
                });
            }
        }
        // An owner asking for an operator decision (`[COOP-REQUESTED.1]`): registering so, and
        // updating so while waiting or running; every other update withdraws the request.
        for &module in &modules {
            inputs.push(Input::Register {
                id,
                module,
                decision: Decision::Activate,
                requested: true,
                geometry: velocity,
            });
            for phase in [Phase::WaitingForExecution, Phase::Running] {
                inputs.push(Input::Update {
                    id,
                    module,
                    phase,
                    decision: Decision::Activate,
                    requested: true,
                    geometry: velocity,
                });
            }
        }
        for &module in &modules {
            for phase in Phase::ALL {
                for decision in Decision::ALL {
                    inputs.push(Input::Update {
                        id,
                        module,
                        phase,
                        decision,
                        requested: false,
                        geometry: velocity,
                    });
                }
            }
            inputs.push(Input::Remove { id, module });
        }
        let steering = Geometry::steering(cooperation::Direction::Left, 0.0, 1.0);
        inputs.push(Input::Update {
            id,
            module: first,
            phase: Phase::Running,
            decision: Decision::Activate,
            requested: false,
            geometry: steering,
        });
        for decision in OperatorDecision::ALL {
            inputs.push(Input::SetCommands {
                commands: vec![Command { id, decision }],
            });
        }
        let twice = Command {
            id,
            decision: OperatorDecision::Activate,
        };
        inputs.push(Input::SetCommands {
            commands: vec![twice, twice],
        });
    }
    for (n, &a) in ids.iter().enumerate() {
        for &b in ids.iter().skip(n + 1) {
            inputs.push(Input::SetCommands {
                commands: vec![
                    Command {
                        id: a,
                        decision: OperatorDecision::Activate,
                    },
                    Command {
                        id: b,
                        decision: OperatorDecision::Deactivate,
                    },
                ],
            });
        }
    }
    inputs.push(Input::SetCommands {
        commands: Vec::new(),
    });
    if let Some(&id) = ids.first() {
        let command = Command {
            id,
            decision: OperatorDecision::Autonomous,
        };
        inputs.push(Input::SetCommands {
            commands: vec![command; over_limit],
        });
    }
    for &module in modules.iter().chain([&STRANGER]) {
        for policy in Policy::ALL {
            inputs.push(Input::SetPolicies {
                policies: vec![PolicySetting { module, policy }],
            });
        }
    }
    let setting = PolicySetting {
        module: first,
        policy: Policy::Required,
    };
    inputs.push(Input::SetPolicies {
        policies: vec![setting, setting],
    });
    inputs.push(Input::SetPolicies {
        policies: Vec::new(),
    });
    inputs.push(Input::SetPolicies {
        policies: vec![setting; over_limit],
    });
    inputs.push(Input::Tick { elapsed_ms: 1 });
    inputs
}

/// What the step from `from` by `input` to `core` did, as history for the step properties.
/// It compares states and reads the input; it decides nothing.
fn observe(
    from: &Step,
    input: &Input,
    result: &Result<Transition, Rejection>,
    core: &State,
) -> Ghost {
    let old: &State = &from.core;
    let mut ghost = from.ghost;
    let broken = &mut ghost.broken;
    let rule = result.as_ref().ok().map(|t| t.rule);
    broken.set(Broken::REJECTION_CHANGED, result.is_err() && core != old);

    let scenes_changed = old.scenes().ne(core.scenes());
    let policies_changed = old.policies().ne(core.policies());
    let kept: Vec<_> = core
        .scenes()
        .filter_map(|(id, new)| old.scene(id).map(|old| (id, old, new)))
        .collect();
    if rule != Some(Rule::CommandApply) {
        let changed = kept
            .iter()
            .any(|(_, o, n)| o.operator_decision() != n.operator_decision());
        broken.set(Broken::OPERATOR_BY_OTHER, changed);
    }
    if rule != Some(Rule::PolicySet) {
        broken.set(Broken::POLICY_BY_OTHER, policies_changed);
    }
    match (input, rule) {
        (Input::SetCommands { commands }, Some(Rule::CommandApply)) => {
            let decision_of = |id| commands.iter().find(|c| c.id == id).map(|c| c.decision);
            let same_ids = old
                .scenes()
                .map(|(id, _)| id)
                .eq(core.scenes().map(|(id, _)| id));
            let spilled = !same_ids
                || policies_changed
                || old.retired().ne(core.retired())
                || kept.iter().any(|(id, o, n)| {
                    let operator_moved = o.operator_decision() != n.operator_decision();
                    let rest_moved = o.phase() != n.phase()
                        || o.module_decision() != n.module_decision()
                        || o.is_requested() != n.is_requested()
                        || o.age_ms() != n.age_ms()
                        || o.geometry() != n.geometry()
                        || o.module() != n.module();
                    rest_moved || (operator_moved && decision_of(*id).is_none())
                });
            broken.set(Broken::COMMAND_SPILLED, spilled);
            let missed = commands.iter().any(|c| {
                core.scene(c.id).map(cooperation::Scene::operator_decision) != Some(c.decision)
            });
            broken.set(Broken::COMMAND_MISSED, missed);
        }
        (Input::SetPolicies { policies }, Some(Rule::PolicySet)) => {
            let named = |module| policies.iter().any(|p: &PolicySetting| p.module == module);
            let foreign = old
                .policies()
                .zip(core.policies())
                .any(|(o, n)| o != n && !named(o.module));
            broken.set(
                Broken::POLICY_SPILLED,
                scenes_changed || foreign || old.retired().ne(core.retired()),
            );
            let missed = policies
                .iter()
                .any(|p| core.policy(p.module) != Some(p.policy));
            broken.set(Broken::POLICY_MISSED, missed);
        }
        _ => {}
    }
    if let Input::SetCommands { commands } = input {
        let names_retired = commands.iter().any(|c| old.retirement(c.id).is_some());
        broken.set(Broken::RETIRED_COMMAND, names_retired && core != old);
    }
    for (id, scene) in core.scenes() {
        let slot = index(id).and_then(|i| ghost.owners.get_mut(i));
        let owner = slot.map(|slot| *slot.get_or_insert(scene.module()));
        ghost
            .broken
            .set(Broken::ID_MOVED, owner != Some(scene.module()));
        ghost.broken.set(Broken::REVIVED, ghost.was_retired(id));
    }
    for (id, retirement) in core.retirements() {
        if let Some(i) = index(id) {
            ghost.retired_ever |= 1 << i;
        }
        let changed = old
            .retirement(id)
            .is_some_and(|before| before != retirement);
        ghost.broken.set(Broken::TERMINAL_LEFT, changed);
    }
    // An identifier known before (live or retired) and unknown now has been forgotten: it is
    // unknown again, and the history forgets it too. Forgetting is allowed only to make room
    // (the retired set is full afterwards) and oldest first: of the earlier retirements only a
    // prefix of the retirement order, and one retired by this very step only after all of them.
    let vanished = |id: &SceneId| core.retirement(*id).is_none() && core.scene(*id).is_none();
    let old_order: Vec<SceneId> = old.retired().map(|(id, _)| id).collect();
    let forgotten_old = old_order.iter().take_while(|id| vanished(id)).count();
    let forgotten_new = old.scenes().filter(|(id, _)| vanished(id)).count();
    let any_forgotten = old_order.iter().any(vanished) || forgotten_new > 0;
    if any_forgotten {
        let prefix = old_order.iter().filter(|id| vanished(id)).count() == forgotten_old;
        let after_all_old = forgotten_new == 0 || forgotten_old == old_order.len();
        let full = core.retired().count() == core.limits().retired_capacity;
        ghost
            .broken
            .set(Broken::FORGOT_EARLY, !(prefix && after_all_old && full));
        let known = old_order
            .iter()
            .copied()
            .chain(old.scenes().map(|(id, _)| id));
        for id in known.filter(vanished) {
            if let Some(i) = index(id) {
                ghost.retired_ever &= !(1 << i);
                if let Some(slot) = ghost.owners.get_mut(i) {
                    *slot = None;
                }
            }
        }
    }
    ghost
}

/// An action of the model: the position of an input in [`SequentialModel::alphabet`].
pub type Action = usize;

impl Model for SequentialModel {
    type State = Step;
    type Action = Action;

    fn init_states(&self) -> Vec<Step> {
        self.initial().into_iter().collect()
    }

    fn actions(&self, step: &Step, actions: &mut Vec<Action>) {
        // A step that changed nothing is a dead end: its predecessor, equal to it but for the
        // rule just recorded, is expanded already.
        if !step.stalled {
            actions.extend(0..self.alphabet.len());
        }
    }

    fn next_state(&self, from: &Step, action: Action) -> Option<Step> {
        self.alphabet
            .get(action)
            .map(|input| self.step(from, input))
    }

    fn format_action(&self, action: &Action) -> String {
        self.alphabet
            .get(*action)
            .map_or_else(|| format!("input #{action}"), crate::trace::describe)
    }

    fn properties(&self) -> Vec<Property<Self>> {
        let mut all = properties();
        if let Some(focus) = self.focus {
            all.retain(|p| p.name == focus);
        }
        all
    }
}

// ---------------------------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------------------------

type Condition = fn(&SequentialModel, &Step) -> bool;

/// The policy `[COOP-MERGE.1]` applies to a scene: required if it is requested
/// (`[COOP-REQUESTED.1]`), else its module's.
fn policy_for(core: &State, scene: &cooperation::Scene) -> Option<Policy> {
    let module = core.policy(scene.module())?;
    Some(if scene.is_requested() {
        Policy::Required
    } else {
        module
    })
}

/// Every live scene's merged decision is the spec table's for its current values.
fn merge_is_the_table(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let policy = policy_for(&step.core, scene);
        let expected = policy.and_then(|policy| {
            model
                .table
                .merged(scene.operator_decision(), policy, scene.module_decision())
        });
        expected.is_some() && model.merged_decision(&step.core, id) == expected
    })
}

/// A required policy, or a request for the operator, with no operator decision never
/// activates.
fn required_none_never_activates(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let held = scene.operator_decision() == OperatorDecision::Undecided
            && (scene.is_requested() || step.core.policy(scene.module()) == Some(Policy::Required));
        !held || model.merged_decision(&step.core, id) == Some(Decision::Deactivate)
    })
}

/// An explicit operator decision (activate or deactivate) is the merged decision.
fn explicit_operator_wins(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let explicit = match scene.operator_decision() {
            OperatorDecision::Activate => Some(Decision::Activate),
            OperatorDecision::Deactivate => Some(Decision::Deactivate),
            OperatorDecision::Autonomous | OperatorDecision::Undecided => None,
        };
        explicit.is_none() || model.merged_decision(&step.core, id) == explicit
    })
}

fn unbroken<const FLAG: u16>(_: &SequentialModel, step: &Step) -> bool {
    !step.ghost.broken.contains(Broken(FLAG))
}

/// The library's own invariant check (every invariant of spec §8) passes.
fn invariants_hold(_: &SequentialModel, step: &Step) -> bool {
    step.core.check_invariants().is_ok()
}

fn rule_fired<const I: usize>(_: &SequentialModel, step: &Step) -> bool {
    step.last.is_some() && step.last == Rule::ALL.get(I).copied()
}

/// Witness: the operator made the planner go on with a scene its module holds back.
fn operator_overrides_module(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().any(|(id, scene)| {
        scene.module_decision() == Decision::Deactivate
            && model.merged_decision(&step.core, id) == Some(Decision::Activate)
    })
}

/// Witness: a required policy holds back a scene its module would go on with.
fn policy_holds_scene_back(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().any(|(id, scene)| {
        scene.module_decision() == Decision::Activate
            && scene.operator_decision() == OperatorDecision::Undecided
            && model.merged_decision(&step.core, id) == Some(Decision::Deactivate)
    })
}

/// Witness: an owner's request holds back a scene whose module's policy is optional.
fn request_holds_scene_back(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().any(|(id, scene)| {
        scene.is_requested()
            && step.core.policy(scene.module()) == Some(Policy::Optional)
            && scene.module_decision() == Decision::Activate
            && model.merged_decision(&step.core, id) == Some(Decision::Deactivate)
    })
}

macro_rules! per_index {
    ($f:ident: $($i:literal)*) => { [$($f::<$i> as Condition),*] };
}

/// The safety properties, by name.
fn always() -> Vec<(&'static str, Condition)> {
    vec![
        (
            "COOP-MERGE.1: the merged decision is the spec table's",
            merge_is_the_table,
        ),
        (
            "COOP-MERGE.1, COOP-REQUESTED.1: required or requested with no operator decision never activates",
            required_none_never_activates,
        ),
        (
            "COOP-MERGE.1: an explicit operator decision wins",
            explicit_operator_wins,
        ),
        (
            "spec §4: a rejected input changes nothing",
            unbroken::<{ Broken::REJECTION_CHANGED.0 }>,
        ),
        (
            "COOP-CMD-APPLY.1: only commands change operator decisions",
            unbroken::<{ Broken::OPERATOR_BY_OTHER.0 }>,
        ),
        (
            "COOP-CMD-APPLY.1: a command changes only the operator decision it names",
            unbroken::<{ Broken::COMMAND_SPILLED.0 }>,
        ),
        (
            "COOP-CMD-APPLY.1: an applied command takes effect",
            unbroken::<{ Broken::COMMAND_MISSED.0 }>,
        ),
        (
            "COOP-POL-SET.1: a policy change alters no scene and no other module",
            unbroken::<{ Broken::POLICY_SPILLED.0 }>,
        ),
        (
            "COOP-POL-SET.1: a policy change reaches its module",
            unbroken::<{ Broken::POLICY_MISSED.0 }>,
        ),
        (
            "COOP-POL-SET.1: only policy changes change policies",
            unbroken::<{ Broken::POLICY_BY_OTHER.0 }>,
        ),
        (
            "COOP-CMD-RETIRED.1: commands naming retired identifiers change nothing",
            unbroken::<{ Broken::RETIRED_COMMAND.0 }>,
        ),
        (
            "COOP-OWN-MODULE.1: an identifier keeps its module while remembered",
            unbroken::<{ Broken::ID_MOVED.0 }>,
        ),
        (
            "COOP-REG-RETIRED.1: a remembered retired identifier never becomes live again",
            unbroken::<{ Broken::REVIVED.0 }>,
        ),
        (
            "COOP-RETIRE.1: terminal states are sticky",
            unbroken::<{ Broken::TERMINAL_LEFT.0 }>,
        ),
        (
            "COOP-RETIRE.1: the retired set forgets only when full, oldest first",
            unbroken::<{ Broken::FORGOT_EARLY.0 }>,
        ),
    ]
}

/// The name of the property that runs the library's invariant check.
pub const INVARIANTS: &str = "COOP-INV-*: State::check_invariants holds (spec §8)";

/// Every property: the safety properties, the library's invariant check, one reachability
/// property per rule, and two scenario witnesses.
#[must_use]
pub fn properties() -> Vec<Property<SequentialModel>> {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    let rule_names = NAMES.get_or_init(|| {
        let leak = |text: String| -> &'static str { Box::leak(text.into_boxed_str()) };
        Rule::ALL
            .iter()
            .map(|r| leak(format!("{} is reachable", r.tag())))
            .collect()
    });
    let rules =
        per_index!(rule_fired: 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23);
    let mut properties: Vec<Property<SequentialModel>> = always()
        .into_iter()
        .map(|(name, condition)| Property::always(name, condition))
        .collect();
    properties.push(Property::always(INVARIANTS, invariants_hold));
    properties.extend(
        rule_names
            .iter()
            .zip(rules)
            .map(|(n, c)| Property::sometimes(n, c)),
    );
    properties.push(Property::sometimes(
        "witness: the operator overrides a deactivated scene",
        operator_overrides_module,
    ));
    properties.push(Property::sometimes(
        "witness: a required policy holds a scene back",
        policy_holds_scene_back,
    ));
    properties.push(Property::sometimes(
        "witness: an owner's request holds a scene back under an optional policy",
        request_holds_scene_back,
    ));
    properties
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn there_is_a_property_per_rule_and_per_invariant() {
        let names: Vec<&str> = properties().iter().map(|p| p.name).collect();
        for rule in Rule::ALL {
            assert!(
                names
                    .iter()
                    .any(|n| n.starts_with(rule.tag()) && n.ends_with("is reachable")),
                "{rule}"
            );
        }
        assert!(names.contains(&INVARIANTS));
        let unique: std::collections::BTreeSet<&str> = names.iter().copied().collect();
        assert_eq!(unique.len(), names.len(), "property names are unique");
    }

    #[test]
    fn the_alphabet_is_deterministic_and_covers_every_kind_of_input() {
        let model = SequentialModel::new(Bounds::new(2, 3)).expect("valid");
        let again = SequentialModel::new(Bounds::new(2, 3)).expect("valid");
        assert_eq!(model.alphabet(), again.alphabet());
        let has = |f: fn(&Input) -> bool| model.alphabet().iter().any(f);
        assert!(has(|i| matches!(i, Input::Register { .. })));
        assert!(has(|i| matches!(i, Input::Update { .. })));
        assert!(has(|i| matches!(i, Input::Remove { .. })));
        assert!(has(|i| matches!(i, Input::SetCommands { .. })));
        assert!(has(|i| matches!(i, Input::SetPolicies { .. })));
        assert!(has(|i| matches!(i, Input::Tick { .. })));
    }
}
