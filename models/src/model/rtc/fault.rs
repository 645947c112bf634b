//! Deliberately wrong RTC adapters, for showing that the RTC model's properties can fail.
//!
//! An [`RtcFault`] wraps the calls the model makes: it calls the library's adapter (or the
//! core directly, to skip a check the adapter makes) and changes what happens the way a bug
//! would, several of them the way upstream's `rtc_interface` behaves. Nothing here is compiled
//! into the library: the shipped code path is untouched.

use std::sync::Arc;

use cooperation::{
    Command, Decision, Input, Module, OperatorDecision, PolicySetting, Rejection, Report, Rule,
    SceneId, State,
};
use cooperation_adapters::rtc::{policy_for_auto_mode, Binding, Rtc};
use serde::{Deserialize, Serialize};

use super::call::{request, Call, Order};
use super::observe::Said;
use super::step::{Answer, Kind, Refusal};
use super::RtcModel;

/// A deliberately wrong RTC adapter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum RtcFault {
    /// Switching auto mode on makes every cancellable scene of the switched modules autonomous,
    /// erasing operator decisions (upstream's toggle).
    AutoModeClobbers,
    /// An interface's command service matches commands to scenes of every interface.
    CommandCrossesInterface,
    /// Every command request is stored, unknown and refused commands included, and re-applied
    /// after every status update (upstream's stored commands, without the lock).
    StoredCommandReapplies,
    /// A refused status update answers success with no transition (upstream logs and drops).
    RejectionDropped,
    /// A status update refused by the lifecycle still writes the module decision.
    RefusalHalfApplies,
    /// An interface's removal removes a scene of another interface of the same module.
    RemoveCrossesInterface,
    /// A status update is made in its interface's first sequence, whatever sequence the owner
    /// states (a return registers as a shift out).
    SequenceIgnored,
    /// An interface's auto-mode switch sets the policy of its first module only (one flag per
    /// interface, as upstream, mapped to one module).
    AutoModeOneSequence,
    /// A removal names the interface's first module, not the scene's.
    RemoveInFirstSequence,
}

impl RtcFault {
    /// Every fault.
    pub const ALL: [Self; 9] = [
        Self::AutoModeClobbers,
        Self::CommandCrossesInterface,
        Self::StoredCommandReapplies,
        Self::RejectionDropped,
        Self::RefusalHalfApplies,
        Self::RemoveCrossesInterface,
        Self::SequenceIgnored,
        Self::AutoModeOneSequence,
        Self::RemoveInFirstSequence,
    ];

    /// Whether the fault can show only through an interface bound to several sequences.
    #[must_use]
    pub const fn needs_sequences(self) -> bool {
        matches!(
            self,
            Self::SequenceIgnored | Self::AutoModeOneSequence | Self::RemoveInFirstSequence
        )
    }

    /// The call, made wrong. `stash` is the fault's memory, kept in the model's state.
    pub(super) fn invoke(
        self,
        model: &RtcModel,
        core: &mut State,
        rtc: &mut Rtc,
        stash: &mut Option<Arc<Vec<Order>>>,
        call: &Call,
    ) -> Said {
        match (self, call) {
            (
                Self::CommandCrossesInterface,
                Call::Commands {
                    interface: Some(_),
                    orders,
                },
            ) => Said::commands(
                Kind::Commands,
                rtc.cooperate_commands(core, &request(orders)),
            ),
            (Self::StoredCommandReapplies, Call::Commands { orders, .. }) => {
                *stash = Some(Arc::new(orders.clone()));
                model.invoke(core, rtc, call)
            }
            (Self::StoredCommandReapplies, Call::Update { .. }) => {
                let said = model.invoke(core, rtc, call);
                if let Some(stored) = stash.as_deref() {
                    let _ = rtc.cooperate_commands(core, &request(stored));
                }
                said
            }
            (Self::RejectionDropped, Call::Update { .. }) => {
                let said = model.invoke(core, rtc, call);
                if said.accepted() {
                    said
                } else {
                    Said::of(Kind::Update, Answer::Accepted(None, None))
                }
            }
            (
                Self::RefusalHalfApplies,
                Call::Update {
                    id,
                    safe,
                    requested,
                    ..
                },
            ) => {
                let said = model.invoke(core, rtc, call);
                let refused = Answer::Refused(Refusal::Core(Rule::OwnerTransition));
                if said.outcome.answer == refused {
                    half_apply(core, *id, *safe, *requested);
                }
                said
            }
            (Self::RemoveCrossesInterface, Call::Remove { interface, id }) => {
                let module = model.binding(*interface).and_then(Binding::only_module);
                let result = module
                    .ok_or(Rejection::OwnerUnknown { id: *id })
                    .and_then(|module| core.apply(&Input::Remove { id: *id, module }));
                Said::transitions(Kind::Remove, result.map_err(Into::into))
            }
            (
                Self::SequenceIgnored,
                Call::Update {
                    interface,
                    sequence: Some(_),
                    ..
                },
            ) => {
                let first = model
                    .binding(*interface)
                    .and_then(|b| b.sequences.first().copied());
                let mut call = call.clone();
                if let Call::Update { sequence, .. } = &mut call {
                    *sequence = first;
                }
                model.invoke(core, rtc, &call)
            }
            (Self::AutoModeOneSequence, Call::AutoMode { interface, enable }) => {
                let Some(module) = first_module(model, *interface) else {
                    return model.invoke(core, rtc, call);
                };
                let result = core
                    .apply(&Input::SetPolicies {
                        policies: vec![PolicySetting {
                            module,
                            policy: policy_for_auto_mode(*enable),
                        }],
                    })
                    .map_err(Into::into);
                let success = result.is_ok();
                Said::auto_mode(Kind::AutoMode, result, success)
            }
            (Self::RemoveInFirstSequence, Call::Remove { interface, id }) => {
                let own = model.binding(*interface).map(|b| &b.name)
                    == rtc.owner(core, *id).map(|b| &b.name);
                match first_module(model, *interface) {
                    Some(module) if own && core.scene(*id).is_some() => {
                        let result = core.apply(&Input::Remove { id: *id, module });
                        Said::transitions(Kind::Remove, result.map_err(Into::into))
                    }
                    _ => model.invoke(core, rtc, call),
                }
            }
            (
                Self::AutoModeClobbers,
                Call::AutoMode { enable: true, .. } | Call::AutoModeWithModule { enable: true, .. },
            ) => {
                let said = model.invoke(core, rtc, call);
                if said.accepted() {
                    clobber(core, &model.switched_modules(call));
                }
                said
            }
            _ => model.invoke(core, rtc, call),
        }
    }
}

/// The first module interface `interface` is bound to.
fn first_module(model: &RtcModel, interface: usize) -> Option<Module> {
    model.binding(interface).and_then(|b| b.modules().next())
}

/// The refused update's module decision written anyway: an update to the scene's own phase.
fn half_apply(core: &mut State, id: SceneId, safe: bool, requested: bool) {
    let Some(scene) = core.scene(id) else { return };
    let update = Input::Update {
        id,
        module: scene.module(),
        phase: scene.phase(),
        report: Report {
            requested,
            ..Report::new(
                if safe {
                    Decision::Activate
                } else {
                    Decision::Deactivate
                },
                *scene.geometry(),
            )
        },
    };
    let _ = core.apply(&update);
}

/// Every cancellable scene of `modules` made autonomous.
fn clobber(core: &mut State, modules: &[Module]) {
    let commands: Vec<Command> = core
        .scenes()
        .filter(|(_, scene)| scene.is_cancellable() && modules.contains(&scene.module()))
        .map(|(id, _)| Command {
            id,
            decision: OperatorDecision::Autonomous,
        })
        .collect();
    let _ = core.apply(&Input::SetCommands { commands });
}
