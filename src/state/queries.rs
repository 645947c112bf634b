//! What a state answers: its scenes, retirements, policies and limits.

use super::{Limits, Scene, State};
use crate::{Decision, Module, Policy, PolicySetting, Retirement, SceneId};

impl State {
    /// The limits in force.
    #[must_use]
    pub const fn limits(&self) -> Limits {
        self.limits
    }

    /// The live scene with this identifier.
    #[must_use]
    #[inline]
    pub fn scene(&self, id: SceneId) -> Option<&Scene> {
        self.scenes.get(id)
    }

    /// Every live scene, in identifier order.
    pub fn scenes(&self) -> impl Iterator<Item = (SceneId, &Scene)> + '_ {
        self.scenes.iter()
    }

    /// Every live scene, in no particular order: for outputs sorted afterwards.
    pub(crate) fn scenes_in_any_order(&self) -> impl Iterator<Item = (SceneId, &Scene)> + '_ {
        self.scenes.iter_unordered()
    }

    /// The live scene at `position` of [`scenes_in_any_order`](Self::scenes_in_any_order).
    pub(crate) fn scene_at(&self, position: usize) -> Option<(SceneId, &Scene)> {
        self.scenes.entry_at(position)
    }

    /// How many scenes are live.
    #[must_use]
    pub fn scene_count(&self) -> usize {
        self.scenes.len()
    }

    /// What a retired identifier retired as, while it is remembered.
    #[must_use]
    pub fn retirement(&self, id: SceneId) -> Option<Retirement> {
        self.retired.get(&id).copied()
    }

    /// The remembered retired identifiers, oldest first: the order in which they are forgotten
    /// (`[COOP-RETIRE.1]`).
    pub fn retired_oldest_first(&self) -> impl Iterator<Item = (SceneId, Retirement)> + '_ {
        self.retired_order
            .iter()
            .filter_map(|id| self.retired.get(id).map(|retirement| (*id, *retirement)))
    }

    /// The remembered retired identifiers, in identifier order.
    pub fn retired_by_id(&self) -> impl Iterator<Item = (SceneId, Retirement)> + '_ {
        self.retired
            .iter()
            .map(|(id, retirement)| (*id, *retirement))
    }

    /// This state with every identifier renamed by `rename`, or `None` if `rename` gives two
    /// identifiers the same name.
    ///
    /// No rule reads an identifier's value, only whether two are equal and their order: a
    /// renamed state behaves as this one does with the names changed, except that scenes
    /// expiring on the same tick retire in the order of their new names. Model checkers use it
    /// for symmetry reduction.
    ///
    /// A model checker's hook, public with the `verification` feature only: the model checker
    /// of this crate is a crate of its own, which must check the very `State` consumers use.
    /// It builds a new state and changes nothing, and the state it builds holds every invariant
    /// this one holds.
    #[cfg(feature = "verification")]
    #[must_use]
    pub fn relabel(&self, rename: impl Fn(SceneId) -> SceneId) -> Option<Self> {
        let scenes = self.scenes.like(
            self.scenes
                .iter()
                .map(|(id, scene)| (rename(id), scene.clone())),
        );
        let retired: std::collections::BTreeMap<SceneId, Retirement> = self
            .retired
            .iter()
            .map(|(id, retirement)| (rename(*id), *retirement))
            .collect();
        let renamed = Self {
            limits: self.limits,
            policies: self.policies.clone(),
            retired_order: std::sync::Arc::new(
                self.retired_order.iter().map(|id| rename(*id)).collect(),
            ),
            scenes,
            retired: std::sync::Arc::new(retired),
        };
        let distinct = renamed.scenes.len() == self.scenes.len()
            && renamed.retired.len() == self.retired.len()
            && renamed
                .scenes
                .iter()
                .all(|(id, _)| !renamed.retired.contains_key(&id));
        distinct.then_some(renamed)
    }

    /// A module's current policy, if it supports cooperation.
    #[must_use]
    #[inline]
    pub fn policy(&self, module: Module) -> Option<Policy> {
        self.policies.get(module)
    }

    /// Every module's current policy, in module order: the AD API `get_policies` answer
    /// (`[COOP-POL-GET.2]`).
    pub fn policies(&self) -> impl Iterator<Item = PolicySetting> + '_ {
        self.policies
            .iter()
            .map(|(module, policy)| PolicySetting { module, policy })
    }

    /// The merged decision the planner drives a live scene with (`[COOP-MERGE.1]`).
    #[must_use]
    pub fn merged_decision(&self, id: SceneId) -> Option<Decision> {
        let scene = self.scenes.get(id)?;
        let policy = self.policies.at(scene.slot)?;
        Some(scene.merged_decision(policy))
    }

    /// Every live scene's merged decision (`[COOP-MERGE.1]`), in identifier order: what
    /// [`merged_decision`](Self::merged_decision) gives for each, with no policy to look up.
    pub fn merged_decisions(&self) -> impl Iterator<Item = (SceneId, Decision)> + '_ {
        self.scenes().filter_map(|(id, scene)| {
            let policy = self.policies.at(scene.slot)?;
            Some((id, scene.merged_decision(policy)))
        })
    }

    /// Whether a live scene waits for an operator ([`Scene::awaits_operator`]).
    #[must_use]
    pub fn awaits_operator(&self, id: SceneId) -> Option<bool> {
        let scene = self.scenes.get(id)?;
        let policy = self.policies.at(scene.slot)?;
        Some(scene.awaits_operator(policy))
    }

    /// Whether the operator activated what the module would not (`[COOP-FORCE-ACTIVATED.1]`).
    #[must_use]
    pub fn force_activated(&self, id: SceneId) -> Option<bool> {
        self.scenes.get(id).map(Scene::is_force_activated)
    }

    /// Whether the operator deactivated a running scene the module would go on with
    /// (`[COOP-FORCE-DEACTIVATED.1]`).
    #[must_use]
    pub fn force_deactivated(&self, id: SceneId) -> Option<bool> {
        self.scenes.get(id).map(Scene::is_force_deactivated)
    }
}
