//! Reading `spec/cooperation.md`'s tables, shared by the tests that check them against the code.
#![allow(dead_code, unreachable_pub)]

use cooperation::{Decision, OperatorDecision, Phase, Policy};

pub fn spec() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../spec/cooperation.md"
    ))
    .expect("spec/cooperation.md is readable")
}

/// The spec's text reader, shared with the model checker (one reader of the spec).
#[path = "../../models/src/model/spec/text.rs"]
pub mod spec_text;

/// The rows of the first table whose header row starts with `header`, as trimmed cells.
pub fn table(spec: &str, header: &str) -> Vec<Vec<String>> {
    spec_text::table_rows(spec, header)
        .unwrap_or_else(|| panic!("no table starting {header:?}, with its separator, in the spec"))
        .into_iter()
        .map(|row| row.into_iter().map(str::to_owned).collect())
        .collect()
}

/// A decision word of the spec, `None` for `-` ("any value").
pub fn decision(word: &str) -> Option<Decision> {
    match word {
        "deactivate" => Some(Decision::Deactivate),
        "activate" => Some(Decision::Activate),
        "-" => None,
        other => panic!("not a decision: {other:?}"),
    }
}

pub fn operator(word: &str) -> OperatorDecision {
    OperatorDecision::ALL
        .into_iter()
        .find(|o| o.as_str() == word)
        .unwrap_or_else(|| panic!("not an operator decision: {word:?}"))
}

pub fn policy(word: &str) -> Option<Policy> {
    if word == "-" {
        return None;
    }
    Some(
        Policy::ALL
            .into_iter()
            .find(|p| p.as_str() == word)
            .unwrap_or_else(|| panic!("not a policy: {word:?}")),
    )
}

pub fn phase(word: &str) -> Phase {
    Phase::ALL
        .into_iter()
        .find(|p| p.as_str() == word)
        .unwrap_or_else(|| panic!("not a phase: {word:?}"))
}

/// The values a cell stands for: itself, or every value for `-`.
pub fn expand<T: Copy>(cell: Option<T>, all: &[T]) -> Vec<T> {
    cell.map_or_else(|| all.to_vec(), |value| vec![value])
}
