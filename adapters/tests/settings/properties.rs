//! Property tests: every configuration written by `to_yaml` reads back the same, and no text
//! makes the reader panic; what it accepts is a configuration the core accepts.

use proptest::prelude::*;

use super::*;
use cooperation::{Limits, State};

/// A built-in module, or one with a user-extension behaviour or sequence.
fn any_module() -> impl Strategy<Value = Module> {
    let name = "[a-z][a-z0-9-]{0,23}";
    let behavior = prop_oneof![
        prop::sample::select(Behavior::ALL.to_vec()),
        name.prop_map(|name| name.parse::<Behavior>().unwrap()),
    ];
    let sequence = prop_oneof![
        prop::sample::select(Sequence::ALL.to_vec()),
        name.prop_map(|name| name.parse::<Sequence>().unwrap()),
    ];
    (behavior, sequence).prop_map(|(behavior, sequence)| Module::with_sequence(behavior, sequence))
}

fn any_policy() -> impl Strategy<Value = Policy> {
    prop::sample::select(Policy::ALL.to_vec())
}

/// A count limit: small, or anywhere up to the type's largest.
fn any_count() -> impl Strategy<Value = usize> {
    prop_oneof![1..=64_usize, 1..=usize::MAX]
}

/// Every configuration `State::new` accepts with at least one module.
fn any_config() -> impl Strategy<Value = Config> {
    (
        prop::collection::btree_map(any_module(), any_policy(), 1..24),
        prop_oneof![0..=100_000_u64, any::<u64>()],
        any_count(),
        any_count(),
        any_count(),
    )
        .prop_map(
            |(policies, ttl_ms, max_scenes, retired_capacity, max_batch)| {
                Config::new(policies).with_limits(Limits {
                    ttl_ms,
                    max_scenes,
                    retired_capacity,
                    max_batch,
                })
            },
        )
}

/// Text made of YAML's punctuation, a few words of the layout, and white space.
fn yaml_ish() -> impl Strategy<Value = String> {
    let pieces = prop::sample::select(vec![
        "/**",
        ":",
        " ",
        "  ",
        "\n",
        "\t",
        "-",
        "- ",
        "{",
        "}",
        "[",
        "]",
        ",",
        "\"",
        "'",
        "&a",
        "*a",
        "!!str",
        "!",
        "#",
        "|",
        ">",
        "?",
        "---",
        "...",
        "%YAML 1.2",
        "~",
        ".",
        "0",
        "-1",
        "0x",
        "1e9",
        "\\",
        "\u{feff}",
        "\r",
        "ros__parameters",
        "cooperation",
        "policies",
        "limits",
        "ttl_ms",
        "max_batch",
        "lane-change",
        "avoidance",
        "change",
        "optional",
        "required",
    ]);
    prop::collection::vec(pieces, 0..64).prop_map(|pieces| pieces.concat())
}

/// The example file with up to four random edits: a range deleted, or text inserted.
fn edited_example() -> impl Strategy<Value = String> {
    let example = settings::to_yaml(&config(&[
        (module(Behavior::LaneChange), Policy::Optional),
        (module(Behavior::Avoidance), Policy::Required),
        (
            sequence(Behavior::Avoidance, Sequence::Change),
            Policy::Optional,
        ),
        (
            sequence(Behavior::Intersection, Sequence::Return),
            Policy::Required,
        ),
    ]));
    let edit = (any::<prop::sample::Index>(), 0..8_usize, "[ -~\n\t]{0,6}");
    prop::collection::vec(edit, 0..4).prop_map(move |edits| {
        let mut text: Vec<char> = example.chars().collect();
        for (at, delete, insert) in edits {
            let at = at.index(text.len() + 1);
            let end = (at + delete).min(text.len());
            text.splice(at..end, insert.chars());
        }
        text.into_iter().collect()
    })
}

/// Whatever `parse` accepts, the core accepts, and it writes and reads back unchanged.
fn accepted_is_sound(text: &str) {
    if let Ok(config) = settings::parse(text) {
        assert!(!config.policies.is_empty(), "{text}");
        assert!(State::new(config.clone()).is_ok(), "{text}");
        assert_eq!(
            settings::parse(&settings::to_yaml(&config)),
            Ok(config),
            "{text}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn every_configuration_round_trips(config in any_config()) {
        let written = settings::to_yaml(&config);
        prop_assert_eq!(settings::parse(&written), Ok(config), "{}", written);
    }

    #[test]
    fn any_text_is_read_or_refused_without_panicking(text in any::<String>()) {
        accepted_is_sound(&text);
    }

    #[test]
    fn yaml_like_text_is_read_or_refused_without_panicking(text in yaml_ish()) {
        accepted_is_sound(&text);
    }

    #[test]
    fn an_edited_file_is_read_or_refused_with_a_line_in_the_text(text in edited_example()) {
        match settings::parse(&text) {
            Ok(_) => accepted_is_sound(&text),
            Err(error) => {
                // The line is one of the text's, or the one after its last line break.
                let lines = text.split('\n').count().max(1);
                prop_assert!(error.line >= 1 && error.line <= lines, "{}\n{}", error, text);
                prop_assert!(error.column >= 1, "{}", error);
            }
        }
    }
}

#[test]
fn deep_nesting_is_refused_without_descending() {
    for text in [
        format!("{}{}", "[".repeat(100_000), "]".repeat(100_000)),
        format!("{}{}", "{a: ".repeat(100_000), "}".repeat(100_000)),
        format!(
            "/**: {{ros__parameters: {{cooperation: {{policies: {{avoidance: {{change: {}",
            "{a: ".repeat(100_000)
        ),
    ] {
        assert!(settings::parse(&text).is_err());
    }
}
