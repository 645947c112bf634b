//! Versions of the trace format, and reading a version-1 line.
//!
//! Version 2 writes the spec's and the AD API's words for every value (`"lane-change"`, `""`,
//! `"activate"`, `"none"`, `"waiting"`, `"optional"`, `"left"`, `"removed"`); version 1 wrote
//! the library's Rust variant names (`"LaneChange"`, `"Empty"`, `"Activate"`, `"Undecided"`,
//! `"WaitingForExecution"`, `"Optional"`, `"Left"`, `"Removed"`). Nothing else differs. A
//! trace is version 1 unless its first record is `{"version": 2}`.

use std::collections::BTreeMap;
use std::sync::OnceLock;

use cooperation::{
    Behavior, Decision, Direction, OperatorDecision, Phase, Policy, RetireReason, Sequence,
    SteeringStatus, VelocityStatus,
};
use serde::Serialize;
use serde_json::Value;

use crate::json::from_json;
use crate::ErrorKind;

/// A version of the trace format.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub enum Version {
    /// Values in the library's Rust variant names. A trace without a version record.
    #[default]
    V1,
    /// Values in the spec's and the AD API's words; what the tools write.
    V2,
}

impl Version {
    /// The version the tools write.
    pub const CURRENT: Self = Self::V2;

    /// The number in a version record.
    #[must_use]
    pub const fn number(self) -> u64 {
        match self {
            Self::V1 => 1,
            Self::V2 => 2,
        }
    }

    /// The version numbered `number`, if this reader knows it.
    #[must_use]
    pub const fn from_number(number: u64) -> Option<Self> {
        match number {
            1 => Some(Self::V1),
            2 => Some(Self::V2),
            _ => None,
        }
    }

    /// The version record, as a line: `{"version": 2}`.
    #[must_use]
    pub fn record(self) -> String {
        format!("{{\"version\": {}}}", self.number())
    }
}

/// Every version-1 word and its version-2 spelling: each built-in value of every type whose
/// serde form changed, by its Rust variant name then (as version 2 writes it) its serde form.
fn words() -> &'static BTreeMap<String, String> {
    static WORDS: OnceLock<BTreeMap<String, String>> = OnceLock::new();
    WORDS.get_or_init(|| {
        let mut words = BTreeMap::new();
        let mut add = |old: String, new: Value| {
            if let Value::String(new) = new {
                words.insert(old, new);
            }
        };
        fn pairs<T: Serialize + core::fmt::Debug>(values: &[T]) -> Vec<(String, Value)> {
            values
                .iter()
                .map(|value| {
                    let new = serde_json::to_value(value).unwrap_or(Value::Null);
                    (format!("{value:?}"), new)
                })
                .collect()
        }
        let all = [
            pairs(&Behavior::ALL),
            pairs(&Sequence::ALL),
            pairs(&Decision::ALL),
            pairs(&OperatorDecision::ALL),
            pairs(&Policy::ALL),
            pairs(&Phase::ALL),
            pairs(&[
                VelocityStatus::Unknown,
                VelocityStatus::Approaching,
                VelocityStatus::Stopped,
            ]),
            pairs(&[SteeringStatus::Approaching, SteeringStatus::Turning]),
            pairs(&[
                RetireReason::Succeeded,
                RetireReason::Failed,
                RetireReason::Removed,
                RetireReason::Expired,
            ]),
            pairs(&[
                Direction::Unknown,
                Direction::Left,
                Direction::Right,
                Direction::Straight,
            ]),
        ];
        for (old, new) in all.into_iter().flatten() {
            add(old, new);
        }
        // The phase's Rust name changed too.
        add("WaitingForExecution".to_owned(), Value::from("waiting"));
        words
    })
}

/// A version-1 record line in version 2's words: every string value that is a version-1
/// word, except a scene's identifier and an owner's free-text `detail`; `None` if it has no
/// version-1 word. The line given back has its keys sorted, so an error's column is in that
/// line.
///
/// # Errors
/// The line is not JSON, or gives a key twice.
pub(crate) fn upgrade_v1(text: &str) -> Result<Option<String>, ErrorKind> {
    let mut value: Value = from_json(text, true)?;
    Ok(upgrade(&mut value, None).then(|| value.to_string()))
}

/// Upgrades the words in `value`, whose key is `key`; whether any changed.
fn upgrade(value: &mut Value, key: Option<&str>) -> bool {
    match value {
        Value::String(text) if !matches!(key, Some("id" | "detail")) => {
            words().get(text.as_str()).is_some_and(|new| {
                new.clone_into(text);
                true
            })
        }
        Value::Array(items) => items
            .iter_mut()
            .fold(false, |changed, item| upgrade(item, key) | changed),
        Value::Object(fields) => fields.iter_mut().fold(false, |changed, (name, field)| {
            upgrade(field, Some(name)) | changed
        }),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_changed_word_is_upgraded_and_nothing_else() {
        let words = words();
        assert_eq!(words["LaneChange"], "lane-change");
        assert_eq!(words["Empty"], "");
        assert_eq!(words["Undecided"], "none");
        assert_eq!(words["WaitingForExecution"], "waiting");
        assert_eq!(words["Optional"], "optional");
        assert_eq!(words["Turning"], "turning");
        assert!(!words.contains_key("Register") && !words.contains_key("Velocity"));
        let line = r#"{"input": {"Register": {"id": "Activate", "module": {"behavior": "LaneChange", "sequence": "Empty"}, "decision": "Activate", "detail": "Activate"}}}"#;
        assert_eq!(
            upgrade_v1(line).unwrap().unwrap(),
            r#"{"input":{"Register":{"decision":"activate","detail":"Activate","id":"Activate","module":{"behavior":"lane-change","sequence":""}}}}"#
        );
    }

    #[test]
    fn a_line_without_version_1_words_is_left_as_it_is() {
        let line = r#"{"at_ms": 5, "input": {"Remove": {"id": "x", "module": {"behavior": "lane-change", "sequence": ""}}}}"#;
        assert_eq!(upgrade_v1(line), Ok(None));
    }

    #[test]
    fn version_numbers() {
        assert_eq!(Version::from_number(2), Some(Version::CURRENT));
        assert_eq!(Version::from_number(1), Some(Version::V1));
        assert_eq!(Version::from_number(3), None);
        assert_eq!(Version::V2.record(), r#"{"version": 2}"#);
    }
}
