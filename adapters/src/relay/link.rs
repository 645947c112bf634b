//! One planning module's RTC interface as the relay sees it: what its newest status array said
//! of each scene, its auto mode, and what must be sent to it so that it drives as the core
//! decides (`[COOP-RELAY-FOLLOW.1]`).

use std::collections::BTreeMap;

use cooperation::{Decision, OperatorDecision, Phase, Policy, SceneId, State};

use crate::rtc::{Binding, ParsedStatus};
use crate::Time;

/// What a module's newest status array said of one scene: the settings its RTC interface
/// drives with.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct Seen {
    /// `safe`.
    pub safe: bool,
    /// `requested`.
    pub requested: bool,
    /// `command_status`.
    pub command: Decision,
    /// `auto_mode`.
    pub auto_mode: bool,
    /// `state`.
    pub phase: Phase,
}

impl Seen {
    /// The scene's status as the array carried it.
    #[must_use]
    pub const fn of(status: &ParsedStatus) -> Self {
        Self {
            safe: matches!(status.module_decision, Decision::Activate),
            requested: status.requested,
            command: status.command,
            auto_mode: status.auto_mode,
            phase: status.phase,
        }
    }

    /// What an upstream RTC interface with these settings answers to `isActivated`: nothing
    /// after a terminal state, the module's `safe` in auto mode unless the scene is requested,
    /// else the operator's command.
    #[must_use]
    pub const fn activation(&self) -> Decision {
        let activated = match self.phase {
            Phase::Succeeded | Phase::Failed => false,
            _ if self.auto_mode && !self.requested => self.safe,
            _ => matches!(self.command, Decision::Activate),
        };
        if activated {
            Decision::Activate
        } else {
            Decision::Deactivate
        }
    }
}

/// A module interface's state in the relay.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Default)]
pub struct Link {
    /// The stamp of the newest status array taken: an older or equal one is late.
    pub newest: Option<Time>,
    /// Each scene of the newest array.
    pub seen: BTreeMap<SceneId, Seen>,
    /// The interface's auto mode, from its auto-mode status topic.
    pub auto_mode: Option<bool>,
    /// A status array came since the last call to the module was answered (or ran out of
    /// time): what it says reflects every call sent, so a correction may be judged from it.
    pub fresh: bool,
}

/// What the relay must send an interface for it to drive as the core decides.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Correction {
    /// Switch the interface's auto mode (which sets every one of its scenes' `auto_mode`).
    AutoMode(bool),
    /// Send these commands.
    Commands(Vec<(SceneId, Decision)>),
}

/// The policy the interface's auto mode stands for: that of its modules, if they agree.
#[must_use]
pub(super) fn interface_policy(state: &State, binding: &Binding) -> Option<Policy> {
    let mut policies = binding.modules().filter_map(|module| state.policy(module));
    let first = policies.next()?;
    policies.all(|policy| policy == first).then_some(first)
}

impl Link {
    /// Whether the module has spoken: a status array or its auto mode has come.
    #[must_use]
    pub const fn heard(&self) -> bool {
        self.newest.is_some() || self.auto_mode.is_some()
    }

    /// What to send the interface so that every scene it reports drives with the merged
    /// decision the core shows, if anything: first its auto mode, then per scene a command
    /// (`[COOP-RELAY-FOLLOW.1]`). Only scenes both sides hold cancellable are judged; a scene
    /// with the operator decision autonomous is not (the relay never sets one,
    /// `[COOP-RELAY-INEXPRESSIBLE.1]`).
    #[must_use]
    pub fn correction(&self, state: &State, binding: &Binding) -> Option<Correction> {
        let policy = interface_policy(state, binding)?;
        let auto = policy == Policy::Optional;
        if self.auto_mode.is_some_and(|on| on != auto) {
            return Some(Correction::AutoMode(auto));
        }
        let mut commands = Vec::new();
        for (&id, seen) in &self.seen {
            let Some(scene) = state.scene(id) else {
                continue;
            };
            if !scene.is_cancellable() || !seen.phase.is_cancellable() {
                continue;
            }
            let effective = scene.effective_policy(state.policy(scene.module())?);
            match scene.operator_decision() {
                OperatorDecision::Activate => {
                    if seen.auto_mode || seen.command != Decision::Activate {
                        commands.push((id, Decision::Activate));
                    }
                }
                OperatorDecision::Deactivate => {
                    if seen.auto_mode || seen.command != Decision::Deactivate {
                        commands.push((id, Decision::Deactivate));
                    }
                }
                OperatorDecision::Undecided if effective == Policy::Required => {
                    if (seen.auto_mode && !seen.requested) || seen.command != Decision::Deactivate {
                        commands.push((id, Decision::Deactivate));
                    }
                }
                OperatorDecision::Undecided => {
                    if !seen.auto_mode {
                        // Upstream has no per-scene command back to auto mode: only the switch.
                        return Some(Correction::AutoMode(true));
                    }
                }
                OperatorDecision::Autonomous => {}
            }
        }
        (!commands.is_empty()).then_some(Correction::Commands(commands))
    }

    /// The standing operator decisions of the interface's scenes (activate or deactivate, on a
    /// cancellable scene): what an auto-mode switch overwrites and the relay sends again
    /// (`[COOP-RELAY-POLICY.1]`).
    #[must_use]
    pub fn standing(&self, state: &State) -> Vec<(SceneId, Decision)> {
        self.seen
            .keys()
            .filter_map(|&id| {
                let scene = state.scene(id).filter(|scene| scene.is_cancellable())?;
                match scene.operator_decision() {
                    OperatorDecision::Activate => Some((id, Decision::Activate)),
                    OperatorDecision::Deactivate => Some((id, Decision::Deactivate)),
                    OperatorDecision::Autonomous | OperatorDecision::Undecided => None,
                }
            })
            .collect()
    }
}
