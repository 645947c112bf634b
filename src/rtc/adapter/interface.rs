//! One RTC interface's calls (`rtc_interface`'s methods for one module): [`Interface`] to
//! change the core through, [`View`] to query it.

use std::collections::BTreeMap;

use crate::ros::path::FieldPath;
use crate::rtc::{
    AutoModeRequest, AutoModeResponse, AutoModeStatus, Binding, CooperateCommandsRequest,
    CooperateCommandsResponse, CooperateStatusArray, FieldError, RtcError, Time,
};
use crate::{Decision, Input, Phase, Report, RetireReason, Scene, SceneId, Transition};

use super::{
    apply_commands, auto_mode, auto_mode_status, cooperate_status, prune, set_auto_mode, Reply,
};

/// One RTC interface, for queries. Made by [`Rtc::view`](super::Rtc::view).
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    pub(super) bindings: &'a [Binding],
    pub(super) binding: &'a Binding,
    pub(super) index: usize,
    pub(super) routes: &'a BTreeMap<SceneId, usize>,
    pub(super) state: &'a crate::State,
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

    /// `Ok` unless `id` is live but not this interface's (`[COOP-DEV-ID-REUSE.1]`). An identifier
    /// that is not live is left to the core to judge.
    fn check_owned(&self, id: SceneId) -> Result<(), RtcError> {
        if self.state.scene(id).is_none() || self.scene(id).is_some() {
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
        self.scene(id).map(|scene| !auto_mode(scene, self.state))
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
            statuses: self
                .state
                .scenes()
                .filter(|(id, _)| self.routes.get(id) == Some(&self.index))
                .map(|(id, scene)| cooperate_status(self.binding, id, scene, self.state, stamp))
                .collect(),
        }
    }

    /// Upstream's auto-mode status: on when the interface's module policy is optional.
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
    pub(super) routes: &'a mut BTreeMap<SceneId, usize>,
    pub(super) state: &'a mut crate::State,
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
        }
    }

    /// Upstream `updateCooperateStatus`: the owner reports a scene.
    ///
    /// For a live scene of this interface it is the core's `Update`: `safe` is the module
    /// decision (activate when safe), `state` the phase, the distances the geometry, and
    /// `requested` the requested flag. For an identifier that is not live it is the core's
    /// `Register` (`[COOP-DEV-IMPLICIT-REGISTER.1]`), followed, if `state` is not waiting, by the
    /// update to it, as one step (`[COOP-DEV-REGISTER-PHASE.1]`). The answer lists the
    /// transitions.
    ///
    /// # Errors
    /// [`RtcError::Field`] if `state` is none of `State`'s constants (`[COOP-DEV-CONSTANTS.1]`);
    /// [`RtcError::ForeignScene`] if the scene is another interface's;
    /// [`RtcError::InitialPhase`] if a new scene cannot start in `state`; the core's rejection
    /// otherwise (for example a phase change the lifecycle forbids, or a retired identifier).
    /// Nothing changes on an error.
    pub fn update_cooperate_status(
        &mut self,
        id: SceneId,
        safe: bool,
        state: u8,
        start_distance: f32,
        finish_distance: f32,
        requested: bool,
    ) -> Result<Vec<Transition>, RtcError> {
        // [COOP-DEV-CONSTANTS.1]
        let phase = crate::rtc::State::new(state)
            .phase()
            .map_err(|e| FieldError {
                field: FieldPath::field("state"),
                ..e
            })?;
        let decision = if safe {
            Decision::Activate
        } else {
            Decision::Deactivate
        };
        // RTC statuses carry no detail.
        let report = Report {
            requested,
            ..Report::new(
                decision,
                self.binding.geometry(start_distance, finish_distance),
            )
        };
        let module = self.binding.module;
        let register = Input::Register {
            id,
            module,
            report: report.clone(),
        };
        let update = Input::Update {
            id,
            module,
            phase,
            report,
        };
        if self.state.scene(id).is_some() {
            self.view().check_owned(id)?;
            return Ok(vec![self.state.apply(&update)?]);
        }
        // [COOP-DEV-IMPLICIT-REGISTER.1] [COOP-DEV-REGISTER-PHASE.1]
        let transitions = if phase == Phase::Waiting {
            vec![self.state.apply(&register)?]
        } else {
            // Both inputs on a copy, so that a refused second one leaves nothing behind.
            let mut next = self.state.clone();
            let first = next.apply(&register)?;
            let second = next
                .apply(&update)
                .map_err(|rejection| RtcError::InitialPhase {
                    id,
                    phase,
                    rejection: Box::new(rejection),
                })?;
            *self.state = next;
            vec![first, second]
        };
        prune(self.routes, self.state);
        self.routes.insert(id, self.index);
        Ok(transitions)
    }

    /// Upstream `removeCooperateStatus`: the core's `Remove`. The identifier retires.
    ///
    /// # Errors
    /// [`RtcError::ForeignScene`] if the scene is another interface's; the core's rejection if
    /// the identifier is unknown or retired.
    pub fn remove_cooperate_status(&mut self, id: SceneId) -> Result<Transition, RtcError> {
        self.view().check_owned(id)?;
        let module = self.binding.module;
        Ok(self.state.apply(&Input::Remove { id, module })?)
    }

    /// Upstream `clearCooperateStatus`: removes every live scene of this interface, all or
    /// none, and answers their identifiers.
    ///
    /// # Errors
    /// The core's rejection of a removal; then nothing is removed.
    pub fn clear_cooperate_status(&mut self) -> Result<Vec<SceneId>, RtcError> {
        let ids: Vec<SceneId> = self
            .state
            .scenes()
            .map(|(id, _)| id)
            .filter(|id| self.routes.get(id) == Some(&self.index))
            .collect();
        if ids.is_empty() {
            return Ok(ids);
        }
        let module = self.binding.module;
        let mut next = self.state.clone();
        for id in &ids {
            next.apply(&Input::Remove { id: *id, module })?;
        }
        *self.state = next;
        Ok(ids)
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
        let routes: &BTreeMap<SceneId, usize> = self.routes;
        apply_commands(self.state, request, |state, id| {
            View {
                bindings,
                binding,
                index,
                routes,
                state,
            }
            .check_owned(id)
        })
    }

    /// Upstream's `AutoMode` service of this interface: the policy of its core module,
    /// `optional` when enabled, `required` when not. Operator decisions stand
    /// (`[COOP-DEV-POLICY-CLOBBER.1]`), and every interface of the same core module is switched
    /// with it (`[COOP-DEV-AUTO-MODE-KEY.1]`).
    pub fn auto_mode(&mut self, request: &AutoModeRequest) -> Reply<AutoModeResponse> {
        let result = set_auto_mode(self.state, [self.binding.module].into(), request.enable);
        Reply {
            response: AutoModeResponse {
                success: result.is_ok(),
            },
            result,
        }
    }
}
