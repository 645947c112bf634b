//! Inputs and identifiers in words, for traces, the checker's action names and reports.

use cooperation::{Input, SceneId};

/// A scene identifier as the model's small number.
#[must_use]
pub fn short(id: SceneId) -> String {
    let value = id.to_u128();
    format!("#{value}")
}

/// How a trace says that an owner asks for an operator decision.
const fn asks(requested: bool) -> &'static str {
    if requested {
        ", asks the operator"
    } else {
        ""
    }
}

/// One input in words.
#[must_use]
pub fn describe(input: &Input) -> String {
    match input {
        Input::Register {
            id,
            module,
            decision,
            requested,
            geometry,
        } => {
            format!(
                "owner registers {} for {module} ({decision}{}, {:?})",
                short(*id),
                asks(*requested),
                geometry.kind()
            )
        }
        Input::Update {
            id,
            module,
            phase,
            decision,
            requested,
            geometry,
        } => format!(
            "owner of {module} updates {}: {phase}, {decision}{} ({:?})",
            short(*id),
            asks(*requested),
            geometry.kind()
        ),
        Input::Remove { id, module } => format!("owner of {module} removes {}", short(*id)),
        Input::SetCommands { commands } => {
            let list: Vec<String> = commands
                .iter()
                .map(|c| format!("{} {}", short(c.id), c.decision))
                .collect();
            format!("operator set_commands [{}]", list.join(", "))
        }
        Input::SetPolicies { policies } => {
            let list: Vec<String> = policies
                .iter()
                .map(|p| format!("{} {}", p.module, p.policy))
                .collect();
            format!("operator set_policies [{}]", list.join(", "))
        }
        Input::Tick { elapsed_ms } => format!("time passes ({elapsed_ms} tick)"),
    }
}
