//! The serialised form of [`Input`](super::Input): an owner's report is written flat, beside
//! the scene's identifier and module, as it was before the report had a type of its own.
//!
//! Serde cannot flatten a struct into a variant that refuses unknown fields, so the form is
//! this enum, converted both ways without loss.

use super::{Command, PolicySetting, Report};
use crate::{Decision, Geometry, Module, Phase, SceneId};

/// [`super::Input`] with each report's fields spelled out. Named `Input` so that serde's
/// messages name the type a reader knows.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum Input {
    Register {
        id: SceneId,
        module: Module,
        decision: Decision,
        #[serde(default)]
        requested: bool,
        geometry: Geometry,
    },
    Update {
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        #[serde(default)]
        requested: bool,
        geometry: Geometry,
    },
    Remove {
        id: SceneId,
        module: Module,
    },
    SetCommands {
        commands: Vec<Command>,
    },
    SetPolicies {
        policies: Vec<PolicySetting>,
    },
    Tick {
        elapsed_ms: u64,
    },
}

impl From<Input> for super::Input {
    fn from(form: Input) -> Self {
        match form {
            Input::Register {
                id,
                module,
                decision,
                requested,
                geometry,
            } => Self::Register {
                id,
                module,
                report: Report {
                    decision,
                    requested,
                    geometry,
                },
            },
            Input::Update {
                id,
                module,
                phase,
                decision,
                requested,
                geometry,
            } => Self::Update {
                id,
                module,
                phase,
                report: Report {
                    decision,
                    requested,
                    geometry,
                },
            },
            Input::Remove { id, module } => Self::Remove { id, module },
            Input::SetCommands { commands } => Self::SetCommands { commands },
            Input::SetPolicies { policies } => Self::SetPolicies { policies },
            Input::Tick { elapsed_ms } => Self::Tick { elapsed_ms },
        }
    }
}

impl From<super::Input> for Input {
    fn from(input: super::Input) -> Self {
        match input {
            super::Input::Register { id, module, report } => Self::Register {
                id,
                module,
                decision: report.decision,
                requested: report.requested,
                geometry: report.geometry,
            },
            super::Input::Update {
                id,
                module,
                phase,
                report,
            } => Self::Update {
                id,
                module,
                phase,
                decision: report.decision,
                requested: report.requested,
                geometry: report.geometry,
            },
            super::Input::Remove { id, module } => Self::Remove { id, module },
            super::Input::SetCommands { commands } => Self::SetCommands { commands },
            super::Input::SetPolicies { policies } => Self::SetPolicies { policies },
            super::Input::Tick { elapsed_ms } => Self::Tick { elapsed_ms },
        }
    }
}
