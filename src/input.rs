//! The input alphabet: everything that can change the state, and who sends it.

use crate::{Decision, Geometry, Module, OperatorDecision, Phase, Policy, SceneId};

/// One input to [`State::apply`](crate::State::apply).
///
/// Scene owners (planning modules) send `Register`, `Update` and `Remove`; operators send
/// `SetCommands` and `SetPolicies`; the system clock sends `Tick`.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub enum Input {
    /// A module opens a scene under an identifier it chose (`[COOP-REG-NEW.1]`).
    Register {
        /// The new scene's identifier.
        id: SceneId,
        /// The module the scene belongs to, for ever.
        module: Module,
        /// The module's first decision.
        decision: Decision,
        /// The owner asks for an operator decision whatever the module's policy
        /// (`[COOP-REQUESTED.1]`). Absent in a serialised input means `false`.
        #[cfg_attr(feature = "serde", serde(default))]
        requested: bool,
        /// Where the scene is; its kind (velocity or steering) is fixed from here on.
        geometry: Geometry,
    },
    /// A scene's owner reports its phase, decision and geometry (`[COOP-OWN-UPDATE.1]`).
    Update {
        /// The scene.
        id: SceneId,
        /// The module the owner believes the scene belongs to.
        module: Module,
        /// The phase the owner moves the scene to.
        phase: Phase,
        /// The module's current decision.
        decision: Decision,
        /// Whether the owner asks for an operator decision (`[COOP-REQUESTED.1]`). Absent in a
        /// serialised input means `false`.
        #[cfg_attr(feature = "serde", serde(default))]
        requested: bool,
        /// The scene's current geometry.
        geometry: Geometry,
    },
    /// A scene's owner drops the scene (`[COOP-OWN-REMOVE.1]`).
    Remove {
        /// The scene.
        id: SceneId,
        /// The module the owner believes the scene belongs to.
        module: Module,
    },
    /// The AD API `set_commands` call: operator decisions for scenes, all or none
    /// (`[COOP-CMD-APPLY.1]`).
    SetCommands {
        /// The commands, in request order.
        commands: Vec<Command>,
    },
    /// The AD API `set_policies` call: policies for modules, all or none (`[COOP-POL-SET.1]`).
    SetPolicies {
        /// The policies, in request order.
        policies: Vec<PolicySetting>,
    },
    /// Time passed (`[COOP-TIME-AGE.1]`). The caller measures it; the core reads no clock.
    Tick {
        /// How much time passed since the previous tick, in milliseconds.
        elapsed_ms: u64,
    },
}

/// One operator command: an operator decision for the scene with this identifier.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Command {
    /// The scene.
    pub id: SceneId,
    /// The operator's decision; `Undecided` withdraws an earlier one (`[COOP-CMD-APPLY.1]`).
    pub decision: OperatorDecision,
}

/// One policy setting: the cooperation policy for a module.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct PolicySetting {
    /// The module.
    pub module: Module,
    /// Its new policy.
    pub policy: Policy,
}
