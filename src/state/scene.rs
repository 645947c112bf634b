//! A live scene: what the rules read and write.

use super::policies::Slot;
use crate::{merge, Decision, Detail, Geometry, Module, OperatorDecision, Phase, Policy};

/// A live scene: what the rules read and write.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Scene {
    pub(super) module: Module,
    pub(super) phase: Phase,
    pub(super) module_decision: Decision,
    pub(super) operator_decision: OperatorDecision,
    pub(super) requested: bool,
    pub(super) age_ms: u64,
    pub(super) geometry: Geometry,
    /// Absent in a serialised state means empty.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Detail::is_empty")
    )]
    pub(super) detail: Detail,
    /// Where the module's policy is kept; invisible to equality, order, hash and serde.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(super) slot: Slot,
}

impl core::fmt::Debug for Scene {
    /// Every field but the policy's place, which is the module's.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Scene")
            .field("module", &self.module)
            .field("phase", &self.phase)
            .field("module_decision", &self.module_decision)
            .field("operator_decision", &self.operator_decision)
            .field("requested", &self.requested)
            .field("age_ms", &self.age_ms)
            .field("geometry", &self.geometry)
            .field("detail", &self.detail)
            .finish()
    }
}

impl Scene {
    /// The module the scene belongs to, for ever.
    #[must_use]
    pub const fn module(&self) -> Module {
        self.module
    }

    /// The lifecycle phase; never terminal for a live scene.
    #[must_use]
    pub const fn phase(&self) -> Phase {
        self.phase
    }

    /// The module decision, as last reported by the owner.
    #[must_use]
    pub const fn module_decision(&self) -> Decision {
        self.module_decision
    }

    /// The operator decision; `Undecided` until an operator command sets it.
    #[must_use]
    pub const fn operator_decision(&self) -> OperatorDecision {
        self.operator_decision
    }

    /// Whether the owner asks for an operator decision (`[COOP-REQUESTED.1]`): an undecided
    /// scene is then held back whatever its module's policy.
    #[must_use]
    pub const fn is_requested(&self) -> bool {
        self.requested
    }

    /// The policy that applies to this scene: `required` if the owner asks for an operator
    /// decision, else its module's policy (`[COOP-REQUESTED.1]`).
    #[must_use]
    pub const fn effective_policy(&self, module_policy: Policy) -> Policy {
        if self.requested {
            Policy::Required
        } else {
            module_policy
        }
    }

    /// Time since the owner last registered or updated the scene, at most the time-to-live.
    #[must_use]
    pub const fn age_ms(&self) -> u64 {
        self.age_ms
    }

    /// The geometry last reported.
    #[must_use]
    pub const fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The owner's text for the operator, as last reported; its factor carries it.
    #[must_use]
    pub const fn detail(&self) -> &Detail {
        &self.detail
    }

    /// Whether operator commands are accepted (`[COOP-CANCELLABLE.1]`).
    #[must_use]
    pub const fn is_cancellable(&self) -> bool {
        self.phase.is_cancellable()
    }

    /// The merged decision under the module's policy (`[COOP-MERGE.1]`), with the policy
    /// made `required` for a requested scene (`[COOP-REQUESTED.1]`). A scene does not hold its
    /// module's policy: [`State::merged_decision`](crate::State::merged_decision) and
    /// [`State::merged_decisions`](crate::State::merged_decisions) look it up.
    #[must_use]
    pub const fn merged_decision(&self, module_policy: Policy) -> Decision {
        merge(
            self.operator_decision,
            self.effective_policy(module_policy),
            self.module_decision,
        )
    }

    /// Whether the scene waits for an operator: it takes commands, no operator has decided, and
    /// the policy that applies to it is `required`, so its merged decision is deactivate until
    /// one does (`[COOP-MERGE.1]`, `[COOP-REQUESTED.1]`). What an operator interface highlights.
    ///
    /// ```
    /// use cooperation::*;
    ///
    /// let lane_change = Module::new(Behavior::LaneChange);
    /// let mut state = State::new(Config::new([(lane_change, Policy::Required)]))?;
    /// let id = SceneId::from_u128(1);
    /// let report = Report::new(Decision::Activate, Geometry::velocity(30.0));
    /// state.apply(&Input::Register { id, module: lane_change, report })?;
    /// assert_eq!(state.awaits_operator(id), Some(true));
    /// let command = Command { id, decision: OperatorDecision::Activate };
    /// state.apply(&Input::SetCommands { commands: vec![command] })?;
    /// assert_eq!(state.awaits_operator(id), Some(false));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[must_use]
    pub const fn awaits_operator(&self, module_policy: Policy) -> bool {
        self.phase.is_cancellable()
            && matches!(self.operator_decision, OperatorDecision::Undecided)
            && matches!(self.effective_policy(module_policy), Policy::Required)
    }

    /// The operator activated what the module would not, or would not decide on its own
    /// (`[COOP-FORCE-ACTIVATED.1]`).
    #[must_use]
    pub const fn is_force_activated(&self) -> bool {
        self.phase.is_cancellable()
            && matches!(self.operator_decision, OperatorDecision::Activate)
            && (matches!(self.module_decision, Decision::Deactivate) || self.requested)
    }

    /// The operator deactivated a running scene the module would go on with
    /// (`[COOP-FORCE-DEACTIVATED.1]`).
    #[must_use]
    pub const fn is_force_deactivated(&self) -> bool {
        matches!(self.phase, Phase::Running)
            && matches!(self.operator_decision, OperatorDecision::Deactivate)
            && matches!(self.module_decision, Decision::Activate)
    }
}
