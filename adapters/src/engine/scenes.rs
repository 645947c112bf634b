//! `/cooperation/scenes`: what the AD API's factors do not say of each live scene, read from the
//! core. For each: the merged decision the planner drives with (`[COOP-MERGE.1]`), whether the
//! scene waits for an operator (`State::awaits_operator`), whether its owner asked for one
//! (`[COOP-REQUESTED.1]`), the policy that applies to it, and the time since its owner last
//! reported it. The operator panel shows them; nothing here is decided by the node.

use crate::wire::{CooperationDecision, CooperationPolicy, Uuid};
use crate::Time;
use cooperation::{PolicySetting, State};
use serde::{Deserialize, Serialize};

/// The topic's name.
pub const NAME: &str = "/cooperation/scenes";
/// The topic's type.
pub const TYPE: &str = "cooperation_server/msg/SceneArray";

/// The topic's message: every live scene, in identifier order.
#[derive(Clone, PartialEq, Eq, Debug, Default, Serialize, Deserialize)]
pub struct SceneArray {
    /// When it was read.
    pub stamp: Time,
    /// The live scenes.
    pub scenes: Vec<SceneState>,
}

/// One live scene.
#[derive(Clone, PartialEq, Eq, Debug, Default, Serialize, Deserialize)]
pub struct SceneState {
    /// The scene.
    pub uuid: Uuid,
    /// The merged decision: `CooperationDecision::DEACTIVATE` or `ACTIVATE`.
    pub merged: CooperationDecision,
    /// It waits for an operator: cancellable, undecided, under a required policy.
    pub awaits_operator: bool,
    /// Its owner asked for an operator decision.
    pub requested: bool,
    /// The policy that applies to it: `CooperationPolicy::OPTIONAL` or `REQUIRED`.
    pub policy: u8,
    /// Milliseconds since its owner last reported it.
    pub age_ms: u64,
}

/// The message for `state`, stamped `stamp`.
#[must_use]
pub fn scene_array(state: &State, stamp: Time) -> SceneArray {
    let scenes = state
        .scenes()
        .filter_map(|(id, scene)| {
            let policy = state.policy(scene.module())?;
            let effective = scene.effective_policy(policy);
            Some(SceneState {
                uuid: id.into(),
                merged: scene.merged_decision(policy).into(),
                awaits_operator: scene.awaits_operator(policy),
                requested: scene.is_requested(),
                policy: CooperationPolicy::from(PolicySetting {
                    module: scene.module(),
                    policy: effective,
                })
                .policy,
                age_ms: scene.age_ms(),
            })
        })
        .collect();
    SceneArray { stamp, scenes }
}
