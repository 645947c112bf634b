//! One RTC interface's calls (`rtc_interface`'s methods for one module): [`Interface`] to
//! change the core through, [`View`] to query it.

use crate::rtc::{
    AutoModeRequest, AutoModeResponse, AutoModeStatus, Binding, CooperateCommandsRequest,
    CooperateCommandsResponse, CooperateStatus, CooperateStatusArray, RtcError, StatusReport,
    Transitions,
};
use crate::Time;
use cooperation::{
    Decision, Input, Module, Phase, Policy, Report, RetireReason, Scene, SceneId, Sequence,
    Transition,
};

use super::{
    apply_commands, auto_mode_status, auto_mode_under, cooperate_status, set_auto_mode,
    ModulePolicy, Reply, Routes,
};

/// What upstream's per-scene queries answer of one live scene of an interface
/// ([`View::answers`]).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Answers {
    /// [`View::is_activated`].
    pub activated: bool,
    /// [`View::is_force_activated`].
    pub force_activated: bool,
    /// [`View::is_force_deactivated`].
    pub force_deactivated: bool,
    /// [`View::is_rtc_enabled`] (a live scene's, so never `None`).
    pub rtc_enabled: bool,
}

/// One RTC interface, for queries. Made by [`Rtc::view`](super::Rtc::view).
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    pub(super) bindings: &'a [Binding],
    pub(super) binding: &'a Binding,
    pub(super) index: usize,
    pub(super) routes: &'a Routes,
    pub(super) state: &'a cooperation::State,
    /// The binding's module and its policy, read when the view was made, if the binding has
    /// one module: the policy of every scene of the interface, read once.
    pub(super) module_policy: ModulePolicy<'a>,
}

impl<'a> View<'a> {
    /// The interface's binding.
    #[must_use]
    pub const fn binding(&self) -> &'a Binding {
        self.binding
    }

    /// The live scene `id`, if it registered through this interface.
    #[must_use]
    pub fn scene(&self, id: SceneId) -> Option<&'a Scene> {
        let scene = self.state.scene(id)?;
        (self.routes.get(&id) == Some(&self.index)).then_some(scene)
    }

    /// This interface's live scenes, in identifier order: found from the adapter's list of the
    /// interface's scenes, not among every live scene of the core.
    pub fn scenes(&self) -> impl Iterator<Item = (SceneId, &'a Scene)> + 'a {
        self.routes.scenes(self.index, self.state)
    }

    /// The policy of the module of `scene`, one of this interface's scenes.
    #[inline]
    fn policy_of(&self, scene: &Scene) -> Option<Policy> {
        match self.module_policy {
            Some((module, policy)) if scene.module() == *module => Some(policy),
            _ => self.state.policy(scene.module()),
        }
    }

    /// `Ok` unless `id` is live but not this interface's (`[COOP-DEV-ID-REUSE.1]`). An identifier
    /// that is not live is left to the core to judge.
    fn check_owned(&self, id: SceneId) -> Result<(), RtcError> {
        // This interface's own scene, the usual case, is found by its route alone.
        if self.routes.get(&id) == Some(&self.index) || self.state.scene(id).is_none() {
            return Ok(());
        }
        let owner = self
            .routes
            .get(&id)
            .and_then(|index| self.bindings.get(*index))
            .map(|binding| binding.name.clone());
        Err(RtcError::ForeignScene {
            id,
            interface: self.binding.name.clone(),
            owner,
        })
    }

    /// Upstream `isRegistered`: the scene is live and registered through this interface.
    #[must_use]
    pub fn is_registered(&self, id: SceneId) -> bool {
        self.scene(id).is_some()
    }

    /// Upstream `isActivated`: the core's merged decision is activate. `false` for a scene
    /// that is not live, as upstream.
    #[must_use]
    pub fn is_activated(&self, id: SceneId) -> bool {
        self.scene(id).is_some() && self.state.merged_decision(id) == Some(Decision::Activate)
    }

    /// Upstream `isForceActivated`: the core's force-activated flag (`[COOP-DEV-FORCE.1]`).
    #[must_use]
    pub fn is_force_activated(&self, id: SceneId) -> bool {
        self.scene(id).is_some_and(Scene::is_force_activated)
    }

    /// Upstream `isForceDeactivated`: the core's force-deactivated flag (`[COOP-DEV-FORCE.1]`).
    #[must_use]
    pub fn is_force_deactivated(&self, id: SceneId) -> bool {
        self.scene(id).is_some_and(Scene::is_force_deactivated)
    }

    /// Upstream `isRTCEnabled`: the scene waits for the operator rather than proceeding on the
    /// module's judgment (its status's `auto_mode` is false). `None` for a scene that is not
    /// live, where upstream answers its auto-mode flag (`[COOP-DEV-UNKNOWN-QUERY.1]`).
    #[must_use]
    pub fn is_rtc_enabled(&self, id: SceneId) -> Option<bool> {
        // [COOP-DEV-UNKNOWN-QUERY.1]
        self.scene(id)
            .map(|scene| !auto_mode_under(scene, || self.policy_of(scene)))
    }

    /// The four queries above of each of this interface's live scenes, in identifier order,
    /// answered together: each scene's route and its module's policy read once (the policy
    /// once for all of them, where the binding has one module), where asking the four queries
    /// of a scene finds it five times in the core and four among the routes. For a caller that
    /// keeps the answers of all its scenes (the C++ class's copy of them); every answer is the
    /// one the query gives.
    pub fn answers(&self) -> impl Iterator<Item = (SceneId, Answers)> + 'a {
        let view = *self;
        self.scenes().map(move |(id, scene)| {
            let policy = view.policy_of(scene);
            let answers = Answers {
                activated: policy.map(|policy| scene.merged_decision(policy))
                    == Some(Decision::Activate),
                force_activated: scene.is_force_activated(),
                force_deactivated: scene.is_force_deactivated(),
                rtc_enabled: !auto_mode_under(scene, || policy),
            };
            (id, answers)
        })
    }

    /// Upstream `isTerminated`: `Some(true)` once the scene succeeded or failed (the core
    /// retires it, `[COOP-DEV-TERMINAL.1]`), `Some(false)` while it is live or if it was
    /// removed or expired, `None` if this interface never registered it or the core has
    /// forgotten it (`[COOP-DEV-UNKNOWN-QUERY.1]`).
    #[must_use]
    pub fn is_terminated(&self, id: SceneId) -> Option<bool> {
        if self.scene(id).is_some() {
            return Some(false);
        }
        if self.routes.get(&id) != Some(&self.index) {
            return None;
        }
        // [COOP-DEV-UNKNOWN-QUERY.1] [COOP-DEV-TERMINAL.1]
        let retirement = self.state.retirement(id)?;
        Some(matches!(
            retirement.reason,
            RetireReason::Succeeded | RetireReason::Failed
        ))
    }

    /// Upstream `publishCooperateStatus`'s message: this interface's live scenes, in identifier
    /// order, each stamped with its owner's last report (`stamp` less the scene's age).
    #[must_use]
    pub fn cooperate_status_array(&self, stamp: Time) -> CooperateStatusArray {
        CooperateStatusArray {
            stamp,
            statuses: self.cooperate_statuses(stamp).collect(),
        }
    }

    /// The statuses of [`cooperate_status_array`](Self::cooperate_status_array), one by one,
    /// for a caller that builds its own array.
    pub fn cooperate_statuses(&self, stamp: Time) -> impl Iterator<Item = CooperateStatus> + 'a {
        let view = *self;
        self.scenes().map(move |(id, scene)| {
            cooperate_status(view.binding, id, scene, || view.policy_of(scene), stamp)
        })
    }

    /// Upstream's auto-mode status: on when the interface's module policy is optional (every
    /// one of its modules', for an interface that binds several sequences).
    #[must_use]
    pub fn auto_mode_status(&self) -> AutoModeStatus {
        auto_mode_status(self.binding, self.state)
    }
}

/// One RTC interface, to change the core through and to query. Made by [`Rtc::interface`](super::Rtc::interface).
#[derive(Debug)]
pub struct Interface<'a> {
    pub(super) bindings: &'a [Binding],
    pub(super) binding: &'a Binding,
    pub(super) index: usize,
    pub(super) routes: &'a mut Routes,
    pub(super) state: &'a mut cooperation::State,
    pub(super) quota: Option<usize>,
}

impl Interface<'_> {
    /// The same interface, for queries.
    #[must_use]
    pub fn view(&self) -> View<'_> {
        View {
            bindings: self.bindings,
            binding: self.binding,
            index: self.index,
            routes: self.routes,
            state: self.state,
            module_policy: None,
        }
    }

    /// Upstream `updateCooperateStatus`: the owner reports a scene.
    ///
    /// For a live scene of this interface it is the core's `Update` of the scene's module:
    /// `safe` is the module decision (activate when safe), the phase the phase, the distances
    /// the geometry, and `requested` the requested flag. For an identifier that is not live it
    /// is the core's `Register` (`[COOP-DEV-IMPLICIT-REGISTER.1]`) followed, if the phase is not
    /// waiting, by the update to it, applied together, all or none
    /// ([`State::apply_all`](cooperation::State::apply_all), `[COOP-DEV-REGISTER-PHASE.1]`). The
    /// answer lists the transitions.
    ///
    /// A new scene registers in the interface's module; an interface that binds several
    /// sequences (the avoidances: change and return) cannot tell which a new scene is, so its
    /// owner states it in [`StatusReport::sequence`], which picks the scene's core module and so
    /// the policy it is cooperated under (`[COOP-DEV-SEQUENCE.1]`). A scene's module never
    /// changes: reporting a live scene in another sequence than it registered with is the core's
    /// `Update` naming another module, which the core refuses (`WrongModule`,
    /// `[COOP-OWN-MODULE.1]`).
    ///
    /// # Errors
    /// [`RtcError::UnboundSequence`] if the interface does not bind the stated sequence;
    /// [`RtcError::ForeignScene`] if the scene is another interface's;
    /// [`RtcError::SequenceUnstated`] if the scene is not live, the interface binds several
    /// sequences and none is stated; [`RtcError::InitialPhase`] if a new scene cannot start in
    /// the phase; the core's rejection otherwise (`WrongModule` for a live scene of another
    /// sequence, a phase change the lifecycle forbids, a retired identifier);
    /// [`RtcError::SceneQuota`] if the scene is new and the interface holds its quota of live
    /// scenes ([`Rtc::with_scene_quota`](super::Rtc::with_scene_quota)). Nothing changes on an
    /// error.
    pub fn update_cooperate_status(
        &mut self,
        status: &StatusReport,
    ) -> Result<Transitions, RtcError> {
        let id = status.id;
        // [COOP-DEV-SEQUENCE.1]
        let stated = status
            .sequence
            .map(|sequence| self.stated_module(sequence))
            .transpose()?;
        let decision = if status.safe {
            Decision::Activate
        } else {
            Decision::Deactivate
        };
        // RTC statuses carry no detail.
        let report = Report {
            requested: status.requested,
            ..Report::new(
                decision,
                self.binding
                    .geometry(status.start_distance, status.finish_distance),
            )
        };
        let phase = status.phase;
        if let Some(own) = self.state.scene(id).map(Scene::module) {
            self.view().check_owned(id)?;
            // The stated module, if any, goes to the core as it is: a scene of another module is
            // the core's to refuse ([COOP-OWN-MODULE.1]).
            let module = stated.unwrap_or(own);
            let update = Input::Update {
                id,
                module,
                phase,
                report,
            };
            let transition = self.state.apply(&update)?;
            self.routes.retired([&transition]);
            return Ok(transition.into());
        }
        // [COOP-DEV-SEQUENCE.1]
        let module = match stated {
            Some(module) => module,
            None => self
                .binding
                .only_module()
                .ok_or_else(|| RtcError::SequenceUnstated {
                    id,
                    name: self.binding.name.clone(),
                    bound: self.binding.modules().collect(),
                })?,
        };
        // [COOP-DEV-QUOTA.1]
        if let Some(quota) = self.quota {
            let live = self.view().scenes().count();
            if live >= quota {
                return Err(RtcError::SceneQuota {
                    id,
                    interface: self.binding.name.clone(),
                    quota,
                });
            }
        }
        let register = Input::Register {
            id,
            module,
            report: report.clone(),
        };
        // [COOP-DEV-IMPLICIT-REGISTER.1] [COOP-DEV-REGISTER-PHASE.1]
        let transitions = if phase == Phase::Waiting {
            Transitions::from(self.state.apply(&register)?)
        } else {
            let update = Input::Update {
                id,
                module,
                phase,
                report,
            };
            self.state
                .apply_all(&[register, update])
                .map_err(|refused| match refused.index {
                    0 => RtcError::from(*refused.rejection),
                    _ => RtcError::InitialPhase {
                        id,
                        phase,
                        rejection: refused.rejection,
                    },
                })?
                .into()
        };
        self.routes.prune(self.state);
        self.routes.insert(id, self.index, self.state);
        Ok(transitions)
    }

    /// The module of this interface's scenes of `sequence`, if it binds it.
    fn stated_module(&self, sequence: Sequence) -> Result<Module, RtcError> {
        self.binding
            .module(sequence)
            .ok_or_else(|| RtcError::UnboundSequence {
                name: self.binding.name.clone(),
                module: Module::with_sequence(self.binding.behavior, sequence),
                bound: self.binding.modules().collect(),
            })
    }

    /// The module a removal names: a live scene's own (the adapter has checked that it is this
    /// interface's), else any of the interface's, since the core refuses an identifier that is
    /// not live whatever module is named.
    fn removal_module(&self, id: SceneId) -> Option<Module> {
        self.state
            .scene(id)
            .map(Scene::module)
            .or_else(|| self.binding.modules().next())
    }

    /// Upstream `removeCooperateStatus`: the core's `Remove` in the scene's module. The
    /// identifier retires.
    ///
    /// # Errors
    /// [`RtcError::ForeignScene`] if the scene is another interface's; the core's rejection if
    /// the identifier is unknown or retired.
    pub fn remove_cooperate_status(&mut self, id: SceneId) -> Result<Transition, RtcError> {
        self.view().check_owned(id)?;
        let module = self.removal_module(id).ok_or(RtcError::NoSequence {
            name: self.binding.name.clone(),
        })?;
        let transition = self.state.apply(&Input::Remove { id, module })?;
        self.routes.retired([&transition]);
        Ok(transition)
    }

    /// Upstream `clearCooperateStatus`: removes every live scene of this interface, all or
    /// none, and answers their identifiers.
    ///
    /// # Errors
    /// The core's rejection of a removal; then nothing is removed.
    pub fn clear_cooperate_status(&mut self) -> Result<Vec<SceneId>, RtcError> {
        let scenes: Vec<(SceneId, Module)> = self
            .view()
            .scenes()
            .map(|(id, scene)| (id, scene.module()))
            .collect();
        if scenes.is_empty() {
            return Ok(Vec::new());
        }
        let removals: Vec<Input> = scenes
            .iter()
            .map(|&(id, module)| Input::Remove { id, module })
            .collect();
        let transitions = self
            .state
            .apply_all(&removals)
            .map_err(|refused| RtcError::from(*refused.rejection))?;
        self.routes.retired(&transitions);
        Ok(scenes.into_iter().map(|(id, _)| id).collect())
    }

    /// Upstream's `CooperateCommands` service of this interface: the core's `SetCommands`. The
    /// batch applies whole or not at all, so each response is `success = true` exactly when it
    /// applied (`[COOP-DEV-BATCH.1]`); a command naming another interface's scene refuses the
    /// batch, as upstream answers "not found" for it.
    pub fn cooperate_commands(
        &mut self,
        request: &CooperateCommandsRequest,
    ) -> Reply<CooperateCommandsResponse> {
        let (bindings, binding, index) = (self.bindings, self.binding, self.index);
        let routes: &Routes = self.routes;
        apply_commands(self.state, request, |state, id| {
            View {
                bindings,
                binding,
                index,
                routes,
                state,
                module_policy: None,
            }
            .check_owned(id)
        })
    }

    /// Upstream's `AutoMode` service of this interface: the policy of its core module (of each,
    /// for an interface that binds several sequences, `[COOP-DEV-SEQUENCE.1]`), `optional` when
    /// enabled, `required` when not. Operator decisions stand (`[COOP-DEV-POLICY-CLOBBER.1]`),
    /// and every interface of the same core module is switched with it
    /// (`[COOP-DEV-AUTO-MODE-KEY.1]`).
    pub fn auto_mode(&mut self, request: &AutoModeRequest) -> Reply<AutoModeResponse> {
        let result = set_auto_mode(self.state, self.binding.modules().collect(), request.enable);
        Reply {
            response: AutoModeResponse {
                success: result.is_ok(),
            },
            result,
        }
    }
}
