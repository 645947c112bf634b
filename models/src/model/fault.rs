//! Deliberately wrong behaviours, for showing that the model's properties can fail.
//!
//! A [`Fault`] wraps the library's transition (or its merged-decision query) and changes its
//! result, the way a bug would. Nothing here is compiled into the library: the shipped code
//! path is untouched. Faults that must reach past the public API edit the serialized state; a
//! state edited into one that breaks a library invariant is refused on the way back in, and the
//! fault then does nothing for that step.

use cooperation::{
    merge, CommandFailure, CommandOutcome, Decision, Input, OperatorDecision, Policy, Rejection,
    Rule, SceneId, SequenceRejection, State, Transition,
};
use serde_json::{json, Value};
use std::borrow::Cow;

/// A deliberately wrong behaviour.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum Fault {
    /// The merged decision treats a required policy as optional.
    RequiredAsOptional,
    /// The merged decision ignores an operator's deactivate when the module would activate.
    OperatorDeactivateIgnored,
    /// Commands naming retired identifiers are dropped and the rest of the batch applies.
    CommandReachesRetired,
    /// A policy change sets the module's scenes to autonomous (upstream's auto-mode toggle).
    PolicyClobbersOperator,
    /// An update for a retired identifier brings its scene back in the update's phase.
    TerminalLeaves,
    /// Registering a retired identifier forgets the retirement and registers it again.
    RetiredIdReused,
    /// A forbidden phase change is rejected, but its module decision is applied anyway.
    RejectionHalfApplies,
    /// A rejected command batch still applies its valid commands.
    BatchNotAtomic,
    /// Registering a live identifier under another module moves it there.
    IdMovesModule,
    /// An owner's update resets the operator decision to none.
    OwnerClearsOperator,
    /// A retirement forgets the oldest retired identifier although the retired set has room.
    ForgetsEarly,
    /// A command repeating the scene's operator decision flips it (activate and deactivate).
    CommandToggles,
    /// A command is applied to every cancellable scene, not only the one it names.
    CommandBroadcast,
    /// A command is applied even to a scene that is not cancellable (aborting), and reported
    /// as applied.
    CommandIgnoresCancellable,
}

impl Fault {
    /// Every fault.
    pub const ALL: [Self; 14] = [
        Self::RequiredAsOptional,
        Self::OperatorDeactivateIgnored,
        Self::CommandReachesRetired,
        Self::PolicyClobbersOperator,
        Self::TerminalLeaves,
        Self::RetiredIdReused,
        Self::RejectionHalfApplies,
        Self::BatchNotAtomic,
        Self::IdMovesModule,
        Self::OwnerClearsOperator,
        Self::ForgetsEarly,
        Self::CommandToggles,
        Self::CommandBroadcast,
        Self::CommandIgnoresCancellable,
    ];

    /// The library's transition, made wrong.
    ///
    /// # Errors
    /// The (possibly wrong) rejection.
    pub fn apply(self, core: &mut State, input: &Input) -> Result<Transition, Rejection> {
        let before = core.clone();
        let result = match (self, input) {
            (Self::CommandReachesRetired, Input::SetCommands { commands }) => {
                let kept = commands
                    .iter()
                    .filter(|c| before.retirement(c.id).is_none())
                    .copied();
                core.apply(&Input::SetCommands {
                    commands: kept.collect(),
                })
            }
            _ => core.apply(input),
        };
        let edited = match (self, input, &result) {
            (Self::PolicyClobbersOperator, Input::SetPolicies { policies }, Ok(_)) => {
                edit(core, |raw| {
                    for entry in scenes(raw) {
                        let module = entry.pointer("/1/module").cloned();
                        let named = policies.iter().any(|p| Some(json!(p.module)) == module);
                        if named {
                            set(entry, "/1/operator_decision", json!(OperatorDecision::Autonomous));
                        }
                    }
                })
            }
            (Self::OwnerClearsOperator, Input::Update { id, .. }, Ok(t)) if t.rule == Rule::OwnerUpdate => {
                edit_scene(core, *id, |scene| set(scene, "/operator_decision", json!(OperatorDecision::Undecided)))
            }
            (Self::RejectionHalfApplies, Input::Update { id, report, .. }, Err(Rejection::PhaseTransition { .. })) => {
                edit_scene(core, *id, |scene| set(scene, "/module_decision", json!(report.decision)))
            }
            (Self::BatchNotAtomic, Input::SetCommands { commands }, Err(Rejection::Commands { outcomes, .. })) => {
                let valid = commands.iter().zip(outcomes).filter(|(_, o)| **o == CommandOutcome::Withheld);
                let valid: Vec<_> = valid.map(|(c, _)| *c).collect();
                let mut next = core.clone();
                next.apply(&Input::SetCommands { commands: valid }).ok().map(|_| next)
            }
            (Self::RetiredIdReused, Input::Register { id, .. }, Err(Rejection::Revival { .. })) => {
                let mut next = unretire(core, *id);
                let revived = next.as_mut().map(|next| next.apply(input));
                if let (Some(next), Some(Ok(transition))) = (next, revived) {
                    *core = next;
                    return Ok(transition);
                }
                None
            }
            (
                Self::TerminalLeaves,
                Input::Update { id, phase, report, .. },
                Err(Rejection::OwnerRetired { retirement, .. }),
            ) if !phase.is_terminal() => unretire(core, *id).and_then(|mut next| {
                let scene = json!({
                    "module": retirement.module, "phase": phase, "module_decision": report.decision,
                    "operator_decision": OperatorDecision::Undecided, "requested": false, "age_ms": 0, "geometry": report.geometry,
                });
                let id = json!(id);
                next = edit(&next, |raw| push(raw, "/scenes", json!([id, scene])))?;
                Some(next)
            }),
            (Self::CommandToggles, Input::SetCommands { commands }, Ok(_)) => {
                edit(core, |raw| {
                    for command in commands {
                        let before = before.scene(command.id).map(cooperation::Scene::operator_decision);
                        let flipped = match command.decision {
                            OperatorDecision::Activate => OperatorDecision::Deactivate,
                            OperatorDecision::Deactivate => OperatorDecision::Activate,
                            other => other,
                        };
                        if before == Some(command.decision) {
                            let id = json!(command.id);
                            for entry in scenes(raw) {
                                if entry.get(0) == Some(&id) {
                                    set(entry, "/1/operator_decision", json!(flipped));
                                }
                            }
                        }
                    }
                })
            }
            (Self::CommandBroadcast, Input::SetCommands { commands }, Ok(_)) => {
                let decision = commands.first().map(|c| c.decision);
                edit(core, |raw| {
                    for entry in scenes(raw) {
                        let cancellable = matches!(
                            entry.pointer("/1/phase").and_then(Value::as_str),
                            Some("waiting" | "running")
                        );
                        if let (true, Some(decision)) = (cancellable, decision) {
                            set(entry, "/1/operator_decision", json!(decision));
                        }
                    }
                })
            }
            (
                Self::CommandIgnoresCancellable,
                Input::SetCommands { commands },
                Err(Rejection::Commands { outcomes, .. }),
            ) if outcomes.iter().all(|o| {
                matches!(o, CommandOutcome::Withheld | CommandOutcome::Failed(CommandFailure::NotCancellable(_)))
            }) =>
            {
                // Every command that failed only for its scene's phase is applied as if the
                // scene were cancellable.
                edit(core, |raw| {
                    for command in commands {
                        let id = json!(command.id);
                        for entry in scenes(raw) {
                            if entry.get(0) == Some(&id) {
                                set(entry, "/1/operator_decision", json!(command.decision));
                            }
                        }
                    }
                })
            }
            (Self::ForgetsEarly, _, Ok(t)) if !t.retired.is_empty() => {
                let remembered = core.retired_oldest_first().count();
                let oldest = core.retired_oldest_first().map(|(id, _)| id).next();
                let room = remembered < core.limits().retired_capacity;
                oldest.filter(|_| room && remembered > 1).and_then(|id| unretire(core, id))
            }
            (Self::IdMovesModule, Input::Register { id, module, .. }, Err(Rejection::WrongModule { .. })) => {
                edit_scene(core, *id, |scene| set(scene, "/module", json!(module)))
            }
            _ => None,
        };
        if let Some(edited) = edited {
            *core = edited;
        }
        // A fault that changed the outcome reports the rule its result now looks like.
        match (self, &result) {
            (Self::TerminalLeaves, Err(Rejection::OwnerRetired { .. })) if *core != before => {
                Ok(Transition {
                    rule: Rule::OwnerUpdate,
                    retired: Vec::new(),
                })
            }
            (Self::CommandIgnoresCancellable, Err(Rejection::Commands { .. }))
                if *core != before =>
            {
                Ok(Transition {
                    rule: Rule::CommandApply,
                    retired: Vec::new(),
                })
            }
            (Self::IdMovesModule, Err(Rejection::WrongModule { .. })) if *core != before => {
                Ok(Transition {
                    rule: Rule::RegisterNew,
                    retired: Vec::new(),
                })
            }
            _ => result,
        }
    }

    /// The library's merged decision, made wrong.
    #[must_use]
    pub fn merged_decision(self, core: &State, id: SceneId) -> Option<Decision> {
        let scene = core.scene(id)?;
        let policy = core.policy(scene.module())?;
        let (operator, module) = (scene.operator_decision(), scene.module_decision());
        match self {
            Self::RequiredAsOptional if policy == Policy::Required => {
                Some(merge(operator, Policy::Optional, module))
            }
            Self::OperatorDeactivateIgnored
                if operator == OperatorDecision::Deactivate && module == Decision::Activate =>
            {
                Some(Decision::Activate)
            }
            _ => core.merged_decision(id),
        }
    }
}

/// The transition every model makes: `State::after`, as a consumer that keeps the state it
/// came from calls it (`State::apply` on a copy, the copy made only for an accepted input), or,
/// in a sensitivity test, the faulty wrapper around `apply` on a copy. Gives the state the input
/// left (`core` itself when it was refused), and the result.
pub fn transition<'a>(
    fault: Option<Fault>,
    core: &'a State,
    input: &Input,
) -> (Cow<'a, State>, Result<Transition, Rejection>) {
    match fault {
        None => match core.after(input) {
            Ok((next, transition)) => (Cow::Owned(next), Ok(transition)),
            Err(rejection) => (Cow::Borrowed(core), Err(rejection)),
        },
        Some(fault) => {
            let mut next = core.clone();
            let result = fault.apply(&mut next, input);
            (Cow::Owned(next), result)
        }
    }
}

/// The transition of a sequence of inputs: `State::apply_all` on a copy of `core`, as a
/// consumer calls it. Gives the copy as the sequence left it, and the result.
pub fn sequence(
    core: &State,
    inputs: &[Input],
) -> (State, Result<Vec<Transition>, SequenceRejection>) {
    let mut next = core.clone();
    let result = next.apply_all(inputs);
    (next, result)
}

/// `state` serialized, edited and read back (and so checked against every invariant).
fn edit(state: &State, change: impl FnOnce(&mut Value)) -> Option<State> {
    let mut raw = serde_json::to_value(state).ok()?;
    change(&mut raw);
    serde_json::from_value(raw).ok()
}

fn edit_scene(state: &State, id: SceneId, change: impl FnOnce(&mut Value)) -> Option<State> {
    let id = json!(id);
    edit(state, |raw| {
        if let Some(entry) = scenes(raw)
            .into_iter()
            .find(|entry| entry.get(0) == Some(&id))
        {
            if let Some(scene) = entry.get_mut(1) {
                change(scene);
            }
        }
    })
}

fn scenes(raw: &mut Value) -> Vec<&mut Value> {
    raw.pointer_mut("/scenes")
        .and_then(Value::as_array_mut)
        .map(|list| list.iter_mut().collect())
        .unwrap_or_default()
}

fn push(raw: &mut Value, pointer: &str, item: Value) {
    if let Some(list) = raw.pointer_mut(pointer).and_then(Value::as_array_mut) {
        list.push(item);
    }
}

fn set(raw: &mut Value, pointer: &str, value: Value) {
    if let Some(slot) = raw.pointer_mut(pointer) {
        *slot = value;
    }
}

/// `state` with `id` forgotten by the retired set.
fn unretire(state: &State, id: SceneId) -> Option<State> {
    let id = json!(id);
    edit(state, |raw| {
        if let Some(list) = raw.pointer_mut("/retired").and_then(Value::as_array_mut) {
            list.retain(|entry| entry.get(0) != Some(&id));
        }
        if let Some(list) = raw
            .pointer_mut("/retired_order")
            .and_then(Value::as_array_mut)
        {
            list.retain(|entry| *entry != id);
        }
    })
}
