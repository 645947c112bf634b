//! Inputs and identifiers in words, for traces, the checker's action names and reports.

use cooperation::{Input, SceneId};

/// A scene identifier as the model's small number.
#[must_use]
pub fn short(id: SceneId) -> String {
    let value = id.to_u128();
    format!("#{value}")
}

/// One input in words, identifiers as the model's small numbers ([`Input::describe_with`]).
#[must_use]
pub fn describe(input: &Input) -> String {
    input.describe_with(short).to_string()
}
