//! The serialised form of [`Input`](super::Input): an owner's report is written flat, beside
//! the scene's identifier and module, as it was before the report had a type of its own.
//!
//! Serde cannot flatten a struct into a variant that refuses unknown fields, so the form is
//! this enum, converted both ways without loss. An empty `detail` is left out, so traces
//! written before reports had one read and write as they did.

use super::{Command, PolicySetting, Report};
use crate::{Decision, Detail, Geometry, Module, Phase, SceneId};

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
        #[serde(default, skip_serializing_if = "Detail::is_empty")]
        detail: Detail,
    },
    Update {
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        #[serde(default)]
        requested: bool,
        geometry: Geometry,
        #[serde(default, skip_serializing_if = "Detail::is_empty")]
        detail: Detail,
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
                detail,
            } => Self::Register {
                id,
                module,
                report: Report {
                    decision,
                    requested,
                    geometry,
                    detail,
                },
            },
            Input::Update {
                id,
                module,
                phase,
                decision,
                requested,
                geometry,
                detail,
            } => Self::Update {
                id,
                module,
                phase,
                report: Report {
                    decision,
                    requested,
                    geometry,
                    detail,
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
                detail: report.detail,
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
                detail: report.detail,
            },
            super::Input::Remove { id, module } => Self::Remove { id, module },
            super::Input::SetCommands { commands } => Self::SetCommands { commands },
            super::Input::SetPolicies { policies } => Self::SetPolicies { policies },
            super::Input::Tick { elapsed_ms } => Self::Tick { elapsed_ms },
        }
    }
}
