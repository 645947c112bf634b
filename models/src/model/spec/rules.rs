//! The rules of spec §5 (and the retirement of §6.1) written out from the spec's text, as an
//! independent statement the model's properties compare the library with.
//!
//! This is not the library's code and must not become a copy of it: each arm below follows
//! the spec's *When*, in the order the spec lists its rules, and builds the spec's *Then* on a
//! [`Snapshot`], a plain record of the state as spec §3 describes it, read through the
//! library's public queries. The model never moves a state with it: `next_state` calls
//! `State::apply`, and the properties ask whether what `apply` did is what this says.

// A refusal is the rule with the core's `Rejection` (itself small enough for `State::apply`),
// compared with what `apply` returned one call up. Boxing it would allocate on every refused
// step of a check.
#![allow(clippy::result_large_err)]

use std::sync::Arc;

use cooperation::{
    Command, CommandFailure, CommandOutcome, Decision, Detail, FactorKind, Geometry, Input, Limits,
    Module, OperatorDecision, Phase, Policy, PolicySetting, Rejection, Report, RetireReason,
    Retirement, Rule, Scene, SceneId, State,
};

use super::LifecycleTable;

/// A live scene as spec §3 lists its variables.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneRecord {
    /// Its module, fixed.
    pub module: Module,
    /// Its phase.
    pub phase: Phase,
    /// The module decision.
    pub module_decision: Decision,
    /// The operator decision.
    pub operator_decision: OperatorDecision,
    /// Whether its owner asks for an operator decision.
    pub requested: bool,
    /// Its age, in ms.
    pub age_ms: u64,
    /// Its geometry.
    pub geometry: Geometry,
    /// Its detail.
    pub detail: Detail,
}

/// The whole state as spec §3 lists its variables.
///
/// The policies and the retired identifiers are shared between a snapshot and the copies the
/// rules make of it until a rule changes them: most inputs change neither, and the model
/// copies the snapshot for every accepted input.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// The limits.
    pub limits: Limits,
    /// Every configured module's policy, in module order.
    pub policies: Arc<Vec<(Module, Policy)>>,
    /// The live scenes, in identifier order.
    pub scenes: Vec<(SceneId, SceneRecord)>,
    /// The retired identifiers, oldest retirement first.
    pub retired: Arc<Vec<(SceneId, Retirement)>>,
}

impl Snapshot {
    /// The library's state, read through its public queries.
    #[must_use]
    pub fn of(state: &State) -> Self {
        let scenes = state.scenes().map(|(id, scene)| (id, record(scene)));
        Self {
            limits: state.limits(),
            policies: Arc::new(state.policies().map(|p| (p.module, p.policy)).collect()),
            scenes: scenes.collect(),
            retired: Arc::new(state.retired_oldest_first().collect()),
        }
    }

    /// Whether `state` is this snapshot, compared field by field without building a snapshot of
    /// it (the model compares after every accepted input).
    #[must_use]
    pub fn matches(&self, state: &State) -> bool {
        state.limits() == self.limits
            && state
                .policies()
                .map(|p| (p.module, p.policy))
                .eq(self.policies.iter().copied())
            && state.scene_count() == self.scenes.len()
            && state
                .scenes()
                .zip(&self.scenes)
                .all(|((id, scene), (listed, record))| id == *listed && record.is(scene))
            && state
                .retired_oldest_first()
                .eq(self.retired.iter().copied())
    }

    fn scene(&self, id: SceneId) -> Option<&SceneRecord> {
        self.scenes
            .iter()
            .find(|(live, _)| *live == id)
            .map(|(_, scene)| scene)
    }

    fn scene_mut(&mut self, id: SceneId) -> Option<&mut SceneRecord> {
        self.scenes
            .iter_mut()
            .find(|(live, _)| *live == id)
            .map(|(_, scene)| scene)
    }

    fn has_policy(&self, module: Module) -> bool {
        self.policies
            .iter()
            .any(|(configured, _)| *configured == module)
    }

    fn retirement(&self, id: SceneId) -> Option<Retirement> {
        self.retired
            .iter()
            .find(|(retired, _)| *retired == id)
            .map(|(_, retirement)| *retirement)
    }

    /// `[COOP-RETIRE.1]`: the scene leaves the live scenes and joins the retired set with its
    /// module and reason; a full set forgets the identifier that retired longest ago first.
    fn retire(&mut self, id: SceneId, reason: RetireReason) {
        let Some(at) = self.scenes.iter().position(|(live, _)| *live == id) else {
            return;
        };
        let (_, scene) = self.scenes.remove(at);
        let retired = Arc::make_mut(&mut self.retired);
        while retired.len() >= self.limits.retired_capacity && !retired.is_empty() {
            retired.remove(0);
        }
        let retirement = Retirement {
            module: scene.module,
            reason,
        };
        retired.push((id, retirement));
    }
}

/// A live scene's variables, read through the library's queries.
impl SceneRecord {
    /// Whether `scene` is this record, every field compared where it lies (no record is built).
    fn is(&self, scene: &Scene) -> bool {
        let Self {
            module,
            phase,
            module_decision,
            operator_decision,
            requested,
            age_ms,
            geometry,
            detail,
        } = self;
        *module == scene.module()
            && *phase == scene.phase()
            && *module_decision == scene.module_decision()
            && *operator_decision == scene.operator_decision()
            && *requested == scene.is_requested()
            && *age_ms == scene.age_ms()
            && geometry == scene.geometry()
            && detail == scene.detail()
    }
}

fn record(scene: &Scene) -> SceneRecord {
    SceneRecord {
        module: scene.module(),
        phase: scene.phase(),
        module_decision: scene.module_decision(),
        operator_decision: scene.operator_decision(),
        requested: scene.is_requested(),
        age_ms: scene.age_ms(),
        geometry: *scene.geometry(),
        detail: scene.detail().clone(),
    }
}

/// What the spec says an input does: the rule, and either the state after it with the
/// identifiers it retires, or the rejection (after which the state is unchanged).
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The rule the input fires or is rejected by.
    pub rule: Rule,
    /// The state after it and the identifiers it retires, or the rejection.
    pub outcome: Result<(Snapshot, Vec<SceneId>), Rejection>,
}

/// A rejection by `rule`.
type Refusal = (Rule, Rejection);

fn fires(rule: Rule, after: Snapshot, retired: Vec<SceneId>) -> Result<Verdict, Refusal> {
    Ok(Verdict {
        rule,
        outcome: Ok((after, retired)),
    })
}

/// What spec §5 says `input` does in `before`.
#[must_use]
pub fn verdict(lifecycle: &LifecycleTable, before: &Snapshot, input: &Input) -> Verdict {
    decide(lifecycle, before, input).unwrap_or_else(|(rule, rejection)| Verdict {
        rule,
        outcome: Err(rejection),
    })
}

fn decide(
    lifecycle: &LifecycleTable,
    before: &Snapshot,
    input: &Input,
) -> Result<Verdict, Refusal> {
    match input {
        Input::Register { id, module, report } => register(before, *id, *module, report),
        Input::Update {
            id,
            module,
            phase,
            report,
        } => {
            owned(before, *id, *module)?;
            update(lifecycle, before, *id, *phase, report)
        }
        Input::Remove { id, module } => {
            owned(before, *id, *module)?;
            let mut after = before.clone();
            after.retire(*id, RetireReason::Removed);
            fires(Rule::OwnerRemove, after, vec![*id])
        }
        Input::Tick { elapsed_ms } => tick(before, *elapsed_ms),
        Input::SetCommands { commands } => {
            batch(before, commands.len())?;
            set_commands(before, commands)
        }
        Input::SetPolicies { policies } => {
            batch(before, policies.len())?;
            set_policies(before, policies)
        }
    }
}

/// §5.1, in the order the spec lists its rules.
fn register(
    before: &Snapshot,
    id: SceneId,
    module: Module,
    report: &Report,
) -> Result<Verdict, Refusal> {
    if let Some(retirement) = before.retirement(id) {
        return Err((Rule::RegisterRetired, Rejection::Revival { id, retirement }));
    }
    if let Some(scene) = before.scene(id) {
        return Err(if scene.module == module {
            (Rule::RegisterLive, Rejection::AlreadyLive { id })
        } else {
            wrong_module(id, scene.module, module)
        });
    }
    if !before.has_policy(module) {
        return Err((
            Rule::RegisterModule,
            Rejection::UnsupportedModule { id, module },
        ));
    }
    if before.scenes.len() + 1 > before.limits.max_scenes {
        let limit = before.limits.max_scenes;
        return Err((Rule::RegisterFull, Rejection::SceneLimit { limit }));
    }
    let mut after = before.clone();
    let scene = SceneRecord {
        module,
        phase: Phase::Waiting,
        module_decision: report.decision,
        operator_decision: OperatorDecision::Undecided,
        requested: report.requested,
        age_ms: 0,
        geometry: report.geometry,
        detail: report.detail.clone(),
    };
    let at = after.scenes.partition_point(|(live, _)| *live < id);
    after.scenes.insert(at, (id, scene));
    fires(Rule::RegisterNew, after, Vec::new())
}

fn wrong_module(id: SceneId, owner: Module, named: Module) -> Refusal {
    let rejection = Rejection::WrongModule { id, owner, named };
    (Rule::OwnerModule, rejection)
}

/// The identifier checks of §5.2 that every owner input shares, in the spec's order.
fn owned(before: &Snapshot, id: SceneId, module: Module) -> Result<(), Refusal> {
    match (before.scene(id), before.retirement(id)) {
        (Some(scene), _) if scene.module != module => Err(wrong_module(id, scene.module, module)),
        (Some(_), _) => Ok(()),
        (None, None) => Err((Rule::OwnerUnknown, Rejection::OwnerUnknown { id })),
        (None, Some(retirement)) => Err((
            Rule::OwnerRetired,
            Rejection::OwnerRetired { id, retirement },
        )),
    }
}

/// The rest of §5.2 for an update of a live scene of the module.
fn update(
    lifecycle: &LifecycleTable,
    before: &Snapshot,
    id: SceneId,
    phase: Phase,
    report: &Report,
) -> Result<Verdict, Refusal> {
    let Some(scene) = before.scene(id) else {
        return Err((Rule::OwnerUnknown, Rejection::OwnerUnknown { id }));
    };
    let kind = |g: &Geometry| match g {
        Geometry::Velocity { .. } => FactorKind::Velocity,
        Geometry::Steering { .. } => FactorKind::Steering,
    };
    if kind(&scene.geometry) != kind(&report.geometry) {
        let rejection = Rejection::KindMismatch {
            id,
            registered: kind(&scene.geometry),
            given: kind(&report.geometry),
        };
        return Err((Rule::OwnerKind, rejection));
    }
    if !lifecycle.allows(scene.phase, phase) {
        let rejection = Rejection::PhaseTransition {
            id,
            from: scene.phase,
            to: phase,
        };
        return Err((Rule::OwnerTransition, rejection));
    }
    let mut after = before.clone();
    let finish = match phase {
        Phase::Succeeded => Some(RetireReason::Succeeded),
        Phase::Failed => Some(RetireReason::Failed),
        Phase::Waiting | Phase::Running | Phase::Aborting => None,
    };
    if let Some(reason) = finish {
        after.retire(id, reason);
        return fires(Rule::OwnerFinish, after, vec![id]);
    }
    if let Some(scene) = after.scene_mut(id) {
        scene.phase = phase;
        scene.module_decision = report.decision;
        scene.requested = report.requested;
        scene.geometry = report.geometry;
        scene.detail.clone_from(&report.detail);
        scene.age_ms = 0;
    }
    fires(Rule::OwnerUpdate, after, Vec::new())
}

/// §5.3: every age grows; the scenes past the TTL retire as expired, in identifier order.
fn tick(before: &Snapshot, elapsed_ms: u64) -> Result<Verdict, Refusal> {
    let mut after = before.clone();
    for (_, scene) in &mut after.scenes {
        scene.age_ms = scene.age_ms.saturating_add(elapsed_ms);
    }
    let ttl = after.limits.ttl_ms;
    let expired: Vec<SceneId> = after
        .scenes
        .iter()
        .filter(|(_, scene)| scene.age_ms > ttl)
        .map(|(id, _)| *id)
        .collect();
    for id in &expired {
        after.retire(*id, RetireReason::Expired);
    }
    let rule = if expired.is_empty() {
        Rule::TimeAge
    } else {
        Rule::TimeExpire
    };
    fires(rule, after, expired)
}

/// §5.6, checked before any entry of a batch.
fn batch(before: &Snapshot, len: usize) -> Result<(), Refusal> {
    let limit = before.limits.max_batch;
    if len > limit {
        return Err((Rule::BatchLimit, Rejection::BatchLimit { len, limit }));
    }
    Ok(())
}

/// §5.4: each command classified in batch order; all apply or none.
fn set_commands(before: &Snapshot, commands: &[Command]) -> Result<Verdict, Refusal> {
    let mut outcomes = Vec::with_capacity(commands.len());
    for (at, command) in commands.iter().enumerate() {
        let earlier = commands.iter().take(at).any(|c| c.id == command.id);
        // §6.3: a live scene is cancellable when it is waiting or running.
        let failure = match (before.scene(command.id), before.retirement(command.id)) {
            _ if earlier => Some(CommandFailure::DuplicateId),
            (Some(scene), _) => match scene.phase {
                Phase::Waiting | Phase::Running => None,
                phase => Some(CommandFailure::NotCancellable(phase)),
            },
            (None, Some(retirement)) => Some(CommandFailure::RetiredScene(retirement.reason)),
            (None, None) => Some(CommandFailure::UnknownScene),
        };
        outcomes.push(failure.map_or(CommandOutcome::Withheld, CommandOutcome::Failed));
    }
    let first = outcomes.iter().enumerate().find_map(|(at, o)| match o {
        CommandOutcome::Failed(failure) => Some((at, *failure)),
        _ => None,
    });
    if let Some((index, failure)) = first {
        let failed = commands
            .iter()
            .zip(&outcomes)
            .filter(|(_, o)| matches!(o, CommandOutcome::Failed(_)))
            .map(|(c, _)| c.id)
            .collect();
        let rule = match failure {
            CommandFailure::DuplicateId => Rule::CommandDuplicate,
            CommandFailure::NotCancellable(_) => Rule::CommandNotCancellable,
            CommandFailure::RetiredScene(_) => Rule::CommandRetired,
            CommandFailure::UnknownScene => Rule::CommandUnknown,
        };
        let rejection = Rejection::Commands {
            index,
            failure,
            outcomes,
            failed,
        };
        return Err((rule, rejection));
    }
    let mut after = before.clone();
    for command in commands {
        if let Some(scene) = after.scene_mut(command.id) {
            scene.operator_decision = command.decision;
        }
    }
    fires(Rule::CommandApply, after, Vec::new())
}

/// §5.5: each setting checked in batch order; all apply or none.
fn set_policies(before: &Snapshot, settings: &[PolicySetting]) -> Result<Verdict, Refusal> {
    for (index, setting) in settings.iter().enumerate() {
        let module = setting.module;
        if settings.iter().take(index).any(|s| s.module == module) {
            let rejection = Rejection::DuplicatePolicyModule { index, module };
            return Err((Rule::PolicyDuplicate, rejection));
        }
        if !before.has_policy(module) {
            let rejection = Rejection::UnknownPolicyModule { index, module };
            return Err((Rule::PolicyUnknown, rejection));
        }
    }
    let mut after = before.clone();
    for setting in settings {
        for (module, policy) in Arc::make_mut(&mut after.policies).iter_mut() {
            if *module == setting.module {
                *policy = setting.policy;
            }
        }
    }
    fires(Rule::PolicySet, after, Vec::new())
}

impl Verdict {
    /// Whether the library's result and the state it left agree with this verdict: the same
    /// rule; for an accepted input the same transition and the spec's next state, and the
    /// state changed exactly when the spec's next state differs from `before`; for a
    /// rejection the same rejection and the state unchanged (`unchanged`: the state after the
    /// input equals the state before it, which the caller has compared once for all its uses).
    #[must_use]
    pub fn agrees(
        &self,
        before: &Snapshot,
        result: &Result<cooperation::Transition, Rejection>,
        unchanged: bool,
        after: &State,
    ) -> bool {
        let rule = match result {
            Ok(transition) => transition.rule,
            Err(rejection) => rejection.rule(),
        };
        rule == self.rule
            && match (&self.outcome, result) {
                (Ok((next, retired)), Ok(transition)) => {
                    transition.retired == *retired
                        && next.matches(after)
                        && unchanged == (next == before)
                }
                (Err(expected), Err(rejection)) => rejection == expected && unchanged,
                _ => false,
            }
    }
}
