//! The layouts a settings file may take, each read into the configuration it says.

use super::*;
use cooperation::Limits;

#[test]
fn the_nested_layout_reads_every_module_and_limit() {
    let text = lines(&[
        "/**:",
        "  ros__parameters:",
        "    cooperation:",
        "      policies:",
        "        intersection: required",
        "        lane-change: optional",
        "        avoidance:",
        "          change: optional",
        "          return: required",
        "      limits:",
        "        ttl_ms: 2000",
        "        max_scenes: 64",
        "        retired_capacity: 128",
        "        max_batch: 16",
    ]);
    let expected = config(&[
        (module(Behavior::Intersection), Policy::Required),
        (module(Behavior::LaneChange), Policy::Optional),
        (
            sequence(Behavior::Avoidance, Sequence::Change),
            Policy::Optional,
        ),
        (
            sequence(Behavior::Avoidance, Sequence::Return),
            Policy::Required,
        ),
    ])
    .ttl_ms(2_000)
    .max_scenes(64)
    .retired_capacity(128)
    .max_batch(16);
    assert_eq!(settings::parse(&text), Ok(expected));
}

#[test]
fn limits_left_out_are_the_defaults() {
    let only_policies = policies(&["        crosswalk: required"]);
    let expected = config(&[(module(Behavior::Crosswalk), Policy::Required)]);
    assert_eq!(settings::parse(&only_policies), Ok(expected.clone()));
    assert_eq!(expected.limits, Limits::default());
    // An empty limits map changes nothing either.
    let empty_limits = policies(&["        crosswalk: required", "      limits: {}"]);
    assert_eq!(settings::parse(&empty_limits), Ok(expected.clone()));
    // One limit given, the others default.
    let one = policies(&[
        "        crosswalk: required",
        "      limits:",
        "        max_batch: 8",
    ]);
    assert_eq!(settings::parse(&one), Ok(expected.max_batch(8)));
}

#[test]
fn any_single_node_key_is_accepted() {
    let expected = config(&[(module(Behavior::Merge), Policy::Optional)]);
    for node in [
        "/**",
        "\"/**\"",
        "'/**'",
        "cooperation",
        "/planning/cooperation",
        "/**/cooperation",
        "cooperation_server_1",
    ] {
        let text = format!(
            "{node}:\n  ros__parameters:\n    cooperation:\n      policies:\n        merge: optional\n"
        );
        assert_eq!(settings::parse(&text), Ok(expected.clone()), "{node}");
    }
}

#[test]
fn the_empty_sequence_is_the_behaviour_alone_and_sits_beside_dotted_sequences() {
    let text = policies(&[
        "        avoidance: required",
        "        avoidance.change: optional",
        "        avoidance.return: optional",
    ]);
    let expected = config(&[
        (module(Behavior::Avoidance), Policy::Required),
        (
            sequence(Behavior::Avoidance, Sequence::Change),
            Policy::Optional,
        ),
        (
            sequence(Behavior::Avoidance, Sequence::Return),
            Policy::Optional,
        ),
    ]);
    assert_eq!(settings::parse(&text), Ok(expected));
    // A nested map of sequences and a dotted sequence of the same behaviour add up.
    let mixed = policies(&[
        "        avoidance:",
        "          change: optional",
        "        avoidance.return: required",
    ]);
    let expected = config(&[
        (
            sequence(Behavior::Avoidance, Sequence::Change),
            Policy::Optional,
        ),
        (
            sequence(Behavior::Avoidance, Sequence::Return),
            Policy::Required,
        ),
    ]);
    assert_eq!(settings::parse(&mixed), Ok(expected));
}

#[test]
fn dotted_keys_are_the_nested_keys_at_every_level() {
    let expected = config(&[
        (module(Behavior::LaneChange), Policy::Optional),
        (
            sequence(Behavior::Avoidance, Sequence::Return),
            Policy::Required,
        ),
    ])
    .ttl_ms(500);
    let flat = lines(&[
        "/**:",
        "  ros__parameters:",
        "    cooperation.policies.lane-change: optional",
        "    cooperation.policies.avoidance.return: required",
        "    cooperation.limits.ttl_ms: 500",
    ]);
    assert_eq!(settings::parse(&flat), Ok(expected.clone()));
    let halfway = cooperation(&[
        "      policies.lane-change: optional",
        "      policies:",
        "        avoidance.return: required",
        "      limits.ttl_ms: 500",
    ]);
    assert_eq!(settings::parse(&halfway), Ok(expected));
}

#[test]
fn flow_style_quoting_comments_and_document_markers_are_yaml_as_usual() {
    let expected = config(&[
        (module(Behavior::LaneChange), Policy::Optional),
        (module(Behavior::StopSign), Policy::Required),
    ])
    .max_scenes(10);
    for text in [
        "/**: {ros__parameters: {cooperation: {policies: {lane-change: optional, stop-sign: \
         required}, limits: {max_scenes: 10}}}}\n"
            .to_owned(),
        lines(&[
            "# Cooperation defaults.",
            "---",
            "/**:",
            "  ros__parameters:   # the node's parameters",
            "    cooperation:",
            "      policies:",
            "        \"lane-change\": 'optional'",
            "        'stop-sign': \"required\"",
            "      limits: {max_scenes: 10}",
            "...",
        ]),
        // A byte-order mark, as an editor may write, and CRLF line ends.
        "\u{feff}/**:\r\n  ros__parameters:\r\n    cooperation:\r\n      policies:\r\n        \
             lane-change: optional\r\n        stop-sign: required\r\n      limits:\r\n        \
             max_scenes: 10\r\n"
            .to_owned(),
    ] {
        assert_eq!(settings::parse(&text), Ok(expected.clone()), "{text}");
    }
}

#[test]
fn limits_are_whole_numbers_in_any_core_schema_form() {
    for (written, value) in [
        ("10", 10),
        ("+10", 10),
        ("0010", 10),
        ("0xA", 10),
        ("0o12", 10),
    ] {
        let text = policies(&[
            "        merge: optional",
            "      limits:",
            &format!("        max_batch: {written}"),
        ]);
        let config = settings::parse(&text).expect(written);
        assert_eq!(config.limits.max_batch, value, "{written}");
    }
    // A TTL of zero is one the core accepts (every scene expires at the next tick), and the
    // largest TTL is `u64::MAX`.
    for (written, value) in [("0", 0), ("-0", 0), ("18446744073709551615", u64::MAX)] {
        let text = policies(&[
            "        merge: optional",
            "      limits:",
            &format!("        ttl_ms: {written}"),
        ]);
        assert_eq!(settings::parse(&text).expect(written).limits.ttl_ms, value);
    }
}

#[test]
fn parse_within_accepts_limits_up_to_its_maximum() {
    let max = Limits {
        ttl_ms: 1_000,
        max_scenes: 64,
        retired_capacity: 64,
        max_batch: 64,
    };
    let text = policies(&[
        "        merge: optional",
        "      limits:",
        "        ttl_ms: 1000",
        "        max_scenes: 64",
        "        retired_capacity: 64",
        "        max_batch: 64",
    ]);
    let config = settings::parse_within(&text, &max).expect("every limit at the maximum");
    assert_eq!(config.limits, max);
    // The defaults are not checked against the maximum: only what the file gives.
    let defaults = policies(&["        merge: optional"]);
    assert_eq!(
        settings::parse_within(&defaults, &max).map(|config| config.limits),
        Ok(Limits::default())
    );
}

#[test]
fn to_yaml_writes_each_behaviour_in_its_form() {
    let config = config(&[
        (module(Behavior::LaneChange), Policy::Optional),
        (
            sequence(Behavior::Avoidance, Sequence::Change),
            Policy::Optional,
        ),
        (
            sequence(Behavior::Avoidance, Sequence::Return),
            Policy::Required,
        ),
        (module(Behavior::StartPlanner), Policy::Required),
        (
            sequence(Behavior::StartPlanner, Sequence::Return),
            Policy::Optional,
        ),
    ])
    .ttl_ms(3_000);
    let written = settings::to_yaml(&config);
    assert_eq!(
        written,
        lines(&[
            "/**:",
            "  ros__parameters:",
            "    cooperation:",
            "      policies:",
            "        avoidance:",
            "          change: optional",
            "          return: required",
            "        lane-change: optional",
            "        start-planner: required",
            "        start-planner.return: optional",
            "      limits:",
            "        ttl_ms: 3000",
            "        max_scenes: 4096",
            "        retired_capacity: 65536",
            "        max_batch: 1024",
        ])
    );
    assert_eq!(settings::parse(&written), Ok(config));
}

#[test]
fn to_yaml_of_no_module_is_refused_when_read() {
    let written = settings::to_yaml(&Config::new([]));
    assert!(written.contains("      policies: {}\n"), "{written}");
    let error = settings::parse(&written).unwrap_err();
    assert_eq!(error.kind, SettingsErrorKind::EmptyMap);
    assert_eq!((error.line, error.key.as_str()), (4, POLICIES));
}

#[test]
fn user_extension_behaviours_and_sequences_read_like_built_in_ones() {
    let text = policies(&[
        "        valet-parking: optional",
        "        valet-parking.approach: required",
        "        avoidance:",
        "          back-off: optional",
    ]);
    let extension = |name: &str| name.parse::<Behavior>().unwrap();
    let expected = config(&[
        (module(extension("valet-parking")), Policy::Optional),
        (
            Module::with_sequence(extension("valet-parking"), "approach".parse().unwrap()),
            Policy::Required,
        ),
        (
            Module::with_sequence(Behavior::Avoidance, "back-off".parse().unwrap()),
            Policy::Optional,
        ),
    ]);
    assert_eq!(settings::parse(&text), Ok(expected.clone()));
    // And written back, they read the same.
    assert_eq!(settings::parse(&settings::to_yaml(&expected)), Ok(expected));
}

#[test]
fn the_examples_settings_configure_a_user_extension() {
    let text = include_str!("../../examples/planner_module.param.yaml");
    let config = settings::parse(text).expect("the example's file reads");
    let valet = Module::new("valet-parking".parse().unwrap());
    assert!(matches!(valet.behavior, Behavior::Extension(_)));
    assert_eq!(config.policies.get(&valet), Some(&Policy::Optional));
}

#[test]
fn extension_names_that_yaml_would_type_round_trip() {
    for name in [
        "null", "true", "false", "nan", "inf", "e1", "x-1", "yes", "off", "y",
    ] {
        let module = Module::new(name.parse().unwrap());
        let expected = config(&[(module, Policy::Required)]);
        let yaml = settings::to_yaml(&expected);
        // Quoted where a YAML reader would type it (1.2's core schema, or 1.1's booleans).
        let typed = ["null", "true", "false", "yes", "off", "y"].contains(&name);
        assert_eq!(
            yaml.contains(&format!("\"{name}\":")),
            typed,
            "{name}:\n{yaml}"
        );
        assert_eq!(settings::parse(&yaml), Ok(expected), "{name}");
        // A policy of its own beside a sequence's: written as flat keys, `null.change`.
        let expected = config(&[
            (module, Policy::Required),
            (
                Module::with_sequence(module.behavior, Sequence::Change),
                Policy::Optional,
            ),
        ]);
        let yaml = settings::to_yaml(&expected);
        assert_eq!(settings::parse(&yaml), Ok(expected), "{name}:\n{yaml}");
    }
}

#[test]
fn a_misspelt_built_in_name_configures_an_extension_and_the_meant_module_is_refused() {
    let config = settings::parse(&policies(&["        lane-chnage: optional"])).expect("reads");
    assert!(config
        .policies
        .keys()
        .all(|module| matches!(module.behavior, Behavior::Extension(_))));
    let mut state = cooperation::State::new(config).expect("valid");
    let register = cooperation::Input::Register {
        id: cooperation::SceneId::from_u128(1),
        module: module(Behavior::LaneChange),
        report: cooperation::Report::new(
            cooperation::Decision::Activate,
            cooperation::Geometry::velocity(1.0),
        ),
    };
    let rejection = state.apply(&register).expect_err("no policy");
    assert_eq!(rejection.rule(), cooperation::Rule::RegisterModule);
}
