//! The state and its one transition function, [`State::apply`].
//!
//! Every arm of `apply` begins with the tag of the spec rule it implements. All checks of an
//! arm come before its first write, so a rejected input returns before anything changed.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::sync::Arc;

use crate::table::IdTable;
#[cfg(feature = "verification")]
use crate::table::TableLayout;
use policies::{Policies, Slot};

use crate::{
    Command, CommandFailure, CommandOutcome, Input, Module, OperatorDecision, Phase, PolicySetting,
    Rejection, Report, RetireReason, Retirement, Rule, SceneId,
};

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
        /// Where the module's policy is kept.
        slot: Slot,
        report: &'a Report,
    },
    /// `[COOP-OWN-UPDATE.1]`, for the scene at `at` in the table: found once, by `decide`.
    Update {
        at: usize,
        phase: Phase,
        report: &'a Report,
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
        rule: Rule,
    },
    /// `[COOP-CMD-APPLY.1]`.
    Commands(&'a [Command]),
    /// `[COOP-POL-SET.1]`.
    Policies(&'a [PolicySetting]),
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
///
/// # Methods by role
///
/// - **Making one:** [`new`](Self::new), from a [`Config`].
/// - **Changing it** (the only two writers): [`apply`](Self::apply), one input, and
///   [`apply_all`](Self::apply_all), a sequence of inputs all or none. Each answers the rule
///   that fired or the typed [`Rejection`].
/// - **The next state beside this one:** [`after`](Self::after), `apply` on a copy made only
///   once the input is accepted (what a model checker calls).
/// - **Asking about scenes:** [`scene`](Self::scene), [`scenes`](Self::scenes),
///   [`scene_count`](Self::scene_count), [`merged_decision`](Self::merged_decision),
///   [`merged_decisions`](Self::merged_decisions), [`awaits_operator`](Self::awaits_operator),
///   [`force_activated`](Self::force_activated),
///   [`force_deactivated`](Self::force_deactivated), [`status`](Self::status).
/// - **Asking about identifiers, policies and limits:** [`retirement`](Self::retirement),
///   [`retired_oldest_first`](Self::retired_oldest_first),
///   [`retired_by_id`](Self::retired_by_id), [`policy`](Self::policy),
///   [`policies`](Self::policies) (the AD API's `get_policies`), [`limits`](Self::limits).
/// - **Outputs for the operator** (filling caller-owned buffers):
///   [`statuses_into`](Self::statuses_into),
///   [`velocity_factors_into`](Self::velocity_factors_into),
///   [`steering_factors_into`](Self::steering_factors_into),
///   [`velocity_factors_with`](Self::velocity_factors_with),
///   [`steering_factors_with`](Self::steering_factors_with),
///   [`factors_into`](Self::factors_into).
/// - **Checking it:** [`check_invariants`](Self::check_invariants), spec §8.
/// - **The model checker's hooks**, with the `verification` feature only: `relabel` (renaming
///   identifiers, for symmetry reduction), `with_table_layout` and `table_layout` (the hashed
///   table from the first scene).
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(into = "raw::State", try_from = "raw::State"))]
pub struct State {
    limits: Limits,
    policies: Policies,
    scenes: IdTable<Scene>,
    /// The retired identifiers. Shared between clones until a retirement changes them, as the
    /// policies are: most inputs retire nothing, and a model checker clones the state for
    /// every step it takes.
    retired: Arc<BTreeMap<SceneId, Retirement>>,
    /// The retired identifiers, oldest first; same set as `retired`, shared as it is.
    retired_order: Arc<VecDeque<SceneId>>,
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
            retired: Arc::default(),
            retired_order: Arc::default(),
        })
    }

    /// This state with its live scenes laid out as `layout` says. A model checker's hook, with
    /// the `verification` feature only.
    /// Nothing a rule, a query or a
    /// comparison sees changes: the layout is speed only. The model checker uses
    /// [`TableLayout::Colliding`] to explore the hashed table with a handful of scenes.
    #[cfg(feature = "verification")]
    #[must_use]
    pub fn with_table_layout(mut self, layout: TableLayout) -> Self {
        self.scenes = self.scenes.relaid(layout);
        self
    }

    /// How the live scenes are laid out. A model checker's hook, with the `verification`
    /// feature only.
    #[cfg(feature = "verification")]
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
        let transition = self.commit(plan, &mut Forget);
        debug_assert_eq!(self.check_invariants(), Ok(()), "after {input:?}");
        Ok(transition)
    }

    /// The state one input leads to, and its transition, with `self` left as it is: what
    /// [`apply`](Self::apply) does to a copy of `self`, the same decision and the same writes,
    /// except that the copy is made only once the input is accepted. A caller that keeps every
    /// state it passes through (a model checker, an undo history) copies nothing for a refused
    /// input.
    ///
    /// # Errors
    /// The [`Rejection`] `apply` gives for the same input.
    pub fn after(&self, input: &Input) -> Result<(Self, Transition), Rejection> {
        let plan = self.decide(input)?;
        let mut next = self.clone();
        let transition = next.commit(plan, &mut Forget);
        debug_assert_eq!(next.check_invariants(), Ok(()), "after {input:?}");
        Ok((next, transition))
    }

    /// The transition function's decision: which rule the input fires, and what it will
    /// write, or the rejection. Every guard of spec §5 is here, each under its rule's tag.
    #[inline(always)]
    fn decide<'a>(&self, input: &'a Input) -> Result<Plan<'a>, Rejection> {
        match input {
            Input::Register { id, module, report } => self.decide_register(*id, *module, report),
            Input::Update {
                id,
                module,
                phase,
                report,
            } => self.decide_update(*id, *module, *phase, report),
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

    /// Carries out a decision. No guard here: every choice was made by `decide`. Before each
    /// write it tells `journal` what the write overwrites ([`State::apply_all`] keeps that, to
    /// take a batch back; [`State::apply`] forgets it, at no cost).
    #[inline(always)]
    fn commit(&mut self, plan: Plan<'_>, journal: &mut impl Journal) -> Transition {
        match plan {
            Plan::Register {
                id,
                module,
                slot,
                report,
            } => {
                journal.record(|| Undo::Registered(id));
                let scene = Scene {
                    module,
                    phase: Phase::Waiting,
                    module_decision: report.decision,
                    operator_decision: OperatorDecision::Undecided,
                    requested: report.requested,
                    age_ms: 0,
                    geometry: report.geometry,
                    detail: report.detail.clone(),
                    slot,
                };
                self.scenes.insert(id, scene);
                Transition::by(Rule::RegisterNew)
            }
            Plan::Update { at, phase, report } => {
                if let Some((id, scene)) = self.scenes.entry_at(at) {
                    journal.record(|| Undo::Changed(id, scene.clone()));
                }
                if let Some(scene) = self.scenes.value_at_mut(at) {
                    scene.phase = phase;
                    scene.module_decision = report.decision;
                    scene.requested = report.requested;
                    scene.geometry = report.geometry;
                    scene.detail.clone_from(&report.detail);
                    scene.age_ms = 0;
                }
                Transition::by(Rule::OwnerUpdate)
            }
            Plan::Retire { id, reason, rule } => {
                self.retire(id, reason, journal);
                Transition {
                    rule,
                    retired: vec![id],
                }
            }
            Plan::Tick {
                elapsed_ms,
                expired,
                rule,
            } => {
                journal.record(|| {
                    Undo::Aged(self.scenes.iter().map(|(id, s)| (id, s.age_ms)).collect())
                });
                for scene in self.scenes.values_mut() {
                    scene.age_ms = scene.age_ms.saturating_add(elapsed_ms);
                }
                for id in &expired {
                    self.retire(*id, RetireReason::Expired, journal);
                }
                Transition {
                    rule,
                    retired: expired,
                }
            }
            Plan::Commands(commands) => {
                for command in commands {
                    if let Some(scene) = self.scenes.get(command.id) {
                        journal.record(|| Undo::Changed(command.id, scene.clone()));
                    }
                    if let Some(scene) = self.scenes.get_mut(command.id) {
                        scene.operator_decision = command.decision;
                    }
                }
                Transition::by(Rule::CommandApply)
            }
            Plan::Policies(settings) => {
                for setting in settings {
                    if let Some(policy) = self.policies.get(setting.module) {
                        journal.record(|| Undo::Policy(setting.module, policy));
                    }
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
        report: &'a Report,
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
        let Some(slot) = self.policies.slot(module) else {
            return Err(Rejection::UnsupportedModule { id, module });
        };
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
            slot,
            report,
        })
    }

    #[inline(always)]
    fn decide_update<'a>(
        &self,
        id: SceneId,
        module: Module,
        phase: Phase,
        report: &'a Report,
    ) -> Result<Plan<'a>, Rejection> {
        let (at, scene) = self.owned_scene(id, module)?;
        // [COOP-OWN-KIND.1]
        if scene.geometry.kind() != report.geometry.kind() {
            return Err(Rejection::KindMismatch {
                id,
                registered: scene.geometry.kind(),
                given: report.geometry.kind(),
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
            Phase::Waiting | Phase::Running | Phase::Aborting => Plan::Update { at, phase, report },
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
                Some(retirement) => Rejection::OwnerRetired {
                    id,
                    retirement: *retirement,
                },
                // [COOP-OWN-UNKNOWN.1]
                None => Rejection::OwnerUnknown { id },
            }),
        }
    }

    /// Moves a live scene to the retired set, forgetting the oldest retired identifier if the
    /// set is full.
    fn retire(&mut self, id: SceneId, reason: RetireReason, journal: &mut impl Journal) {
        // [COOP-RETIRE.1]
        let Some(scene) = self.scenes.remove(id) else {
            return;
        };
        journal.record(|| Undo::Retired(id, scene.clone()));
        let (retired, order) = (
            Arc::make_mut(&mut self.retired),
            Arc::make_mut(&mut self.retired_order),
        );
        while order.len() >= self.limits.retired_capacity {
            let Some(oldest) = order.pop_front() else {
                break;
            };
            if let Some(retirement) = retired.remove(&oldest) {
                journal.record(|| Undo::Forgot(oldest, retirement));
            }
        }
        retired.insert(
            id,
            Retirement {
                module: scene.module,
                reason,
            },
        );
        order.push_back(id);
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
        let rule = if expired.is_empty() {
            // [COOP-TIME-AGE.1]
            Rule::TimeAge
        } else {
            // [COOP-TIME-EXPIRE.1]
            Rule::TimeExpire
        };
        Plan::Tick {
            elapsed_ms,
            expired,
            rule,
        }
    }

    // ---------------------------------------------------------------------------------------
    // Operators
    // ---------------------------------------------------------------------------------------

    fn decide_commands<'a>(&self, commands: &'a [Command]) -> Result<Plan<'a>, Rejection> {
        self.check_batch_len(commands.len())?;
        let failures = self.command_failures(commands);
        if let Some(&(index, failure)) = failures.first() {
            // The first failure in batch order names the rule (`command_failures` tags each).
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
                // [COOP-CMD-DUPLICATE.1]
                Some(CommandFailure::DuplicateId)
            } else {
                // The retired identifiers are searched only for a scene that is not live.
                match self
                    .scenes
                    .get(command.id)
                    .ok_or_else(|| self.retired.get(&command.id))
                {
                    // [COOP-CMD-NOT-CANCELLABLE.1]
                    Ok(scene) if !scene.is_cancellable() => {
                        Some(CommandFailure::NotCancellable(scene.phase))
                    }
                    Ok(_) => None,
                    // [COOP-CMD-RETIRED.1]
                    Err(Some(retirement)) => Some(CommandFailure::RetiredScene(retirement.reason)),
                    // [COOP-CMD-UNKNOWN.1]
                    Err(None) => Some(CommandFailure::UnknownScene),
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
}

mod batch;
mod config;
mod invariants;
mod policies;
mod queries;
#[cfg(feature = "serde")]
mod raw;
mod scene;

pub use batch::SequenceRejection;
use batch::{Forget, Journal, Undo};
pub use config::{Config, ConfigError, Limits};
pub use invariants::{Invariant, Violation};
pub use scene::Scene;
