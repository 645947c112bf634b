//! The state and its one transition function, [`State::apply`].
//!
//! Every arm of `apply` begins with the tag of the spec rule it implements. All checks of an
//! arm come before its first write, so a rejected input returns before anything changed.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use crate::table::{IdTable, TableLayout};

use crate::{
    merge, Command, CommandFailure, CommandOutcome, Decision, Geometry, Input, Invariant, Module,
    OperatorDecision, Phase, Policy, PolicySetting, Rejection, RetireReason, Retirement, Rule,
    SceneId, Violation,
};

/// How to start: the modules that support cooperation, with their default policies, and the
/// limits.
#[derive(Clone, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Config {
    /// Every module that supports cooperation, with its default policy. Only these modules can
    /// have scenes (`[COOP-REG-MODULE.1]`) and policies (`[COOP-POL-UNKNOWN.1]`).
    pub policies: BTreeMap<Module, Policy>,
    /// The limits.
    pub limits: Limits,
}

impl Config {
    /// A configuration with these default policies and [`Limits::default`].
    pub fn new(policies: impl IntoIterator<Item = (Module, Policy)>) -> Self {
        Self {
            policies: policies.into_iter().collect(),
            limits: Limits::default(),
        }
    }
}

/// The bounds that keep memory and work finite.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Limits {
    /// A scene whose owner has not updated it for longer than this expires
    /// (`[COOP-TIME-EXPIRE.1]`). Default 10 000 ms.
    pub ttl_ms: u64,
    /// At most this many live scenes (`[COOP-REG-FULL.1]`). Default 4 096.
    pub max_scenes: usize,
    /// At most this many retired identifiers are remembered; beyond it the oldest is forgotten
    /// (`[COOP-RETIRE.1]`). Default 65 536.
    pub retired_capacity: usize,
    /// At most this many entries in one batch (`[COOP-BATCH-LIMIT.1]`). Default 1 024.
    pub max_batch: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            ttl_ms: 10_000,
            max_scenes: 4_096,
            retired_capacity: 65_536,
            max_batch: 1_024,
        }
    }
}

impl Limits {
    /// Whether these limits can work: every one that bounds a count is at least 1.
    fn check(&self) -> Result<(), ConfigError> {
        if self.max_scenes == 0 {
            return Err(ConfigError::NoScenes);
        }
        if self.retired_capacity == 0 {
            return Err(ConfigError::NoRetiredCapacity);
        }
        if self.max_batch == 0 {
            return Err(ConfigError::NoBatch);
        }
        Ok(())
    }
}

/// A configuration that cannot work.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ConfigError {
    /// `max_scenes` is zero: no scene could ever register.
    NoScenes,
    /// `retired_capacity` is zero: identifiers would be reusable the moment they retire.
    NoRetiredCapacity,
    /// `max_batch` is zero: no command or policy could ever be set.
    NoBatch,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NoScenes => "max_scenes must be at least 1",
            Self::NoRetiredCapacity => "retired_capacity must be at least 1",
            Self::NoBatch => "max_batch must be at least 1",
        })
    }
}

impl std::error::Error for ConfigError {}

/// A live scene: what the rules read and write.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Scene {
    module: Module,
    phase: Phase,
    module_decision: Decision,
    operator_decision: OperatorDecision,
    requested: bool,
    age_ms: u64,
    geometry: Geometry,
}

impl Scene {
    /// The module the scene belongs to, for ever.
    #[must_use]
    pub const fn module(&self) -> Module {
        self.module
    }

    /// The lifecycle phase; never terminal for a live scene.
    #[must_use]
    pub const fn phase(&self) -> Phase {
        self.phase
    }

    /// The module decision, as last reported by the owner.
    #[must_use]
    pub const fn module_decision(&self) -> Decision {
        self.module_decision
    }

    /// The operator decision; `Undecided` until an operator command sets it.
    #[must_use]
    pub const fn operator_decision(&self) -> OperatorDecision {
        self.operator_decision
    }

    /// Whether the owner asks for an operator decision (`[COOP-REQUESTED.1]`): an undecided
    /// scene is then held back whatever its module's policy.
    #[must_use]
    pub const fn is_requested(&self) -> bool {
        self.requested
    }

    /// The policy that applies to this scene: `required` if the owner asks for an operator
    /// decision, else its module's policy (`[COOP-REQUESTED.1]`).
    #[must_use]
    pub const fn effective_policy(&self, module_policy: Policy) -> Policy {
        if self.requested {
            Policy::Required
        } else {
            module_policy
        }
    }

    /// Time since the owner last registered or updated the scene, at most the time-to-live.
    #[must_use]
    pub const fn age_ms(&self) -> u64 {
        self.age_ms
    }

    /// The geometry last reported.
    #[must_use]
    pub const fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// Whether operator commands are accepted (`[COOP-CANCELLABLE.1]`).
    #[must_use]
    pub const fn is_cancellable(&self) -> bool {
        self.phase.is_cancellable()
    }

    /// The merged decision under the module's policy (`[COOP-MERGE.1]`), with the policy
    /// made `required` for a requested scene (`[COOP-REQUESTED.1]`).
    #[must_use]
    pub const fn merged_decision(&self, module_policy: Policy) -> Decision {
        merge(
            self.operator_decision,
            self.effective_policy(module_policy),
            self.module_decision,
        )
    }

    /// The operator activated what the module would not, or would not decide on its own
    /// (`[COOP-FORCE-ACTIVATED.1]`).
    #[must_use]
    pub const fn is_force_activated(&self) -> bool {
        self.phase.is_cancellable()
            && matches!(self.operator_decision, OperatorDecision::Activate)
            && (matches!(self.module_decision, Decision::Deactivate) || self.requested)
    }

    /// The operator deactivated a running scene the module would go on with
    /// (`[COOP-FORCE-DEACTIVATED.1]`).
    #[must_use]
    pub const fn is_force_deactivated(&self) -> bool {
        matches!(self.phase, Phase::Running)
            && matches!(self.operator_decision, OperatorDecision::Deactivate)
            && matches!(self.module_decision, Decision::Activate)
    }
}

/// What an accepted input did.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Transition {
    /// The rule that fired.
    pub rule: Rule,
    /// The identifiers this input retired, in identifier order (empty for most inputs).
    pub retired: Vec<SceneId>,
}

impl Transition {
    const fn by(rule: Rule) -> Self {
        Self {
            rule,
            retired: Vec::new(),
        }
    }
}

/// What an accepted input will write, as decided by `State::decide`.
enum Plan<'a> {
    /// `[COOP-REG-NEW.1]`: the new scene, waiting, undecided and not yet aged.
    Register {
        id: SceneId,
        module: Module,
        decision: Decision,
        requested: bool,
        geometry: &'a Geometry,
    },
    /// `[COOP-OWN-UPDATE.1]`, for the scene at `at` in the table: found once, by `decide`.
    Update {
        at: usize,
        phase: Phase,
        decision: Decision,
        requested: bool,
        geometry: &'a Geometry,
    },
    /// `[COOP-OWN-FINISH.1]` or `[COOP-OWN-REMOVE.1]`.
    Retire {
        id: SceneId,
        reason: RetireReason,
        rule: Rule,
    },
    /// `[COOP-TIME-AGE.1]` or `[COOP-TIME-EXPIRE.1]`: age everything, retire `expired`.
    Tick {
        elapsed_ms: u64,
        expired: Vec<SceneId>,
    },
    /// `[COOP-CMD-APPLY.1]`.
    Commands(&'a [Command]),
    /// `[COOP-POL-SET.1]`.
    Policies(&'a [PolicySetting]),
}

/// Every module's policy, `None` for a module that does not support cooperation: one slot per
/// module, found by [`Module::index`] without a search.
#[derive(Clone, PartialEq, Eq, Hash)]
struct Policies([Option<Policy>; Module::COUNT]);

impl Policies {
    /// The policy of `module`, if it supports cooperation.
    fn get(&self, module: Module) -> Option<Policy> {
        self.0.get(module.index()).copied().flatten()
    }

    /// The policy of `module`, to change, if it supports cooperation.
    fn get_mut(&mut self, module: Module) -> Option<&mut Policy> {
        self.0.get_mut(module.index()).and_then(Option::as_mut)
    }

    /// Every module that supports cooperation and its policy, in module order.
    fn iter(&self) -> impl Iterator<Item = (Module, Policy)> + '_ {
        self.0
            .iter()
            .enumerate()
            .filter_map(|(index, policy)| Some((Module::at_index(index)?, (*policy)?)))
    }
}

impl FromIterator<(Module, Policy)> for Policies {
    /// Of two policies for one module, the later one stays.
    fn from_iter<I: IntoIterator<Item = (Module, Policy)>>(policies: I) -> Self {
        let mut slots = [None; Module::COUNT];
        for (module, policy) in policies {
            if let Some(slot) = slots.get_mut(module.index()) {
                *slot = Some(policy);
            }
        }
        Self(slots)
    }
}

impl core::fmt::Debug for Policies {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_map().entries(self.iter()).finish()
    }
}

/// The whole cooperation state: policies, live scenes and retired identifiers.
///
/// Changed only by [`State::apply`]. `Clone + Eq + Hash`, and every container in it compares,
/// hashes and iterates by its contents alone (the live scenes in identifier order, whatever
/// their layout), so that a model checker can hold it and every iteration order is
/// deterministic.
///
/// With the `serde` feature a state serializes with its maps as lists, and deserializes only if
/// [`State::new`] would accept its limits, no module, scene or retired identifier is listed
/// twice, and it passes [`State::check_invariants`]: only a state the core can hold reads back.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(into = "raw::State", try_from = "raw::State"))]
pub struct State {
    limits: Limits,
    policies: Policies,
    scenes: IdTable<Scene>,
    retired: BTreeMap<SceneId, Retirement>,
    /// The retired identifiers, oldest first; same set as `retired`.
    retired_order: VecDeque<SceneId>,
}

impl State {
    /// A state with the configured policies, no scenes and nothing retired.
    ///
    /// # Errors
    /// A [`ConfigError`] if a limit is zero.
    pub fn new(config: Config) -> Result<Self, ConfigError> {
        let Config { policies, limits } = config;
        limits.check()?;
        Ok(Self {
            limits,
            policies: policies.into_iter().collect(),
            scenes: IdTable::new(),
            retired: BTreeMap::new(),
            retired_order: VecDeque::new(),
        })
    }

    /// This state with its live scenes laid out as `layout` says. Nothing a rule, a query or a
    /// comparison sees changes: the layout is speed only. The model checker uses
    /// [`TableLayout::Colliding`] to explore the hashed table with a handful of scenes.
    #[must_use]
    pub fn with_table_layout(mut self, layout: TableLayout) -> Self {
        self.scenes = self.scenes.relaid(layout);
        self
    }

    /// How the live scenes are laid out.
    #[must_use]
    pub const fn table_layout(&self) -> TableLayout {
        self.scenes.layout()
    }

    /// Applies one input: the only way the state changes.
    ///
    /// Deterministic: the result depends on `self` and `input` only; nothing else is read and
    /// nothing but `self` is written. It decides first, reading `self` only, and writes only if
    /// the input is accepted: on `Err`, `self` is exactly as it was.
    ///
    /// # Errors
    /// A [`Rejection`] naming the rule that refused the input.
    pub fn apply(&mut self, input: &Input) -> Result<Transition, Rejection> {
        let plan = self.decide(input)?;
        let transition = self.commit(plan);
        debug_assert_eq!(self.check_invariants(), Ok(()), "after {input:?}");
        Ok(transition)
    }

    /// The transition function's decision: which rule the input fires, and what it will
    /// write, or the rejection. Every guard of spec §5 is here, each under its rule's tag.
    #[inline(always)]
    fn decide<'a>(&self, input: &'a Input) -> Result<Plan<'a>, Rejection> {
        match input {
            Input::Register {
                id,
                module,
                decision,
                requested,
                geometry,
            } => self.decide_register(*id, *module, *decision, *requested, geometry),
            Input::Update {
                id,
                module,
                phase,
                decision,
                requested,
                geometry,
            } => self.decide_update(*id, *module, *phase, *decision, *requested, geometry),
            Input::Remove { id, module } => {
                self.owned_scene(*id, *module)?;
                // [COOP-OWN-REMOVE.1]
                Ok(Plan::Retire {
                    id: *id,
                    reason: RetireReason::Removed,
                    rule: Rule::OwnerRemove,
                })
            }
            Input::SetCommands { commands } => self.decide_commands(commands),
            Input::SetPolicies { policies } => self.decide_policies(policies),
            Input::Tick { elapsed_ms } => Ok(self.decide_tick(*elapsed_ms)),
        }
    }

    /// Carries out a decision. No guard here: every choice was made by `decide`.
    #[inline(always)]
    fn commit(&mut self, plan: Plan<'_>) -> Transition {
        match plan {
            Plan::Register {
                id,
                module,
                decision,
                requested,
                geometry,
            } => {
                let scene = Scene {
                    module,
                    phase: Phase::WaitingForExecution,
                    module_decision: decision,
                    operator_decision: OperatorDecision::Undecided,
                    requested,
                    age_ms: 0,
                    geometry: *geometry,
                };
                self.scenes.insert(id, scene);
                Transition::by(Rule::RegisterNew)
            }
            Plan::Update {
                at,
                phase,
                decision,
                requested,
                geometry,
            } => {
                if let Some(scene) = self.scenes.value_at_mut(at) {
                    scene.phase = phase;
                    scene.module_decision = decision;
                    scene.requested = requested;
                    scene.geometry = *geometry;
                    scene.age_ms = 0;
                }
                Transition::by(Rule::OwnerUpdate)
            }
            Plan::Retire { id, reason, rule } => {
                self.retire(id, reason);
                Transition {
                    rule,
                    retired: vec![id],
                }
            }
            Plan::Tick {
                elapsed_ms,
                expired,
            } => {
                for scene in self.scenes.values_mut() {
                    scene.age_ms = scene.age_ms.saturating_add(elapsed_ms);
                }
                for id in &expired {
                    self.retire(*id, RetireReason::Expired);
                }
                let rule = if expired.is_empty() {
                    Rule::TimeAge
                } else {
                    Rule::TimeExpire
                };
                Transition {
                    rule,
                    retired: expired,
                }
            }
            Plan::Commands(commands) => {
                for command in commands {
                    if let Some(scene) = self.scenes.get_mut(command.id) {
                        scene.operator_decision = command.decision;
                    }
                }
                Transition::by(Rule::CommandApply)
            }
            Plan::Policies(settings) => {
                for setting in settings {
                    if let Some(policy) = self.policies.get_mut(setting.module) {
                        *policy = setting.policy;
                    }
                }
                Transition::by(Rule::PolicySet)
            }
        }
    }

    // ---------------------------------------------------------------------------------------
    // Scene owners
    // ---------------------------------------------------------------------------------------

    fn decide_register<'a>(
        &self,
        id: SceneId,
        module: Module,
        decision: Decision,
        requested: bool,
        geometry: &'a Geometry,
    ) -> Result<Plan<'a>, Rejection> {
        // [COOP-REG-RETIRED.1]
        if let Some(retirement) = self.retired.get(&id) {
            return Err(Rejection::Revival {
                id,
                retirement: *retirement,
            });
        }
        if let Some(scene) = self.scenes.get(id) {
            // [COOP-REG-LIVE.1]
            if scene.module == module {
                return Err(Rejection::AlreadyLive { id });
            }
            // [COOP-OWN-MODULE.1]
            return Err(Rejection::WrongModule {
                id,
                owner: scene.module,
                named: module,
            });
        }
        // [COOP-REG-MODULE.1]
        if self.policies.get(module).is_none() {
            return Err(Rejection::UnsupportedModule { id, module });
        }
        // [COOP-REG-FULL.1]
        if self.scenes.len() >= self.limits.max_scenes {
            return Err(Rejection::SceneLimit {
                limit: self.limits.max_scenes,
            });
        }
        // [COOP-REG-NEW.1]
        Ok(Plan::Register {
            id,
            module,
            decision,
            requested,
            geometry,
        })
    }

    #[inline(always)]
    fn decide_update<'a>(
        &self,
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        requested: bool,
        geometry: &'a Geometry,
    ) -> Result<Plan<'a>, Rejection> {
        let (at, scene) = self.owned_scene(id, module)?;
        // [COOP-OWN-KIND.1]
        if scene.geometry.kind() != geometry.kind() {
            return Err(Rejection::KindMismatch {
                id,
                registered: scene.geometry.kind(),
                given: geometry.kind(),
            });
        }
        // [COOP-OWN-TRANSITION.1]
        if !scene.phase.may_become(phase) {
            return Err(Rejection::PhaseTransition {
                id,
                from: scene.phase,
                to: phase,
            });
        }
        Ok(match phase {
            // [COOP-OWN-FINISH.1]
            Phase::Succeeded => Plan::Retire {
                id,
                reason: RetireReason::Succeeded,
                rule: Rule::OwnerFinish,
            },
            Phase::Failed => Plan::Retire {
                id,
                reason: RetireReason::Failed,
                rule: Rule::OwnerFinish,
            },
            // [COOP-OWN-UPDATE.1]
            Phase::WaitingForExecution | Phase::Running | Phase::Aborting => Plan::Update {
                at,
                phase,
                decision,
                requested,
                geometry,
            },
        })
    }

    /// The live scene `id` and its place in the table if `module` owns it, or the rejection
    /// every owner input shares.
    #[inline]
    fn owned_scene(&self, id: SceneId, module: Module) -> Result<(usize, &Scene), Rejection> {
        let found = self
            .scenes
            .position(id)
            .and_then(|at| self.scenes.value_at(at).map(|scene| (at, scene)));
        match found {
            // [COOP-OWN-MODULE.1]
            Some((_, scene)) if scene.module != module => Err(Rejection::WrongModule {
                id,
                owner: scene.module,
                named: module,
            }),
            Some(found) => Ok(found),
            None => Err(match self.retired.get(&id) {
                // [COOP-OWN-RETIRED.1]
                Some(retirement) => Rejection::RetiredScene {
                    id,
                    retirement: *retirement,
                },
                // [COOP-OWN-UNKNOWN.1]
                None => Rejection::UnknownScene { id },
            }),
        }
    }

    /// Moves a live scene to the retired set, forgetting the oldest retired identifier if the
    /// set is full.
    fn retire(&mut self, id: SceneId, reason: RetireReason) {
        // [COOP-RETIRE.1]
        let Some(scene) = self.scenes.remove(id) else {
            return;
        };
        while self.retired_order.len() >= self.limits.retired_capacity {
            match self.retired_order.pop_front() {
                Some(oldest) => self.retired.remove(&oldest),
                None => break,
            };
        }
        self.retired.insert(
            id,
            Retirement {
                module: scene.module,
                reason,
            },
        );
        self.retired_order.push_back(id);
    }

    // ---------------------------------------------------------------------------------------
    // Time
    // ---------------------------------------------------------------------------------------

    fn decide_tick(&self, elapsed_ms: u64) -> Plan<'static> {
        let ttl_ms = self.limits.ttl_ms;
        // In table order, which is cheap to walk, then in identifier order: usually nothing
        // expires, and the sort is free.
        let mut expired: Vec<SceneId> = self
            .scenes
            .iter_unordered()
            .filter(|(_, scene)| scene.age_ms.saturating_add(elapsed_ms) > ttl_ms)
            .map(|(id, _)| id)
            .collect();
        expired.sort_unstable();
        // [COOP-TIME-AGE.1] when nothing expires; [COOP-TIME-EXPIRE.1] otherwise.
        Plan::Tick {
            elapsed_ms,
            expired,
        }
    }

    // ---------------------------------------------------------------------------------------
    // Operators
    // ---------------------------------------------------------------------------------------

    fn decide_commands<'a>(&self, commands: &'a [Command]) -> Result<Plan<'a>, Rejection> {
        self.check_batch_len(commands.len())?;
        let failures = self.command_failures(commands);
        if let Some(&(index, failure)) = failures.first() {
            // [COOP-CMD-UNKNOWN.1] [COOP-CMD-RETIRED.1] [COOP-CMD-NOT-CANCELLABLE.1]
            // [COOP-CMD-DUPLICATE.1]: the first failure in batch order names the rule.
            let mut outcomes = vec![CommandOutcome::Withheld; commands.len()];
            for &(at, failure) in &failures {
                if let Some(outcome) = outcomes.get_mut(at) {
                    *outcome = CommandOutcome::Failed(failure);
                }
            }
            let failed = failures
                .iter()
                .filter_map(|&(at, _)| commands.get(at))
                .map(|c| c.id);
            return Err(Rejection::Commands {
                index,
                failure,
                outcomes,
                failed: failed.collect(),
            });
        }
        // [COOP-CMD-APPLY.1]
        Ok(Plan::Commands(commands))
    }

    /// Every command that cannot apply, with its position, in batch order.
    fn command_failures(&self, commands: &[Command]) -> Vec<(usize, CommandFailure)> {
        let mut seen = BTreeSet::new();
        let mut failures = Vec::new();
        for (index, command) in commands.iter().enumerate() {
            let failure = if commands.len() > 1 && !seen.insert(command.id) {
                Some(CommandFailure::DuplicateId)
            } else {
                match (self.scenes.get(command.id), self.retired.get(&command.id)) {
                    (Some(scene), _) if !scene.is_cancellable() => {
                        Some(CommandFailure::NotCancellable(scene.phase))
                    }
                    (Some(_), _) => None,
                    (None, Some(retirement)) => {
                        Some(CommandFailure::RetiredScene(retirement.reason))
                    }
                    (None, None) => Some(CommandFailure::UnknownScene),
                }
            };
            if let Some(failure) = failure {
                failures.push((index, failure));
            }
        }
        failures
    }

    fn decide_policies<'a>(&self, settings: &'a [PolicySetting]) -> Result<Plan<'a>, Rejection> {
        self.check_batch_len(settings.len())?;
        let mut seen = BTreeSet::new();
        for (index, setting) in settings.iter().enumerate() {
            // [COOP-POL-DUPLICATE.1]
            if !seen.insert(setting.module) {
                return Err(Rejection::DuplicatePolicyModule {
                    index,
                    module: setting.module,
                });
            }
            // [COOP-POL-UNKNOWN.1]
            if self.policies.get(setting.module).is_none() {
                return Err(Rejection::UnknownPolicyModule {
                    index,
                    module: setting.module,
                });
            }
        }
        // [COOP-POL-SET.1]
        Ok(Plan::Policies(settings))
    }

    fn check_batch_len(&self, len: usize) -> Result<(), Rejection> {
        // [COOP-BATCH-LIMIT.1]
        if len > self.limits.max_batch {
            return Err(Rejection::BatchLimit {
                len,
                limit: self.limits.max_batch,
            });
        }
        Ok(())
    }
    // ---------------------------------------------------------------------------------------
    // Queries
    // ---------------------------------------------------------------------------------------

    /// The limits in force.
    #[must_use]
    pub const fn limits(&self) -> Limits {
        self.limits
    }

    /// The live scene with this identifier.
    #[must_use]
    pub fn scene(&self, id: SceneId) -> Option<&Scene> {
        self.scenes.get(id)
    }

    /// Every live scene, in identifier order.
    pub fn scenes(&self) -> impl Iterator<Item = (SceneId, &Scene)> + '_ {
        self.scenes.iter()
    }

    /// Every live scene, in no particular order: for outputs sorted afterwards.
    pub(crate) fn scenes_in_any_order(&self) -> impl Iterator<Item = (SceneId, &Scene)> + '_ {
        self.scenes.iter_unordered()
    }

    /// The live scene at `position` of [`scenes_in_any_order`](Self::scenes_in_any_order).
    pub(crate) fn scene_at(&self, position: usize) -> Option<(SceneId, &Scene)> {
        self.scenes.entry_at(position)
    }

    /// How many scenes are live.
    #[must_use]
    pub fn scene_count(&self) -> usize {
        self.scenes.len()
    }

    /// What a retired identifier retired as, while it is remembered.
    #[must_use]
    pub fn retirement(&self, id: SceneId) -> Option<Retirement> {
        self.retired.get(&id).copied()
    }

    /// The remembered retired identifiers, oldest first.
    pub fn retired(&self) -> impl Iterator<Item = (SceneId, Retirement)> + '_ {
        self.retired_order
            .iter()
            .filter_map(|id| self.retired.get(id).map(|retirement| (*id, *retirement)))
    }

    /// The remembered retired identifiers, in identifier order.
    pub fn retirements(&self) -> impl Iterator<Item = (SceneId, Retirement)> + '_ {
        self.retired
            .iter()
            .map(|(id, retirement)| (*id, *retirement))
    }

    /// This state with every identifier renamed by `rename`, or `None` if `rename` gives two
    /// identifiers the same name.
    ///
    /// No rule reads an identifier's value, only whether two are equal and their order: a
    /// renamed state behaves as this one does with the names changed, except that scenes
    /// expiring on the same tick retire in the order of their new names. Model checkers use it
    /// for symmetry reduction.
    #[must_use]
    pub fn relabel(&self, rename: impl Fn(SceneId) -> SceneId) -> Option<Self> {
        let scenes = self.scenes.like(
            self.scenes
                .iter()
                .map(|(id, scene)| (rename(id), scene.clone())),
        );
        let retired: BTreeMap<SceneId, Retirement> = self
            .retired
            .iter()
            .map(|(id, retirement)| (rename(*id), *retirement))
            .collect();
        let renamed = Self {
            limits: self.limits,
            policies: self.policies.clone(),
            retired_order: self.retired_order.iter().map(|id| rename(*id)).collect(),
            scenes,
            retired,
        };
        let distinct = renamed.scenes.len() == self.scenes.len()
            && renamed.retired.len() == self.retired.len()
            && renamed
                .scenes
                .iter()
                .all(|(id, _)| !renamed.retired.contains_key(&id));
        distinct.then_some(renamed)
    }

    /// A module's current policy, if it supports cooperation.
    #[must_use]
    pub fn policy(&self, module: Module) -> Option<Policy> {
        self.policies.get(module)
    }

    /// Every module's current policy, in module order: the AD API `get_policies` answer
    /// (`[COOP-POL-GET.1]`).
    pub fn policies(&self) -> impl Iterator<Item = PolicySetting> + '_ {
        self.policies
            .iter()
            .map(|(module, policy)| PolicySetting { module, policy })
    }

    /// The merged decision the planner drives a live scene with (`[COOP-MERGE.1]`).
    #[must_use]
    pub fn merged_decision(&self, id: SceneId) -> Option<Decision> {
        let scene = self.scenes.get(id)?;
        let policy = self.policies.get(scene.module)?;
        Some(scene.merged_decision(policy))
    }

    /// Whether the operator activated what the module would not (`[COOP-FORCE-ACTIVATED.1]`).
    #[must_use]
    pub fn force_activated(&self, id: SceneId) -> Option<bool> {
        self.scenes.get(id).map(Scene::is_force_activated)
    }

    /// Whether the operator deactivated a running scene the module would go on with
    /// (`[COOP-FORCE-DEACTIVATED.1]`).
    #[must_use]
    pub fn force_deactivated(&self, id: SceneId) -> Option<bool> {
        self.scenes.get(id).map(Scene::is_force_deactivated)
    }

    // ---------------------------------------------------------------------------------------
    // Invariants
    // ---------------------------------------------------------------------------------------

    /// Whether the retirement order lists exactly the retired identifiers, each once. One
    /// algorithm for every size, so that the small sets a model checker sees run the same code
    /// as a full retired set.
    fn retired_order_is_exact(&self) -> bool {
        let order = &self.retired_order;
        // Same length, every entry retired, and no entry repeated: exactly the retired set.
        order.len() == self.retired.len()
            && order.iter().all(|id| self.retired.contains_key(id))
            && order.iter().collect::<BTreeSet<_>>().len() == order.len()
    }

    /// Checks every invariant of spec §8. `apply` asserts this after every input in debug
    /// builds; the models and the property tests call it too.
    ///
    /// # Errors
    /// The first [`Violation`] found.
    pub fn check_invariants(&self) -> Result<(), Violation> {
        let fail = |invariant, id| Err(Violation { invariant, id });
        // [COOP-INV-DISJOINT.1]
        if let Some((id, _)) = self
            .scenes
            .iter()
            .find(|(id, _)| self.retired.contains_key(id))
        {
            return fail(Invariant::Disjoint, Some(id));
        }
        // [COOP-INV-RETIRED-ORDER.1]
        if !self.retired_order_is_exact() {
            return fail(Invariant::RetiredOrder, None);
        }
        // [COOP-INV-RETIRED-BOUND.1]
        if self.retired.len() > self.limits.retired_capacity {
            return fail(Invariant::RetiredBound, None);
        }
        // [COOP-INV-LIVE-BOUND.1]
        if self.scenes.len() > self.limits.max_scenes {
            return fail(Invariant::LiveBound, None);
        }
        for (id, scene) in self.scenes.iter() {
            // [COOP-INV-LIVE-PHASE.1]
            if scene.phase.is_terminal() {
                return fail(Invariant::LivePhase, Some(id));
            }
            // [COOP-INV-AGE.1]
            if scene.age_ms > self.limits.ttl_ms {
                return fail(Invariant::Age, Some(id));
            }
            // [COOP-INV-MODULE.1]
            if self.policies.get(scene.module).is_none() {
                return fail(Invariant::Module, Some(id));
            }
        }
        Ok(())
    }
}

#[cfg(feature = "serde")]
mod raw;
