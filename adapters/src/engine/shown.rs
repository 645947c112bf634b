//! What the node's streams show of a scene: every field a factor or the scenes topic carries,
//! but not its age. A sync changes what the streams show exactly when one of the scenes it names
//! shows otherwise after it than before; an AD API call, when it changes an operator decision or
//! a policy; time, when a scene expires. Those are the changes that make a publication due at
//! once (`[COOP-ENGINE-PUBLISH.1]`); the engine model checks that no other call changes what
//! the streams carry.

use cooperation::{Decision, Detail, Geometry, Module, OperatorDecision, Phase};
use cooperation::{Scene, SceneId, State};

use crate::sync::SyncRequest;

/// One live scene as the streams show it.
type ShownScene = (
    SceneId,
    Module,
    Phase,
    Decision,
    OperatorDecision,
    bool,
    Geometry,
    Detail,
);

/// One scene as the streams show it.
fn shown(id: SceneId, scene: &Scene) -> ShownScene {
    (
        id,
        scene.module(),
        scene.phase(),
        scene.module_decision(),
        scene.operator_decision(),
        scene.is_requested(),
        *scene.geometry(),
        scene.detail().clone(),
    )
}

/// The scenes a sync names, in its order: those it reports, then those it removes.
pub(super) fn named(request: &SyncRequest) -> Vec<SceneId> {
    request
        .statuses
        .iter()
        .map(|status| SceneId::from(status.uuid))
        .chain(request.removed.iter().map(|&uuid| SceneId::from(uuid)))
        .collect()
}

/// How the streams show each of `ids` in `state` (`None`: not live).
pub(super) fn of_scenes(state: &State, ids: &[SceneId]) -> Vec<Option<ShownScene>> {
    ids.iter()
        .map(|&id| state.scene(id).map(|scene| shown(id, scene)))
        .collect()
}
