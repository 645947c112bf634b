//! The relay model's properties: the specification's rules for the relay (`[COOP-RELAY-*]`),
//! each a condition on one state, and witnesses that the checked runs reach what they are about.

use std::collections::BTreeSet;

use cooperation::{Decision, OperatorDecision, Phase, SceneId};
use stateright::Property;

use super::{broken, RelayModel, RelayStep, INTERFACE};

/// `COOP-RELAY-SUCCESS.1`'s property.
pub const SUCCESS: &str =
    "COOP-RELAY-SUCCESS.1: an operator's call is a success only if the module took every command of it";
/// `COOP-RELAY-FORWARD.1`'s property.
pub const SHOWN: &str =
    "COOP-RELAY-FORWARD.1: every operator decision the AD API shows is one the module took";
/// `COOP-RELAY-FOLLOW.1`'s property.
pub const FOLLOW: &str = "COOP-RELAY-FOLLOW.1, COOP-RELAY-POLICY.1: settled, the module drives every cancellable scene as the merged decision the AD API shows";
/// `COOP-RELAY-FOLLOW.1`'s property on switches: a module's auto mode is what it last said,
/// in a status or in a switch's answer, so a switch to that mode is never sent (each one
/// overwrites the module's standing decisions for a moment).
pub const SWITCH: &str =
    "COOP-RELAY-FOLLOW.1: the relay never switches the module to the auto mode it was last told the module has";
/// `COOP-RELAY-REPORT.1`'s property.
pub const SCENES: &str =
    "COOP-RELAY-REPORT.1: settled, the AD API shows exactly the scenes the module lists, not finished";

fn succeeded(_: &RelayModel, state: &RelayStep) -> bool {
    state.broken & broken::SUCCESS == 0
}

fn no_needless_switch(_: &RelayModel, state: &RelayStep) -> bool {
    state.broken & broken::NEEDLESS == 0
}

fn shown_taken(_: &RelayModel, state: &RelayStep) -> bool {
    state.relay.state().scenes().all(|(id, scene)| {
        let decision = match scene.operator_decision() {
            OperatorDecision::Activate => Decision::Activate,
            OperatorDecision::Deactivate => Decision::Deactivate,
            OperatorDecision::Autonomous | OperatorDecision::Undecided => return true,
        };
        state.taken.contains(&(id, decision))
    })
}

fn follows(_: &RelayModel, state: &RelayStep) -> bool {
    !state.settled()
        || state.module.statuses.iter().all(|status| {
            let cancellable = matches!(status.phase, Phase::Waiting | Phase::Running);
            let merged = state.relay.state().merged_decision(status.id);
            !cancellable
                || merged.is_some_and(|merged| {
                    (merged == Decision::Activate) == state.module.is_activated(status.id)
                })
        })
}

fn same_scenes(_: &RelayModel, state: &RelayStep) -> bool {
    if !state.settled() {
        return true;
    }
    let listed: BTreeSet<SceneId> = state
        .module
        .statuses
        .iter()
        .filter(|status| !status.phase.is_terminal())
        .map(|status| status.id)
        .collect();
    let shown: BTreeSet<SceneId> = state.relay.state().scenes().map(|(id, _)| id).collect();
    listed == shown
}

fn refused_forward(_: &RelayModel, state: &RelayStep) -> bool {
    state.answers.iter().any(|(_, answer)| {
        matches!(answer, cooperation_adapters::relay::ModuleAnswer::Commands(r)
            if r.responses.iter().any(|response| !response.success))
    })
}

fn standing_kept_through_switch(_: &RelayModel, state: &RelayStep) -> bool {
    state.settled()
        && state.module.auto_mode
        && state.relay.state().scenes().any(|(_, scene)| {
            matches!(
                scene.operator_decision(),
                OperatorDecision::Activate | OperatorDecision::Deactivate
            )
        })
}

fn unanswered(_: &RelayModel, state: &RelayStep) -> bool {
    state.clock_ms > 0 && state.relay.link(INTERFACE).is_some()
}

/// The properties.
#[must_use]
pub fn properties() -> Vec<Property<RelayModel>> {
    vec![
        Property::always(SUCCESS, succeeded),
        Property::always(SHOWN, shown_taken),
        Property::always(FOLLOW, follows),
        Property::always(SWITCH, no_needless_switch),
        Property::always(SCENES, same_scenes),
        Property::sometimes(
            "witness: the module refuses a forwarded command",
            refused_forward,
        ),
        Property::sometimes(
            "witness: settled in auto mode with a standing operator decision",
            standing_kept_through_switch,
        ),
        Property::sometimes("witness: a call runs out of time", unanswered),
    ]
}
