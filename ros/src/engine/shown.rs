//! What the node's streams show of the core: every field of every live scene that a factor or
//! the scenes topic carries, and every policy, but not the scenes' ages. The engine keeps the
//! projection of its last publication and of the state now; where they differ, a publication is
//! due at once.

use cooperation::{Decision, Detail, Geometry, Module, OperatorDecision, Phase, PolicySetting};
use cooperation::{SceneId, State};

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

/// The streams' content, short of stamps and ages.
#[derive(PartialEq, Eq, Hash, Debug, Default)]
pub(super) struct Shown {
    scenes: Vec<ShownScene>,
    policies: Vec<PolicySetting>,
}

impl Shown {
    /// What `state` shows.
    #[must_use]
    pub(super) fn of(state: &State) -> Self {
        let mut shown = Self::default();
        shown.refresh(state);
        shown
    }

    /// Makes this what `state` shows, in the room it already has: a change of the core costs
    /// no allocation once the lists have grown to the state's size.
    pub(super) fn refresh(&mut self, state: &State) {
        self.scenes.clear();
        self.scenes.extend(state.scenes().map(|(id, scene)| {
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
        }));
        self.policies.clear();
        self.policies.extend(state.policies());
    }
}

impl Clone for Shown {
    fn clone(&self) -> Self {
        Self {
            scenes: self.scenes.clone(),
            policies: self.policies.clone(),
        }
    }

    /// Into the room this one has (the last publication's copy, refreshed at each one).
    fn clone_from(&mut self, source: &Self) {
        self.scenes.clone_from(&source.scenes);
        self.policies.clone_from(&source.policies);
    }
}
