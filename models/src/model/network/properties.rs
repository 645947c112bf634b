//! The network model's properties, named by the spec's tags: step properties recorded as
//! sticky flags when a message is sent or delivered, and conditions on each state.

use std::sync::OnceLock;

use cooperation::{OperatorDecision, Phase, Rule, Scene, State};
use stateright::Property;

use super::{CommandMessage, NetStep, NetworkModel, Seen, StatusMessage, Views};
use crate::model::ids::index;

const SPILLED: u8 = 1;
const STALE_TOUCHED_NEW: u8 = 1 << 1;
const SECOND_EFFECT: u8 = 1 << 2;
pub(super) const REJECTION_CHANGED: u8 = 1 << 3;
const MISREPORTED: u8 = 1 << 4;
const NOT_CANCELLABLE_CHANGED: u8 = 1 << 5;
const NOT_AT_ONCE: u8 = 1 << 6;

const STATUS_RECEIVED: &str = "COOP-OUT-STATUS.1 (network): a status an operator receives is what the library reported for that scene when it was sent";
const TWO_OPERATORS: &str = "witness: two operators have commands in flight at once";
const LATE_NOT_CANCELLABLE: &str =
    "witness: a command arrives after its scene stopped being cancellable and is refused";

/// Whether a scene is cancellable, from the spec's definition (`[COOP-CANCELLABLE.1]`): its
/// phase is waiting or running.
fn cancellable(scene: &Scene) -> bool {
    matches!(scene.phase(), Phase::Waiting | Phase::Running)
}

/// Whether `seen`, a status list as a message carries it, is what the library reported of
/// `sent_from`, the planner's state it was sent from (`[COOP-OUT-STATUS.1]`): one entry per
/// live scene, in identifier order, and, with status views, each scene's status as the
/// library's own query for that scene gives it, which is the spec's: the scene's identifier,
/// module decision and operator decision, and cancellable as `[COOP-CANCELLABLE.1]` defines it.
/// With identifier views, an entry carries no status.
#[must_use]
pub fn reported(sent_from: &State, seen: &[Seen], views: Views) -> bool {
    let mut live = sent_from.scenes();
    let each = seen.iter().all(|entry| {
        let Some((id, scene)) = live.next() else {
            return false;
        };
        let status = match views {
            Views::Identifiers => None,
            Views::Statuses => sent_from.status(id),
        };
        let the_spec_s = status.map_or(true, |status| {
            status.id == id
                && status.module_decision == scene.module_decision()
                && status.operator_decision == scene.operator_decision()
                && status.cancellable == cancellable(scene)
        });
        entry.id == id && entry.status == status && the_spec_s
    });
    each && live.next().is_none()
}

/// The step property of a status sent: it carries what the library reports of the state it is
/// sent from. (An operator that receives it takes the message's list whole as its view.)
pub(super) fn observe_publish(
    model: &NetworkModel,
    from: &NetStep,
    next: &mut NetStep,
    message: &StatusMessage,
) {
    if !reported(&from.core, &message.seen, model.views()) {
        next.broken |= MISREPORTED;
    }
}

/// The step property of an owner's input: no operator decision changes, and a scene that
/// becomes live has none (`[COOP-DEV-STORED-COMMANDS.1]`: no command waits to apply later).
pub(super) fn observe_owner(from: &NetStep, next: &mut NetStep) {
    let stored = next.core.scenes().any(|(id, scene)| {
        let before = from.core.scene(id).map(Scene::operator_decision);
        scene.operator_decision() != before.unwrap_or(OperatorDecision::Undecided)
    });
    if stored {
        next.broken |= NOT_AT_ONCE;
    }
}

/// The step properties of a delivered command, recorded as sticky flags: whether the planner
/// `applied` it, and whether applying it `again` at once changed the core.
pub(super) fn observe_delivery(
    from: &NetStep,
    next: &mut NetStep,
    message: &CommandMessage,
    applied: bool,
    again: bool,
) {
    let id = message.command.id;
    // Only the named scene's operator decision may change.
    let spilled = from.core.scenes().any(|(other, old)| {
        let new = next.core.scene(other);
        let operator_moved = new.map(Scene::operator_decision) != Some(old.operator_decision());
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
    let before = from.core.scene(id);
    let after = next.core.scene(id).map(Scene::operator_decision);
    // A command built from a view of an earlier incarnation never changes a later one.
    let changed =
        before.map(Scene::operator_decision) != after || (before.is_none() && after.is_some());
    let current = index(id)
        .and_then(|i| next.incarnation.get(i))
        .copied()
        .unwrap_or(0);
    if changed && current != message.incarnation {
        next.broken |= STALE_TOUCHED_NEW;
    }
    // A scene that is not cancellable keeps its operator decision.
    if before.is_some_and(|scene| !cancellable(scene)) && changed {
        next.broken |= NOT_CANCELLABLE_CHANGED;
    }
    // A command for a cancellable scene (alone in its batch) takes effect now; one for an
    // identifier that is not live changes nothing, now (and, by `observe_owner`, later).
    let at_once = match before {
        Some(scene) if cancellable(scene) => after == Some(message.command.decision),
        Some(_) => true,
        None => next.core == from.core,
    };
    if !at_once {
        next.broken |= NOT_AT_ONCE;
    }
    // Applying it again at once has no second effect.
    if applied && again {
        next.broken |= SECOND_EFFECT;
    }
}

type Condition = fn(&NetworkModel, &NetStep) -> bool;

fn unbroken<const FLAG: u8>(_: &NetworkModel, step: &NetStep) -> bool {
    step.broken & FLAG == 0
}

fn invariants_hold(_: &NetworkModel, step: &NetStep) -> bool {
    step.core.check_invariants().is_ok()
}

/// Witness: with nothing in flight, every operator sees the planner as it is.
fn views_converge(model: &NetworkModel, step: &NetStep) -> bool {
    let current = model.snapshot(step);
    let quiet = step.statuses.iter().all(Vec::is_empty) && step.commands.iter().all(Vec::is_empty);
    quiet && !current.is_empty() && model.views_of(step).all(|view| *view == current)
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

/// Witness: a command reaches the planner after its scene began aborting, and is refused.
fn late_command_not_cancellable(_: &NetworkModel, step: &NetStep) -> bool {
    step.last == Some(Rule::CommandNotCancellable)
}

/// Whether the named property applies to `model`: two operators acting at once needs two, and
/// a scene that is not cancellable needs status views (only they let an owner abort).
pub(super) fn applies(model: &NetworkModel, name: &str) -> bool {
    match name {
        TWO_OPERATORS => model.operators() > 1,
        LATE_NOT_CANCELLABLE => model.views() == Views::Statuses,
        _ => true,
    }
}

/// Every property of the network model, whatever its operators and views (a model checks
/// those that apply to it).
#[must_use]
pub fn properties() -> Vec<Property<NetworkModel>> {
    static ALL: OnceLock<Vec<(bool, &'static str, Condition)>> = OnceLock::new();
    ALL.get_or_init(|| {
        vec![
            (true, "COOP-CMD-APPLY.1 (network): a command affects only the scene it names", unbroken::<SPILLED>),
            (true, "COOP-REG-RETIRED.1 (network): a command built from a stale status never touches a newer scene", unbroken::<STALE_TOUCHED_NEW>),
            (true, "COOP-CMD-APPLY.1 (network): a duplicated command has no second effect", unbroken::<SECOND_EFFECT>),
            (true, "spec §4 (network): a rejected input changes nothing", unbroken::<REJECTION_CHANGED>),
            (true, "COOP-INV-* (network): State::check_invariants holds", invariants_hold),
            (true, STATUS_RECEIVED, unbroken::<MISREPORTED>),
            (true, "COOP-CMD-NOT-CANCELLABLE.1, COOP-CANCELLABLE.1 (network): a delivered command never changes the operator decision of a scene that is not cancellable", unbroken::<NOT_CANCELLABLE_CHANGED>),
            (true, "COOP-CMD-APPLY.1, COOP-DEV-STORED-COMMANDS.1 (network): a delivered command takes effect at once, and one for an identifier that is not live changes nothing, then or later", unbroken::<NOT_AT_ONCE>),
            (false, "witness: the operators' views converge once messages stop", views_converge),
            (false, "witness: a scene completes while a command for it is in flight", completes_with_command_in_flight),
            (false, "witness: a new scene registers while a command for another is in flight", registers_with_command_in_flight),
            (false, TWO_OPERATORS, two_operators_at_once),
            (false, "witness: a command arrives after its scene retired and is refused", late_command_refused),
            (false, LATE_NOT_CANCELLABLE, late_command_not_cancellable),
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
