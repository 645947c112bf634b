//! Counterexamples and witnesses as data: saved as JSON, replayed, and printed as numbered
//! traces a person can follow.

use core::fmt::Write as _;

use cooperation::{Input, Rule};
use serde::{Deserialize, Serialize};

use crate::sequential::{Bounds, ModelError, SequentialModel, Step};
use crate::Fault;

/// A path found by the checker: the model it is for, the property, and the inputs from the
/// initial state. Replaying the inputs through the model reproduces it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Trace {
    /// The model's bounds.
    pub bounds: Bounds,
    /// The injected fault, if the run was a sensitivity test.
    pub fault: Option<Fault>,
    /// The property the trace breaks (or, for a `sometimes` property, reaches).
    pub property: String,
    /// The inputs, in order.
    pub inputs: Vec<Input>,
}

/// Why a trace could not be replayed.
#[derive(Debug)]
pub enum ReplayError {
    /// The model could not be built.
    Model(ModelError),
    /// No property has the trace's name.
    UnknownProperty(String),
}

impl core::fmt::Display for ReplayError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Model(error) => error.fmt(f),
            Self::UnknownProperty(name) => write!(f, "no property is named {name:?}"),
        }
    }
}

impl std::error::Error for ReplayError {}

impl Trace {
    /// The model the trace is for.
    ///
    /// # Errors
    /// If the bounds are invalid.
    pub fn model(&self) -> Result<SequentialModel, ReplayError> {
        let model = SequentialModel::new(self.bounds).map_err(ReplayError::Model)?;
        Ok(match self.fault {
            Some(fault) => model.with_fault(fault),
            None => model,
        })
    }

    /// Every step of the trace, the initial state first.
    ///
    /// # Errors
    /// If the model cannot be built.
    pub fn replay(&self) -> Result<Vec<Step>, ReplayError> {
        let model = self.model()?;
        let first = model
            .initial()
            .map_err(|e| ReplayError::Model(ModelError::Bounds(e.to_string())))?;
        let mut steps = vec![first];
        for input in &self.inputs {
            let next = steps.last().map(|last| model.step(last, input));
            steps.extend(next);
        }
        Ok(steps)
    }

    /// Whether the property holds in the trace's last state.
    ///
    /// # Errors
    /// If the model cannot be built or the property is unknown.
    pub fn holds_at_end(&self) -> Result<bool, ReplayError> {
        let model = self.model()?;
        let property = crate::sequential::properties()
            .into_iter()
            .find(|p| p.name == self.property)
            .ok_or_else(|| ReplayError::UnknownProperty(self.property.clone()))?;
        let steps = self.replay()?;
        Ok(steps
            .last()
            .is_some_and(|last| (property.condition)(&model, last)))
    }

    /// The trace as numbered steps: the input, the rule that fired or rejected it, and every
    /// live scene's merged decision afterwards.
    ///
    /// # Errors
    /// If the model cannot be built.
    pub fn render(&self) -> Result<String, ReplayError> {
        let model = self.model()?;
        let steps = self.replay()?;
        let mut out = String::new();
        let _ = writeln!(out, "{}", self.property);
        for (n, (input, step)) in self.inputs.iter().zip(steps.iter().skip(1)).enumerate() {
            let rule = step.last.map_or("-", Rule::tag);
            let verdict = if step.last.is_some_and(Rule::is_rejection) {
                "rejected by"
            } else {
                "fired"
            };
            let _ = writeln!(out, "{:>3}. {}", n + 1, describe(input));
            let _ = writeln!(out, "     {verdict} {rule}");
            let mut merged = Vec::new();
            for (id, scene) in step.core.scenes() {
                let decision = model
                    .merged_decision(&step.core, id)
                    .map_or("none", |d| d.as_str());
                merged.push(format!(
                    "{} {} {} [module {}, operator {}, policy {}] -> {decision}",
                    short(id),
                    scene.module(),
                    scene.phase(),
                    scene.module_decision(),
                    scene.operator_decision(),
                    step.core.policy(scene.module()).map_or("-", |p| p.as_str()),
                ));
            }
            if merged.is_empty() {
                merged.push("no live scene".into());
            }
            for line in merged {
                let _ = writeln!(out, "     {line}");
            }
        }
        Ok(out)
    }
}

/// A scene identifier as the model's small number.
fn short(id: cooperation::SceneId) -> String {
    let value = u128::from_be_bytes(*id.as_bytes());
    format!("#{value}")
}

/// One input in words.
#[must_use]
pub fn describe(input: &Input) -> String {
    match input {
        Input::Register {
            id,
            module,
            decision,
            geometry,
        } => {
            format!(
                "owner registers {} for {module} ({decision}, {:?})",
                short(*id),
                geometry.kind()
            )
        }
        Input::Update {
            id,
            module,
            phase,
            decision,
            geometry,
        } => format!(
            "owner of {module} updates {}: {phase}, {decision} ({:?})",
            short(*id),
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
