//! What a call said, and what the step from one state to the next did, as history for the step
//! properties. It compares states and reads the call and its answer; it decides nothing.

use cooperation::{
    Module, OperatorDecision, Phase, RetireReason, Rule, SceneId, Sequence, State, Transition,
};
use cooperation_adapters::rtc::{self, CooperateResponse, Reply, RtcError, Transitions};

use super::call::{Call, Order, UNDEFINED_COMMAND, UNDEFINED_MODULE, UNDEFINED_STATE};
use super::step::{Answer, Broken, Interface, Kind, Outcome, Refusal, RtcStep};
use super::RtcModel;

/// What a call answered, in full, for the step properties.
#[derive(Clone, Debug, PartialEq)]
pub struct Said {
    /// The kind of call and its answer.
    pub outcome: Outcome,
    /// The identifiers it listed: a clear's answer, or the scenes its transitions retired.
    pub ids: Vec<SceneId>,
    /// A command request's wire responses.
    pub responses: Vec<CooperateResponse>,
    /// An auto-mode request's wire `success`.
    pub success: Option<bool>,
    /// The field and value a refusal for an undefined constant names.
    pub field: Option<(String, u8)>,
}

impl Said {
    /// A call of this kind refused with `error`.
    #[must_use]
    pub fn refused(kind: Kind, error: &RtcError) -> Self {
        let mut said = Self::of(kind, Answer::Refused(Refusal::of(error)));
        if let RtcError::Field(error) = error {
            said.field = Some((error.field.to_string(), error.value));
        }
        said
    }

    /// A call of this kind that answered `answer`, listing nothing.
    #[must_use]
    pub const fn of(kind: Kind, answer: Answer) -> Self {
        Self {
            outcome: Outcome { kind, answer },
            ids: Vec::new(),
            responses: Vec::new(),
            success: None,
            field: None,
        }
    }

    /// A call answering these transitions, or its refusal.
    #[must_use]
    pub fn transitions<T: Into<Transitions>>(kind: Kind, result: Result<T, RtcError>) -> Self {
        match result {
            Ok(transitions) => {
                let transitions: Transitions = transitions.into();
                let rule = |n: usize| transitions.get(n).map(|t| t.rule);
                let mut said = Self::of(kind, Answer::Accepted(rule(0), rule(1)));
                said.ids = transitions.iter().flat_map(|t| t.retired.clone()).collect();
                said
            }
            Err(error) => Self::refused(kind, &error),
        }
    }

    /// A command service's reply.
    #[must_use]
    pub fn commands(kind: Kind, reply: Reply<rtc::CooperateCommandsResponse>) -> Self {
        let mut said = Self::transitions(kind, reply.result);
        said.responses = reply.response.responses;
        said
    }

    /// An auto-mode service's reply.
    #[must_use]
    pub fn auto_mode(kind: Kind, result: Result<Transition, RtcError>, success: bool) -> Self {
        let mut said = Self::transitions(kind, result);
        said.success = Some(success);
        said
    }

    /// Whether the call was accepted.
    #[must_use]
    pub const fn accepted(&self) -> bool {
        !matches!(self.outcome.answer, Answer::Refused(_))
    }
}

/// The decision an order carries, if its command is defined.
fn decision(order: &Order) -> Option<OperatorDecision> {
    match order.command {
        rtc::Command::ACTIVATE => Some(OperatorDecision::Activate),
        rtc::Command::DEACTIVATE => Some(OperatorDecision::Deactivate),
        _ => None,
    }
}

/// Whether `id` is no longer live and, if the core still remembers it, retired for `reason` (a
/// call retiring several scenes may make the retired set forget the first of them).
fn gone_as(core: &State, id: SceneId, reason: RetireReason) -> bool {
    core.scene(id).is_none() && core.retirement(id).map_or(true, |r| r.reason == reason)
}

/// Whether the core remembers `id` (live or retired).
fn remembered(core: &State, id: SceneId) -> bool {
    core.scene(id).is_some() || core.retirement(id).is_some()
}

/// The first field of `call` with an undefined constant, and its value, as the adapter's
/// documentation says it names it (`[COOP-DEV-CONSTANTS.1]`): an update's status message's
/// `state.type`, read before the report reaches the interface; a command
/// request's `commands[i].module.type`, else `commands[i].command.type`, of the first command
/// with one; an auto-mode request's `module.type`.
fn undefined_field(call: &Call) -> Option<(String, u8)> {
    match call {
        Call::Update { state, .. } => {
            (*state == UNDEFINED_STATE).then(|| ("state.type".to_owned(), *state))
        }
        Call::Commands { orders, .. } => orders.iter().enumerate().find_map(|(i, order)| {
            if order.module == UNDEFINED_MODULE {
                Some((format!("commands[{i}].module.type"), order.module))
            } else if order.command == UNDEFINED_COMMAND {
                Some((format!("commands[{i}].command.type"), order.command))
            } else {
                None
            }
        }),
        Call::AutoModeWithModule { module, .. } => {
            (*module == UNDEFINED_MODULE).then(|| ("module.type".to_owned(), *module))
        }
        Call::Remove { .. }
        | Call::Clear { .. }
        | Call::AutoMode { .. }
        | Call::Tick
        | Call::SetPolicy { .. } => None,
    }
}

/// The module an accepted status update leaves its scene in, as `docs/rtc.md` says: a live
/// scene's own; else the module of the sequence stated; else the interface's one module.
fn reported_module(
    model: &RtcModel,
    old: &State,
    interface: usize,
    id: SceneId,
    sequence: Option<Sequence>,
) -> Option<Module> {
    if let Some(scene) = old.scene(id) {
        return Some(scene.module());
    }
    let binding = model.binding(interface)?;
    let sequence = match sequence {
        Some(sequence) => sequence,
        None if binding.sequences.len() == 1 => *binding.sequences.first()?,
        None => return None,
    };
    Some(Module::with_sequence(binding.behavior, sequence))
}

/// Which sequence refusal `docs/rtc.md` says a call gets, if any: a status update with a
/// defined state stating a sequence its interface is not bound to; stating none for a scene
/// that is not live through an interface bound to several; stating another than its own live
/// scene's (the core's module rule).
fn sequence_refusal(model: &RtcModel, from: &RtcStep, call: &Call) -> Option<Refusal> {
    let Call::Update {
        interface,
        id,
        sequence,
        state,
        ..
    } = call
    else {
        return None;
    };
    rtc::Lifecycle::new(*state).phase().ok()?;
    let binding = model.binding(*interface)?;
    let scene = from.core.scene(*id);
    match sequence {
        Some(stated) if !binding.sequences.contains(stated) => Some(Refusal::UnboundSequence),
        Some(stated) => {
            let own = scene.filter(|_| from.owner(*id).map(usize::from) == Some(*interface));
            own.is_some_and(|scene| scene.module().sequence != *stated)
                .then_some(Refusal::Core(Rule::OwnerModule))
        }
        None => {
            (scene.is_none() && binding.sequences.len() > 1).then_some(Refusal::SequenceUnstated)
        }
    }
}

/// Whether a step kept the interfaces' quota as `[COOP-DEV-QUOTA.1]` says: a scene that was
/// not live registers only through an interface holding fewer live scenes than the quota (as
/// the model counts them, by the interface whose update registered each), and a refusal for the
/// quota is given only to such a scene through an interface holding the quota.
fn quota_kept(model: &RtcModel, from: &RtcStep, call: &Call, said: &Said, to: &RtcStep) -> bool {
    let Call::Update { interface, id, .. } = call else {
        return said.outcome.answer != Answer::Refused(Refusal::Quota);
    };
    let held = from
        .core
        .scenes()
        .filter(|(live, _)| from.registrar(*live).map(usize::from) == Some(*interface))
        .count();
    let full = model.bounds().quota.is_some_and(|quota| held >= quota);
    let new = from.core.scene(*id).is_none();
    let registered = new && to.core.scene(*id).is_some();
    match said.outcome.answer {
        Answer::Refused(Refusal::Quota) => new && full,
        _ => !(registered && full),
    }
}

/// The flags the step from `from` by `call` (answering `said`) to `to` breaks, and the
/// registrars after it.
pub(super) fn observe(
    model: &RtcModel,
    from: &RtcStep,
    call: &Call,
    said: &Said,
    to: &mut RtcStep,
) {
    let (old, new) = (&*from.core, &*to.core);
    let mut flags = to.broken;
    let broken = &mut flags;
    let mut registrar = to.registrar;
    let ids = model.ids();
    let accepted = said.accepted();
    let unchanged = old == new && from.rtc == to.rtc;
    broken.set(Broken::REFUSAL_CHANGED, !accepted && !unchanged);
    broken.set(Broken::FIELD_MISNAMED, said.field != undefined_field(call));
    let for_sequence = match said.outcome.answer {
        Answer::Refused(
            refusal @ (Refusal::UnboundSequence
            | Refusal::SequenceUnstated
            | Refusal::Core(Rule::OwnerModule)),
        ) => Some(refusal),
        Answer::Refused(Refusal::InitialPhase(Rule::OwnerModule)) => {
            Some(Refusal::Core(Rule::OwnerModule))
        }
        _ => None,
    };
    broken.set(
        Broken::SEQUENCE_WRONG,
        for_sequence != sequence_refusal(model, from, call),
    );
    broken.set(
        Broken::QUOTA_WRONG,
        !quota_kept(model, from, call, said, to),
    );

    // Registrars: who registered each identifier the core remembers now.
    for &id in ids {
        let slot = crate::model::ids::index(id).and_then(|i| registrar.get_mut(i));
        if let Some(slot) = slot {
            if !remembered(new, id) {
                *slot = None;
            } else if !remembered(old, id) {
                *slot = match call {
                    Call::Update { interface, .. } => Interface::try_from(*interface).ok(),
                    _ => None,
                };
            }
        }
        let revived = old.retirement(id).is_some() && new.scene(id).is_some();
        broken.set(Broken::REVIVED, revived);
        let fresh = old.scene(id).is_none() && new.scene(id).is_some();
        let decided = new
            .scene(id)
            .is_some_and(|s| s.operator_decision() != OperatorDecision::Undecided);
        broken.set(Broken::NEW_SCENE_DECIDED, fresh && decided);
    }

    // Operator decisions change only by an applied batch naming the scene.
    let orders: &[Order] = match call {
        Call::Commands { orders, .. } if accepted => orders,
        _ => &[],
    };
    for &id in ids {
        if let (Some(o), Some(n)) = (old.scene(id), new.scene(id)) {
            let named = orders.iter().any(|order| order.id == id);
            let moved = o.operator_decision() != n.operator_decision();
            broken.set(Broken::OPERATOR_BY_OTHER, moved && !named);
        }
    }

    // An interface's call touches only scenes registered through it. (A retirement the core
    // forgets to make room is not a touch: the retired set forgets oldest first, whoever
    // retired the newest.)
    let touched = |id: &SceneId| {
        let retired = new.retirement(*id).is_some() && old.retirement(*id) != new.retirement(*id);
        old.scene(*id) != new.scene(*id) || retired
    };
    let owner = |id: SceneId| from.owner(id).or_else(|| to.owner(id));
    if let (Some(i), false) = (call.interface(), matches!(call, Call::AutoMode { .. })) {
        let foreign = ids
            .iter()
            .filter(|id| touched(id))
            .any(|&id| owner(id).map(usize::from) != Some(i));
        broken.set(Broken::FOREIGN_TOUCHED, foreign);
    }

    match call {
        Call::Update {
            interface,
            id,
            sequence,
            safe,
            state,
            requested,
        } if accepted => {
            let phase = rtc::Lifecycle::new(*state).phase().ok();
            let module = reported_module(model, old, *interface, *id, *sequence);
            let as_reported = match phase {
                Some(Phase::Succeeded | Phase::Failed) => {
                    let reason = if phase == Some(Phase::Succeeded) {
                        RetireReason::Succeeded
                    } else {
                        RetireReason::Failed
                    };
                    gone_as(new, *id, reason)
                        && module.is_some()
                        && new
                            .retirement(*id)
                            .map_or(true, |r| Some(r.module) == module)
                }
                Some(phase) => new.scene(*id).is_some_and(|scene| {
                    Some(scene.module()) == module
                        && scene.phase() == phase
                        && (scene.module_decision() == cooperation::Decision::Activate) == *safe
                        && scene.is_requested() == *requested
                        && scene.age_ms() == 0
                }),
                None => false,
            };
            let routed = to.owner(*id).map(usize::from) == Some(*interface);
            let answered = matches!(said.outcome.answer, Answer::Accepted(Some(_), _));
            broken.set(
                Broken::NOT_AS_REPORTED,
                !(as_reported && routed && answered),
            );
        }
        Call::Remove { id, .. } if accepted => {
            let removed = gone_as(new, *id, RetireReason::Removed);
            broken.set(Broken::NOT_AS_REPORTED, !removed || said.ids != [*id]);
        }
        Call::Clear { interface } => {
            let own: Vec<SceneId> = ids
                .iter()
                .copied()
                .filter(|&id| old.scene(id).is_some())
                .filter(|&id| from.owner(id).map(usize::from) == Some(*interface))
                .collect();
            let retired = own
                .iter()
                .all(|&id| gone_as(new, id, RetireReason::Removed));
            broken.set(
                Broken::CLEAR_WRONG,
                accepted && (said.ids != own || !retired),
            );
        }
        Call::Commands { orders, .. } => {
            let answered = said.responses.len() == orders.len()
                && said.responses.iter().zip(orders).all(|(response, order)| {
                    SceneId::from(response.uuid) == order.id
                        && response.module.r#type == order.module
                        && response.success == accepted
                });
            broken.set(Broken::UNANSWERED, !answered);
            let missed = accepted
                && orders.iter().any(|order| {
                    new.scene(order.id)
                        .map(cooperation::Scene::operator_decision)
                        != decision(order)
                });
            broken.set(Broken::COMMAND_MISSED, missed);
        }
        Call::SetPolicy { .. } => {
            let scenes_kept = old.scenes().eq(new.scenes())
                && old.retired_by_id().eq(new.retired_by_id())
                && from.rtc == to.rtc;
            broken.set(Broken::AUTO_MODE_CLOBBERED, !scenes_kept);
        }
        Call::AutoMode { .. } | Call::AutoModeWithModule { .. } => {
            broken.set(Broken::UNANSWERED, said.success != Some(accepted));
            let scenes_kept = old.scenes().eq(new.scenes())
                && old.retired_by_id().eq(new.retired_by_id())
                && from.rtc == to.rtc;
            broken.set(Broken::AUTO_MODE_CLOBBERED, !scenes_kept);
            if accepted {
                broken.set(
                    Broken::AUTO_MODE_MISSED,
                    !model.switched_as_asked(from, call, to),
                );
            }
        }
        Call::Tick if accepted => {
            let expired: Vec<SceneId> = ids
                .iter()
                .copied()
                .filter(|&id| old.scene(id).is_some())
                .filter(|&id| new.scene(id).is_none())
                .collect();
            let as_expired = expired
                .iter()
                .all(|&id| gone_as(new, id, RetireReason::Expired));
            broken.set(
                Broken::EXPIRY_UNREPORTED,
                said.ids != expired || !as_expired,
            );
        }
        _ => {}
    }
    to.broken = flags;
    to.registrar = registrar;
}
