//! Errors of values: types, names, policies and limits. Each test checks the line, the
//! column, the key path, the kind and the message.

use super::*;
use cooperation::{ConfigError, InvalidName, Limits, NameProblem};
use cooperation_adapters::settings::{Expected, Found};

fn wrong(expected: Expected, found: Found) -> SettingsErrorKind {
    SettingsErrorKind::WrongType { expected, found }
}

#[test]
fn a_policy_of_another_type_is_refused() {
    let expected = "expected a policy (`optional` or `required`), or a map from sequences to \
                    policies";
    for (value, found, shown) in [
        ("1", Found::Integer, "a whole number"),
        ("0.5", Found::Float, "a floating-point number"),
        ("true", Found::Bool, "a boolean"),
        ("~", Found::Null, "null"),
        ("[optional]", Found::List, "a list"),
    ] {
        refused(
            &policies(&[&format!("        lane-change: {value}")]),
            (5, 22),
            &format!("{POLICIES}.lane-change"),
            &wrong(Expected::PolicyOrSequences, found),
            &format!("{expected}, found {shown}"),
        );
    }
    // Nothing after the colon is null, found where the value would be.
    refused(
        &policies(&["        lane-change:", "        merge: optional"]),
        (5, 20),
        &format!("{POLICIES}.lane-change"),
        &wrong(Expected::PolicyOrSequences, Found::Null),
        &format!("{expected}, found null"),
    );
    // A sequence takes a policy only.
    refused(
        &policies(&["        avoidance:", "          change: {left: optional}"]),
        (6, 19),
        &format!("{POLICIES}.avoidance.change"),
        &wrong(Expected::Policy, Found::Map),
        "expected a policy (`optional` or `required`), found a map",
    );
    refused(
        &policies(&["        avoidance:", "          change: 2"]),
        (6, 19),
        &format!("{POLICIES}.avoidance.change"),
        &wrong(Expected::Policy, Found::Integer),
        "expected a policy (`optional` or `required`), found a whole number",
    );
    // A dotted key below a sequence would make the sequence a map.
    refused(
        &policies(&["        avoidance.change.left: optional"]),
        (5, 9),
        &format!("{POLICIES}.avoidance.change.left"),
        &wrong(Expected::Policy, Found::Map),
        "expected a policy (`optional` or `required`), found a map",
    );
}

#[test]
fn a_limit_of_another_type_is_refused() {
    for (value, found, shown) in [
        ("\"10\"", Found::String, "a string"),
        ("ten", Found::String, "a string"),
        ("10_000", Found::String, "a string"),
        ("1e4", Found::Float, "a floating-point number"),
        ("true", Found::Bool, "a boolean"),
        ("{}", Found::Map, "a map"),
        ("[10]", Found::List, "a list"),
    ] {
        refused(
            &policies(&[
                "        merge: optional",
                "      limits:",
                &format!("        max_batch: {value}"),
            ]),
            (7, 20),
            &format!("{LIMITS}.max_batch"),
            &wrong(Expected::Integer, found),
            &format!("expected a whole number, found {shown}"),
        );
    }
    refused(
        &policies(&["        merge: optional", "      limits.ttl_ms.seconds: 1"]),
        (6, 7),
        &format!("{LIMITS}.ttl_ms.seconds"),
        &wrong(Expected::Integer, Found::Map),
        "expected a whole number, found a map",
    );
}

#[test]
fn a_map_of_another_type_is_refused() {
    refused(
        "- /**\n",
        (1, 1),
        "",
        &wrong(Expected::Map, Found::List),
        "expected a map, found a list",
    );
    refused(
        "/**: cooperation\n",
        (1, 6),
        "/**",
        &wrong(Expected::Map, Found::String),
        "expected a map, found a string",
    );
    refused(
        "/**:\n  ros__parameters:\n",
        (2, 18),
        "/**.ros__parameters",
        &wrong(Expected::Map, Found::Null),
        "expected a map, found null",
    );
    refused(
        &lines(&["/**:", "  ros__parameters:", "    cooperation: required"]),
        (3, 18),
        "/**.ros__parameters.cooperation",
        &wrong(Expected::Map, Found::String),
        "expected a map, found a string",
    );
    refused(
        &cooperation(&["      policies:", "        - lane-change"]),
        (5, 9),
        POLICIES,
        &wrong(Expected::Map, Found::List),
        "expected a map, found a list",
    );
    refused(
        &cooperation(&["      policies: {merge: optional}", "      limits: 5"]),
        (5, 15),
        LIMITS,
        &wrong(Expected::Map, Found::Integer),
        "expected a map, found a whole number",
    );
}

#[test]
fn a_behaviour_or_sequence_the_core_does_not_parse_is_refused() {
    // Names refused by `Behavior::from_str` and `Sequence::from_str`: not AD API names, and
    // not valid user-extension names either.
    let unknown = |field, given: &str, problem| InvalidName {
        field,
        given: given.into(),
        problem,
    };
    refused(
        &policies(&["        lane change: optional"]),
        (5, 9),
        &format!("{POLICIES}.lane change"),
        &SettingsErrorKind::InvalidBehavior(unknown(
            "behavior",
            "lane change",
            NameProblem::Character { at: 4 },
        )),
        "\"lane change\" is not a behavior: byte 4 is not a lower-case ASCII letter, digit or '-'",
    );
    refused(
        &policies(&["        avoidance:", "          2nd: optional"]),
        (6, 11),
        &format!("{POLICIES}.avoidance.2nd"),
        &SettingsErrorKind::InvalidSequence(unknown(
            "sequence",
            "2nd",
            NameProblem::Character { at: 0 },
        )),
        "\"2nd\" is not a sequence: it does not start with a lower-case ASCII letter",
    );
    // Found at the key, before its value is read.
    refused(
        &policies(&["        lane change:", "          - what"]),
        (5, 9),
        &format!("{POLICIES}.lane change"),
        &SettingsErrorKind::InvalidBehavior(unknown(
            "behavior",
            "lane change",
            NameProblem::Character { at: 4 },
        )),
        "\"lane change\" is not a behavior: byte 4 is not a lower-case ASCII letter, digit or '-'",
    );
}

#[test]
fn a_policy_other_than_optional_or_required_is_refused() {
    for value in ["maybe", "Optional", "REQUIRED", "'optional '"] {
        let given = value.trim_matches('\'');
        refused(
            &policies(&[&format!("        lane-change: {value}")]),
            (5, 22),
            &format!("{POLICIES}.lane-change"),
            &SettingsErrorKind::UnknownPolicy {
                given: given.into(),
            },
            &format!("unknown policy {given:?}; expected `optional` or `required`"),
        );
    }
}

#[test]
fn a_limit_below_zero_or_beyond_its_type_is_out_of_range() {
    let usize_max = u64::try_from(usize::MAX).unwrap();
    for (limit, value, max) in [
        ("ttl_ms", "-1", u64::MAX),
        ("ttl_ms", "18446744073709551616", u64::MAX),
        ("ttl_ms", "0x10000000000000000", u64::MAX),
        ("max_scenes", "-5", usize_max),
        ("retired_capacity", "99999999999999999999", usize_max),
    ] {
        let line = format!("        {limit}: {value}");
        refused(
            &policies(&["        merge: optional", "      limits:", &line]),
            (7, 9 + limit.len() + 2),
            &format!("{LIMITS}.{limit}"),
            &SettingsErrorKind::OutOfRange {
                given: value.into(),
                max,
            },
            &format!("{value} is not a whole number from 0 to {max}"),
        );
    }
}

#[test]
fn a_limit_above_the_callers_maximum_is_refused() {
    let max = Limits {
        ttl_ms: 1_000,
        max_scenes: 64,
        retired_capacity: 128,
        max_batch: 16,
    };
    for (limit, value, most) in [
        ("ttl_ms", 1_001, 1_000),
        ("max_scenes", 65, 64),
        ("retired_capacity", 129, 128),
        ("max_batch", 1_024, 16),
    ] {
        let text = policies(&[
            "        merge: optional",
            "      limits:",
            &format!("        {limit}: {value}"),
        ]);
        let error = settings::parse_within(&text, &max).unwrap_err();
        assert_eq!((error.line, error.column), (7, 9 + limit.len() + 2));
        assert_eq!(error.key, format!("{LIMITS}.{limit}"));
        assert_eq!(
            error.kind,
            SettingsErrorKind::AboveMaximum {
                given: value,
                max: most
            }
        );
        assert_eq!(
            error.to_string(),
            format!(
                "line 7, column {}: {LIMITS}.{limit}: {value} is more than the {most} allowed here",
                9 + limit.len() + 2
            )
        );
        // `parse` has no maximum but the types'.
        assert!(settings::parse(&text).is_ok());
    }
}

#[test]
fn a_limit_the_core_refuses_is_refused_where_it_is_written() {
    for (limit, error) in [
        ("max_scenes", ConfigError::NoScenes),
        ("retired_capacity", ConfigError::NoRetiredCapacity),
        ("max_batch", ConfigError::NoBatch),
    ] {
        // The same refusal as `State::new`'s.
        let zero = match error {
            ConfigError::NoScenes => Config::new([]).max_scenes(0),
            ConfigError::NoRetiredCapacity => Config::new([]).retired_capacity(0),
            ConfigError::NoBatch => Config::new([]).max_batch(0),
        };
        assert_eq!(cooperation::State::new(zero).unwrap_err(), error);
        refused(
            &policies(&[
                "        merge: optional",
                "      limits:",
                "        ttl_ms: 100",
                &format!("        {limit}: 0"),
            ]),
            (8, 9 + limit.len() + 2),
            &format!("{LIMITS}.{limit}"),
            &SettingsErrorKind::Refused(error),
            &format!("{limit} must be at least 1"),
        );
    }
}
