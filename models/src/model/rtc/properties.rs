//! The RTC model's properties, named by the specification's tags: step properties (sticky
//! flags the model sets when a step breaks one), state properties over what the adapter
//! answers, and reachability of every kind of call's interesting answers and of a few
//! scenarios, so that a vacuous pass shows.

use cooperation::{
    Decision, OperatorDecision, Phase, Policy, RetireReason, Rule, Scene, SceneId, State,
};
use cooperation_adapters::rtc::{self, CooperateStatus, Kind as BindingKind};
use cooperation_adapters::Time;
use stateright::Property;

use super::step::{Answer, Broken, Kind, Outcome, Refusal, RtcStep};
use super::{modules_of, RtcModel, FINISH_DISTANCE, START_DISTANCE};

type Condition = fn(&RtcModel, &RtcStep) -> bool;

/// The stamp the properties ask for status arrays with.
const STAMP: Time = Time::new(100, 0);

/// A scene's `auto_mode` as `docs/rtc.md` defines it: the operator decision is autonomous, or
/// none under an optional policy.
fn auto_mode(core: &State, scene: &Scene) -> bool {
    match scene.operator_decision() {
        OperatorDecision::Autonomous => true,
        OperatorDecision::Undecided => core.policy(scene.module()) == Some(Policy::Optional),
        OperatorDecision::Activate | OperatorDecision::Deactivate => false,
    }
}

/// The live scenes, with the interface that registered each (as the model saw it).
fn live(step: &RtcStep) -> impl Iterator<Item = (SceneId, &Scene, Option<usize>)> + '_ {
    step.core
        .scenes()
        .map(|(id, scene)| (id, scene, step.registrar(id).map(usize::from)))
}

fn unbroken<const FLAG: u16>(_: &RtcModel, step: &RtcStep) -> bool {
    !step.broken.contains(Broken(FLAG))
}

/// Every remembered identifier's route is the interface whose update registered it.
fn routed_to_registrar(model: &RtcModel, step: &RtcStep) -> bool {
    model
        .ids()
        .iter()
        .all(|&id| step.owner(id) == step.registrar(id))
}

/// The status a live scene should have, as `docs/rtc.md`'s field table says.
fn expected_status(
    model: &RtcModel,
    step: &RtcStep,
    id: SceneId,
    scene: &Scene,
    at: usize,
) -> Option<CooperateStatus> {
    let binding = model.binding(at)?;
    let finish = match binding.kind {
        BindingKind::Velocity => START_DISTANCE,
        BindingKind::Steering(_) => FINISH_DISTANCE,
    };
    let command = if scene.operator_decision() == OperatorDecision::Activate {
        rtc::Command::ACTIVATE
    } else {
        rtc::Command::DEACTIVATE
    };
    Some(CooperateStatus {
        stamp: STAMP.before_ms(scene.age_ms()),
        uuid: id.into(),
        module: binding.module_type.into(),
        safe: scene.module_decision() == Decision::Activate,
        requested: scene.is_requested(),
        command_status: rtc::Command::new(command),
        state: scene.phase().into(),
        auto_mode: auto_mode(&step.core, scene),
        start_distance: START_DISTANCE,
        finish_distance: finish,
    })
}

/// Each interface's status array lists exactly the live scenes it registered, in identifier
/// order, with the core's values.
fn statuses_are_the_cores(model: &RtcModel, step: &RtcStep) -> bool {
    (0..model.bindings().len()).all(|at| {
        let Some(view) = model.view(step, at) else {
            return false;
        };
        let array = view.cooperate_status_array(STAMP);
        let expected: Vec<Option<CooperateStatus>> = live(step)
            .filter(|(_, _, registrar)| *registrar == Some(at))
            .map(|(id, scene, _)| expected_status(model, step, id, scene, at))
            .collect();
        array.stamp == STAMP
            && array.statuses.len() == expected.len()
            && array
                .statuses
                .iter()
                .zip(&expected)
                .all(|(s, e)| Some(*s) == *e)
    })
}

/// The external status array is every interface's, nearest start first, then by identifier.
fn external_statuses(model: &RtcModel, step: &RtcStep) -> bool {
    let array = step.rtc.cooperate_status_array(&step.core, STAMP);
    let key = |s: &CooperateStatus| (s.uuid, s.module);
    let mut all: Vec<CooperateStatus> = (0..model.bindings().len())
        .filter_map(|at| model.view(step, at))
        .flat_map(|view| view.cooperate_status_array(STAMP).statuses)
        .collect();
    all.sort_by_key(key);
    let mut listed = array.statuses.clone();
    listed.sort_by_key(key);
    let sorted = array.statuses.windows(2).all(|pair| match pair {
        [a, b] => a
            .start_distance
            .total_cmp(&b.start_distance)
            .then(a.uuid.cmp(&b.uuid))
            .is_lt(),
        _ => true,
    });
    array.stamp == STAMP && listed == all && sorted
}

/// Runs `check(view, interface, id)` for every interface and identifier.
fn every_query(
    model: &RtcModel,
    step: &RtcStep,
    check: impl Fn(&rtc::View<'_>, usize, SceneId) -> bool,
) -> bool {
    (0..model.bindings().len()).all(|at| {
        model
            .view(step, at)
            .is_some_and(|view| model.ids().iter().all(|&id| check(&view, at, id)))
    })
}

/// The interface's own live scene `id`.
fn own(step: &RtcStep, at: usize, id: SceneId) -> Option<&Scene> {
    step.core
        .scene(id)
        .filter(|_| step.registrar(id).map(usize::from) == Some(at))
}

fn activated_is_merged(model: &RtcModel, step: &RtcStep) -> bool {
    every_query(model, step, |view, at, id| {
        let merged = own(step, at, id).and(step.core.merged_decision(id));
        view.is_activated(id) == (merged == Some(Decision::Activate))
    })
}

fn force_flags_agree(model: &RtcModel, step: &RtcStep) -> bool {
    every_query(model, step, |view, at, id| {
        let mine = own(step, at, id).is_some();
        let (fa, fd, act) = (
            view.is_force_activated(id),
            view.is_force_deactivated(id),
            view.is_activated(id),
        );
        fa == (mine && step.core.force_activated(id) == Some(true))
            && fd == (mine && step.core.force_deactivated(id) == Some(true))
            && (!fa || act)
            && (!fd || !act)
    })
}

/// Each interface's answers in one pass list its own live scenes, in identifier order, each
/// answered as the core says (as the per-scene queries are checked above).
fn answers_are_the_queries(model: &RtcModel, step: &RtcStep) -> bool {
    (0..model.bindings().len()).all(|at| {
        model.view(step, at).is_some_and(|view| {
            let expected = model.ids().iter().filter_map(|&id| {
                let scene = own(step, at, id)?;
                let answers = rtc::Answers {
                    activated: step.core.merged_decision(id) == Some(Decision::Activate),
                    force_activated: step.core.force_activated(id) == Some(true),
                    force_deactivated: step.core.force_deactivated(id) == Some(true),
                    rtc_enabled: !auto_mode(&step.core, scene),
                };
                Some((id, answers))
            });
            view.answers().eq(expected)
        })
    })
}

fn queries_say_so(model: &RtcModel, step: &RtcStep) -> bool {
    every_query(model, step, |view, at, id| {
        let scene = own(step, at, id);
        let terminated = match (scene, step.core.retirement(id)) {
            (Some(_), _) => Some(false),
            (None, Some(retirement)) if step.registrar(id).map(usize::from) == Some(at) => {
                Some(matches!(
                    retirement.reason,
                    RetireReason::Succeeded | RetireReason::Failed
                ))
            }
            _ => None,
        };
        view.is_registered(id) == scene.is_some()
            && view.is_rtc_enabled(id) == scene.map(|s| !auto_mode(&step.core, s))
            && view.is_terminated(id) == terminated
    })
}

fn auto_mode_is_policy(model: &RtcModel, step: &RtcStep) -> bool {
    let array = step.rtc.auto_mode_status_array(&step.core, STAMP);
    array.statuses.len() == model.bindings().len()
        && model.bindings().iter().enumerate().all(|(at, binding)| {
            let on = modules_of(binding)
                .into_iter()
                .all(|module| step.core.policy(module) == Some(Policy::Optional));
            let status = rtc::AutoModeStatus {
                module: binding.module_type.into(),
                is_auto_mode: on,
            };
            model
                .view(step, at)
                .is_some_and(|v| v.auto_mode_status() == status)
                && array.statuses.get(at) == Some(&status)
        })
}

/// Every scene the model saw an interface register, live or retired, belongs to one of the
/// modules that interface is bound to.
fn scenes_in_bound_modules(model: &RtcModel, step: &RtcStep) -> bool {
    model.ids().iter().all(|&id| {
        let module = step
            .core
            .scene(id)
            .map(Scene::module)
            .or_else(|| step.core.retirement(id).map(|r| r.module));
        match (module, step.registrar(id)) {
            (Some(module), Some(at)) => model
                .binding(usize::from(at))
                .is_some_and(|binding| modules_of(binding).contains(&module)),
            _ => true,
        }
    })
}

/// The adapter's memory is bounded as the core's is, `Rtc::route_count`'s promise, and the
/// count covers at least every identifier routed.
fn routes_bounded(model: &RtcModel, step: &RtcStep) -> bool {
    let limits = step.core.limits();
    // Every identifier the adapter answers an owner for has a route.
    let routed = model
        .ids()
        .iter()
        .filter(|id| step.rtc.owner(&step.core, **id).is_some())
        .count();
    let count = step.rtc.route_count();
    routed <= count && count <= limits.max_scenes + limits.retired_capacity + 1
}

/// Before any call, every bound module's policy is optional: the model builds its
/// configuration with `Rtc::policies(false)`, upstream's `enable_rtc = false` (auto mode on).
fn starts_in_auto_mode(model: &RtcModel, step: &RtcStep) -> bool {
    step.last.is_some()
        || model
            .bindings()
            .iter()
            .flat_map(modules_of)
            .all(|module| step.core.policy(module) == Some(Policy::Optional))
}

/// `check(view, scene, activated)` for every live scene through the interface that owns it.
fn every_scene(
    model: &RtcModel,
    step: &RtcStep,
    check: fn(&RtcStep, &Scene, bool, bool, bool) -> bool,
) -> bool {
    live(step).all(|(id, scene, registrar)| {
        registrar
            .and_then(|at| model.view(step, at))
            .is_some_and(|view| {
                check(
                    step,
                    scene,
                    view.is_activated(id),
                    view.is_force_activated(id),
                    view.is_force_deactivated(id),
                )
            })
    })
}

fn auto_mode_follows_safe(model: &RtcModel, step: &RtcStep) -> bool {
    every_scene(model, step, |step, scene, activated, _, _| {
        let applies = step.core.policy(scene.module()) == Some(Policy::Optional)
            && scene.operator_decision() == OperatorDecision::Undecided
            && !scene.is_requested();
        !applies || activated == (scene.module_decision() == Decision::Activate)
    })
}

fn requested_held_back(model: &RtcModel, step: &RtcStep) -> bool {
    every_scene(model, step, |_, scene, activated, _, _| {
        !(scene.is_requested()
            && scene.operator_decision() == OperatorDecision::Undecided
            && activated)
    })
}

fn activate_command(model: &RtcModel, step: &RtcStep) -> bool {
    every_scene(model, step, |_, scene, activated, forced, _| {
        let applies =
            scene.operator_decision() == OperatorDecision::Activate && scene.is_cancellable();
        let unsafe_or_asked =
            scene.module_decision() == Decision::Deactivate || scene.is_requested();
        !applies || (activated && forced == unsafe_or_asked)
    })
}

fn deactivate_command(model: &RtcModel, step: &RtcStep) -> bool {
    every_scene(model, step, |_, scene, activated, _, forced| {
        let applies = scene.operator_decision() == OperatorDecision::Deactivate
            && scene.module_decision() == Decision::Activate;
        !applies || (!activated && forced == (scene.phase() == Phase::Running))
    })
}

fn invariants_hold(_: &RtcModel, step: &RtcStep) -> bool {
    step.core.check_invariants().is_ok()
}

/// A reachability property of answers: its name, the kind of call, and the answers it wants.
type Wanted = (&'static str, Kind, fn(Answer) -> bool);

/// The interesting answers of each kind of call.
const ANSWERS: [Wanted; 31] = {
    use Answer::{Accepted as A, Cleared, Refused as R};
    use Rule as U;
    [
        ("COOP-REG-NEW.1: an update registers a scene", Kind::Update, |a| a == A(Some(U::RegisterNew), None)),
        ("COOP-DEV-REGISTER-PHASE.1: an update registers a scene first reported running, in one step", Kind::Update, |a| a == A(Some(U::RegisterNew), Some(U::OwnerUpdate))),
        ("COOP-DEV-REGISTER-PHASE.1: an update registers and fails a scene first reported failed", Kind::Update, |a| a == A(Some(U::RegisterNew), Some(U::OwnerFinish))),
        ("COOP-OWN-UPDATE.1: an update updates a live scene", Kind::Update, |a| a == A(Some(U::OwnerUpdate), None)),
        ("COOP-DEV-TERMINAL.1: an update finishes a scene", Kind::Update, |a| a == A(Some(U::OwnerFinish), None)),
        ("COOP-DEV-CONSTANTS.1: an update with an undefined state is refused", Kind::Update, |a| a == R(Refusal::Field)),
        ("COOP-DEV-ID-REUSE.1: an update of another interface's scene is refused", Kind::Update, |a| a == R(Refusal::ForeignScene)),
        ("COOP-DEV-REGISTER-PHASE.1: a new scene reported aborting or succeeded is refused", Kind::Update, |a| matches!(a, R(Refusal::InitialPhase(_)))),
        ("COOP-DEV-SILENT-DROP.1: an update the lifecycle forbids is refused", Kind::Update, |a| a == R(Refusal::Core(U::OwnerTransition))),
        ("COOP-DEV-ID-REUSE.1: an update of a retired identifier is refused", Kind::Update, |a| a == R(Refusal::Core(U::RegisterRetired))),
        ("COOP-REG-FULL.1: an update beyond the scene limit is refused", Kind::Update, |a| a == R(Refusal::Core(U::RegisterFull))),
        ("COOP-OWN-REMOVE.1: a removal retires a scene", Kind::Remove, |a| a == A(Some(U::OwnerRemove), None)),
        ("COOP-DEV-ID-REUSE.1: a removal of another interface's scene is refused", Kind::Remove, |a| a == R(Refusal::ForeignScene)),
        ("COOP-OWN-UNKNOWN.1: a removal of an unknown identifier is refused", Kind::Remove, |a| a == R(Refusal::Core(U::OwnerUnknown))),
        ("COOP-OWN-RETIRED.1: a removal of a retired identifier is refused", Kind::Remove, |a| a == R(Refusal::Core(U::OwnerRetired))),
        ("COOP-OWN-REMOVE.1: a clear with no live scene answers none", Kind::Clear, |a| a == Cleared(0)),
        ("COOP-OWN-REMOVE.1: a clear retires two scenes", Kind::Clear, |a| a == Cleared(2)),
        ("COOP-CMD-APPLY.1: an interface's commands apply", Kind::Commands, |a| a == A(Some(U::CommandApply), None)),
        ("COOP-DEV-ID-REUSE.1: an interface's command for another interface's scene is refused", Kind::Commands, |a| a == R(Refusal::ForeignScene)),
        ("COOP-DEV-STORED-COMMANDS.1: a command for an unknown identifier is refused", Kind::Commands, |a| a == R(Refusal::Core(U::CommandUnknown))),
        ("COOP-DEV-ROUTING.1: the external API's commands apply", Kind::ExternalCommands, |a| a == A(Some(U::CommandApply), None)),
        ("COOP-DEV-DUPLICATE.1: a request naming a scene twice is refused", Kind::ExternalCommands, |a| a == R(Refusal::Core(U::CommandDuplicate))),
        ("COOP-CMD-RETIRED.1: a command for a retired identifier is refused", Kind::ExternalCommands, |a| a == R(Refusal::Core(U::CommandRetired))),
        ("COOP-CMD-NOT-CANCELLABLE.1: a command for an aborting scene is refused", Kind::ExternalCommands, |a| a == R(Refusal::Core(U::CommandNotCancellable))),
        ("COOP-DEV-CONSTANTS.1: a command with an undefined constant is refused", Kind::ExternalCommands, |a| a == R(Refusal::Field)),
        ("COOP-BATCH-LIMIT.1: a request over the batch limit is refused", Kind::ExternalCommands, |a| a == R(Refusal::Core(U::BatchLimit))),
        ("COOP-DEV-AUTO-MODE-KEY.1: an interface's auto-mode switch sets its module's policy", Kind::AutoMode, |a| a == A(Some(U::PolicySet), None)),
        ("COOP-DEV-ROUTING.1: the external auto-mode switch sets the module type's policies", Kind::AutoModeWithModule, |a| a == A(Some(U::PolicySet), None)),
        ("COOP-DEV-ROUTING.1: an auto-mode switch for a module type no interface reports is refused", Kind::AutoModeWithModule, |a| a == R(Refusal::NoInterface)),
        ("COOP-TIME-AGE.1: a tick ages the scenes", Kind::Tick, |a| a == A(Some(U::TimeAge), None)),
        ("COOP-DEV-EXPIRY.1: a tick expires a scene and says so", Kind::Tick, |a| a == A(Some(U::TimeExpire), None)),
    ]
};

/// The interesting answers of calls that only an interface bound to several sequences, or the
/// AD API's policy of one of its modules, can give.
const SEQUENCE_ANSWERS: [Wanted; 4] = {
    use Answer::{Accepted as A, Refused as R};
    [
        ("COOP-DEV-SEQUENCE.1: an update stating a sequence its interface is not bound to is refused", Kind::Update, |a| a == R(Refusal::UnboundSequence)),
        ("COOP-DEV-SEQUENCE.1: a new scene reported without its sequence through an interface bound to two is refused", Kind::Update, |a| a == R(Refusal::SequenceUnstated)),
        ("COOP-OWN-MODULE.1, COOP-DEV-SEQUENCE.1: an update stating another sequence than its scene's is refused", Kind::Update, |a| a == R(Refusal::Core(Rule::OwnerModule))),
        ("COOP-DEV-SEQUENCE.1: the AD API sets one sequence's policy", Kind::SetPolicy, |a| a == A(Some(Rule::PolicySet), None)),
    ]
};

/// Whether the step's last call answered as `wanted` does.
fn answered_as(step: &RtcStep, wanted: Option<&Wanted>) -> bool {
    if !step.shows_last() {
        return false;
    }
    match (step.last, wanted) {
        (Some(Outcome { kind, answer }), Some((_, wanted, matches))) => {
            kind == *wanted && matches(answer)
        }
        _ => false,
    }
}

fn answered<const I: usize>(_: &RtcModel, step: &RtcStep) -> bool {
    answered_as(step, ANSWERS.get(I))
}

fn answered_in_sequence<const I: usize>(_: &RtcModel, step: &RtcStep) -> bool {
    answered_as(step, SEQUENCE_ANSWERS.get(I))
}

/// The answer only an adapter with a quota gives.
const QUOTA_ANSWER: Wanted = (
    "COOP-DEV-QUOTA.1: a new scene through an interface at its quota is refused",
    Kind::Update,
    |a| a == Answer::Refused(Refusal::Quota),
);

fn answered_for_quota(_: &RtcModel, step: &RtcStep) -> bool {
    answered_as(step, Some(&QUOTA_ANSWER))
}

/// Witnesses, on steps that changed something (a stalled step's states are its
/// predecessor's). The operator holds back a scene that auto mode and its module would run.
fn operator_stands_under_auto_mode(_: &RtcModel, step: &RtcStep) -> bool {
    !step.stalled
        && step.core.scenes().any(|(_, scene)| {
            scene.operator_decision() == OperatorDecision::Deactivate
                && scene.module_decision() == Decision::Activate
                && step.core.policy(scene.module()) == Some(Policy::Optional)
        })
}

fn force_activated(model: &RtcModel, step: &RtcStep) -> bool {
    !step.stalled && !every_scene(model, step, |_, _, _, forced, _| !forced)
}

fn force_deactivated(model: &RtcModel, step: &RtcStep) -> bool {
    !step.stalled && !every_scene(model, step, |_, _, _, _, forced| !forced)
}

/// One interface has live scenes of two modules, under different policies.
fn two_policies_on_one_interface(_: &RtcModel, step: &RtcStep) -> bool {
    !step.stalled
        && live(step).any(|(_, a, at)| {
            live(step).any(|(_, b, bt)| {
                at.is_some()
                    && at == bt
                    && a.module() != b.module()
                    && step.core.policy(a.module()) != step.core.policy(b.module())
            })
        })
}

fn two_interfaces_live(_: &RtcModel, step: &RtcStep) -> bool {
    let mut owners = live(step).filter_map(|(_, _, registrar)| registrar);
    owners
        .next()
        .is_some_and(|first| owners.any(|other| other != first))
}

macro_rules! per_index {
    ($f:ident: $($i:literal)*) => { [$($f::<$i> as Condition),*] };
}

/// The step properties: each holds while no step has set its flag.
fn steps() -> Vec<(&'static str, Condition)> {
    vec![
        ("COOP-DEV-SILENT-DROP.1: a refused call changes nothing (the state after it equals the state before)", unbroken::<{ Broken::REFUSAL_CHANGED.0 }>),
        ("COOP-DEV-ROUTING.1, COOP-DEV-BATCH.1: every command and auto-mode request is answered, success exactly when it applied", unbroken::<{ Broken::UNANSWERED.0 }>),
        ("COOP-DEV-SILENT-DROP.1, COOP-DEV-REGISTER-PHASE.1, COOP-DEV-SEQUENCE.1: an accepted status update or removal leaves the scene as reported, in the module its sequence names", unbroken::<{ Broken::NOT_AS_REPORTED.0 }>),
        ("COOP-DEV-ID-REUSE.1: an interface's calls change only scenes registered through it", unbroken::<{ Broken::FOREIGN_TOUCHED.0 }>),
        ("COOP-DEV-STORED-COMMANDS.1, COOP-CMD-APPLY.1: only an applied command changes an operator decision, and only its scene's", unbroken::<{ Broken::OPERATOR_BY_OTHER.0 }>),
        ("COOP-DEV-STORED-COMMANDS.1, COOP-DEV-NONE.1: a new scene starts with no operator decision", unbroken::<{ Broken::NEW_SCENE_DECIDED.0 }>),
        ("COOP-CMD-APPLY.1, COOP-DEV-BATCH.1: an applied command takes effect on its scene", unbroken::<{ Broken::COMMAND_MISSED.0 }>),
        ("COOP-DEV-POLICY-CLOBBER.1: an auto-mode switch keeps every scene and operator decision", unbroken::<{ Broken::AUTO_MODE_CLOBBERED.0 }>),
        ("COOP-DEV-AUTO-MODE-KEY.1, COOP-DEV-ROUTING.1: an auto-mode switch reaches every interface of its modules and no other", unbroken::<{ Broken::AUTO_MODE_MISSED.0 }>),
        ("COOP-DEV-ID-REUSE.1, COOP-REG-RETIRED.1: a retired identifier never becomes live again", unbroken::<{ Broken::REVIVED.0 }>),
        ("COOP-DEV-EXPIRY.1: a tick reports exactly the scenes that expired", unbroken::<{ Broken::EXPIRY_UNREPORTED.0 }>),
        ("COOP-OWN-REMOVE.1: a clear retires exactly its interface's live scenes and answers them", unbroken::<{ Broken::CLEAR_WRONG.0 }>),
        ("COOP-DEV-CONSTANTS.1: a call is refused for an undefined constant exactly when it carries one, naming the first such field and its value", unbroken::<{ Broken::FIELD_MISNAMED.0 }>),
        ("COOP-DEV-SEQUENCE.1, COOP-OWN-MODULE.1: an update is refused for its sequence exactly when it is unbound, unstated for a new scene of several, or not its live scene's; no other call meets the module rule", unbroken::<{ Broken::SEQUENCE_WRONG.0 }>),
        ("COOP-DEV-QUOTA.1: a new scene registers only through an interface below its quota, and only a new scene through an interface at its quota is refused for it", unbroken::<{ Broken::QUOTA_WRONG.0 }>),
    ]
}

/// The state properties, by name. Each reads the core and the adapter only, so a stalled step
/// (the same states as its predecessor, already checked) needs no check again.
const STATES: [(&str, Condition); 16] = [
        ("COOP-DEV-ID-REUSE.1: each remembered identifier is routed to the interface that registered it", routed_to_registrar),
        ("COOP-DEV-SEQUENCE.1: every scene an interface registered belongs to a module it is bound to", scenes_in_bound_modules),
        ("COOP-DEV-ID-REUSE.1: the adapter's route count covers every routed identifier and no more than the core can remember plus one", routes_bounded),
        ("COOP-OUT-STATUS.1, COOP-DEV-NONE.1: each interface's status array lists exactly its live scenes, with the core's values", statuses_are_the_cores),
        ("COOP-DEV-ORDER.1, COOP-DEV-ROUTING.1: the external status array lists every interface's live scenes, nearest start first", external_statuses),
        ("COOP-MERGE.1: is_activated is the core's merged decision, and false for another interface's scene", activated_is_merged),
        ("COOP-DEV-FORCE.1: the force flags are the core's and agree with is_activated", force_flags_agree),
        ("COOP-MERGE.1, COOP-DEV-FORCE.1: an interface's answers in one pass are its live scenes' queries, in identifier order", answers_are_the_queries),
        ("COOP-DEV-UNKNOWN-QUERY.1, COOP-DEV-TERMINAL.1 (upstream test steps 1, 3, 6, 10): is_registered, is_rtc_enabled and is_terminated answer for the interface's own scenes only", queries_say_so),
        ("COOP-DEV-AUTO-MODE-KEY.1: every interface's auto-mode status is its module's policy", auto_mode_is_policy),
        ("COOP-DEV-AUTO-MODE-KEY.1 (docs/rtc.md): with upstream's enable_rtc = false, as the model is configured, every interface starts in auto mode", starts_in_auto_mode),
        ("COOP-MERGE.1 (upstream test steps 2, 4): under auto mode an undecided scene not requested is activated exactly when safe", auto_mode_follows_safe),
        ("COOP-REQUESTED.1 (upstream test step 11): a requested scene with no operator decision is not activated", requested_held_back),
        ("COOP-FORCE-ACTIVATED.1 (upstream test steps 5, 12): a cancellable scene the operator activated is activated, forced exactly when unsafe or requested", activate_command),
        ("COOP-FORCE-DEACTIVATED.1 (upstream test steps 8, 9): a safe scene the operator deactivated is not activated, forced exactly while running", deactivate_command),
        ("COOP-INV-*: State::check_invariants holds (spec §8)", invariants_hold),
];

fn state<const I: usize>(model: &RtcModel, step: &RtcStep) -> bool {
    step.stalled
        || STATES
            .get(I)
            .is_some_and(|(_, condition)| condition(model, step))
}

/// Every property: the safety properties, then the reachability of each kind of call's
/// interesting answers, then the scenario witnesses; the answers and the witness that only an
/// interface bound to several sequences can give among them. For the traceability matrix and
/// the name checks; a model checks [`properties_for`] its bindings.
#[must_use]
pub fn properties() -> Vec<Property<RtcModel>> {
    properties_for(true, true)
}

/// The properties of a model with (`several_sequences`) or without an interface bound to
/// several sequences, and with or without a `quota`: without one, the reachability of the
/// answers only such an interface or a quota gives is left out, since no call could give them.
#[must_use]
pub fn properties_for(several_sequences: bool, quota: bool) -> Vec<Property<RtcModel>> {
    let answers = per_index!(answered: 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30);
    let in_sequence = per_index!(answered_in_sequence: 0 1 2 3);
    let states = per_index!(state: 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15);
    let mut properties: Vec<Property<RtcModel>> = steps()
        .into_iter()
        .map(|(name, condition)| Property::always(name, condition))
        .collect();
    properties.extend(
        STATES
            .iter()
            .zip(states)
            .map(|((name, _), condition)| Property::always(name, condition)),
    );
    properties.extend(
        ANSWERS
            .iter()
            .zip(answers)
            .map(|((name, _, _), condition)| Property::sometimes(name, condition)),
    );
    if several_sequences {
        properties.extend(
            SEQUENCE_ANSWERS
                .iter()
                .zip(in_sequence)
                .map(|((name, _, _), condition)| Property::sometimes(name, condition)),
        );
    }
    properties.extend([
        Property::sometimes(
            "witness: an operator's deactivate stands under auto mode",
            operator_stands_under_auto_mode,
        ),
        Property::sometimes("witness: a scene is force-activated", force_activated),
        Property::sometimes("witness: a scene is force-deactivated", force_deactivated),
        Property::sometimes(
            "witness: two interfaces have live scenes at once",
            two_interfaces_live,
        ),
    ]);
    if quota {
        properties.push(Property::sometimes(QUOTA_ANSWER.0, answered_for_quota));
    }
    if several_sequences {
        properties.push(Property::sometimes(
            "witness: one interface has live scenes of two modules under different policies",
            two_policies_on_one_interface,
        ));
    }
    properties
}
