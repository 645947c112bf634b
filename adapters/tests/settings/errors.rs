//! Errors of the file's structure: YAML, the node, keys and maps. Each test checks the line,
//! the column, the key path, the kind and the message.

use super::*;
use cooperation_adapters::settings::{Found, Unsupported};

#[test]
fn text_that_is_not_yaml_is_a_syntax_error_at_its_place() {
    // The key is the last one read whole: the parser reads ahead of the reader.
    let text = policies(&["        lane-change: optional: required"]);
    refused(
        &text,
        (5, 30),
        POLICIES,
        &SettingsErrorKind::Syntax {
            message: "mapping values are not allowed in this context".into(),
        },
        "not YAML: mapping values are not allowed in this context",
    );
    // A tab where YAML wants spaces.
    let text = policies(&["\tlane-change: optional"]);
    let error = settings::parse(&text).unwrap_err();
    assert!(
        matches!(error.kind, SettingsErrorKind::Syntax { .. }),
        "{error}"
    );
    assert_eq!((error.line, error.key.as_str()), (5, POLICIES), "{error}");
    // A quote left open: the error is at the end of the text.
    let error = settings::parse("/**:\n  ros__parameters: \"open\n").unwrap_err();
    assert!(
        matches!(error.kind, SettingsErrorKind::Syntax { .. }),
        "{error}"
    );
    assert_eq!(error.key, "/**.ros__parameters");
}

#[test]
fn anchors_aliases_tags_complex_keys_and_second_documents_are_not_read() {
    let unsupported = |what| SettingsErrorKind::Unsupported(what);
    refused(
        &policies(&["        lane-change: &policy optional"]),
        (5, 30),
        &format!("{POLICIES}.lane-change"),
        &unsupported(Unsupported::Anchor),
        "anchors (`&name`) and aliases (`*name`) are not read in a settings file",
    );
    // An alias can only follow its anchor, refused first; one of no anchor is not YAML.
    refused(
        &policies(&["        lane-change: optional", "        merge: *policy"]),
        (6, 16),
        &format!("{POLICIES}.merge"),
        &SettingsErrorKind::Syntax {
            message: "while parsing node, found unknown anchor".into(),
        },
        "not YAML: while parsing node, found unknown anchor",
    );
    refused(
        &policies(&["        lane-change: !!str optional"]),
        (5, 28),
        &format!("{POLICIES}.lane-change"),
        &unsupported(Unsupported::Tag),
        "tags (`!!str`, `!name`) are not read in a settings file",
    );
    refused(
        &policies(&["        ? [lane-change, merge]", "        : optional"]),
        (5, 11),
        POLICIES,
        &unsupported(Unsupported::ComplexKey),
        "a key is a string, not a map or a list",
    );
    let second = format!("{}---\nother: 1\n", policies(&["        merge: optional"]));
    refused(
        &second,
        (6, 1),
        "",
        &unsupported(Unsupported::SecondDocument),
        "a settings file is one YAML document",
    );
}

#[test]
fn a_file_that_sets_nothing_is_refused() {
    let message = "the file sets nothing: it starts with a node key such as `/**`, then \
                   `ros__parameters`";
    for (text, place) in [
        ("", (1, 1)),
        ("# nothing but a comment\n", (2, 1)),
        ("---\n", (2, 1)),
        ("~\n", (1, 1)),
        ("{}\n", (1, 1)),
    ] {
        refused(text, place, "", &SettingsErrorKind::NoNode, message);
    }
}

#[test]
fn the_node_key_is_required_single_and_a_node_name() {
    refused(
        &lines(&[
            "ros__parameters:",
            "  cooperation:",
            "    policies: {merge: optional}",
        ]),
        (1, 1),
        "ros__parameters",
        &SettingsErrorKind::NoNodeKey,
        "`ros__parameters` sits under a node key: write `/**:` (or the node's name) above it",
    );
    let bad = "not a node key: write `/**`, or a node's name of ASCII letters, digits, `_`, `/` \
               and `*`";
    for node in ["cooperation server", "/planning.cooperation", "\"\""] {
        let text = format!("{node}:\n  ros__parameters: {{}}\n");
        let key = node.trim_matches('"');
        refused(&text, (1, 1), key, &SettingsErrorKind::BadNodeKey, bad);
    }
    let two = format!(
        "{}/planning/other:\n  ros__parameters: {{}}\n",
        policies(&["        merge: optional"])
    );
    refused(
        &two,
        (6, 1),
        "/planning/other",
        &SettingsErrorKind::SecondNode,
        "a second node key: a settings file configures one node",
    );
    refused(
        "/**: {}\n",
        (1, 1),
        "/**",
        &SettingsErrorKind::NoParameters,
        "the node has no `ros__parameters`",
    );
}

#[test]
fn a_key_twice_in_one_map_is_refused_naming_both_lines() {
    refused(
        &policies(&[
            "        lane-change: optional",
            "        lane-change: required",
        ]),
        (6, 9),
        &format!("{POLICIES}.lane-change"),
        &SettingsErrorKind::DuplicateKey { first_line: 5 },
        "the key is given twice in one map (first on line 5)",
    );
    // Quoting does not make another key.
    refused(
        &policies(&["        merge: optional", "        'merge': required"]),
        (6, 9),
        &format!("{POLICIES}.merge"),
        &SettingsErrorKind::DuplicateKey { first_line: 5 },
        "the key is given twice in one map (first on line 5)",
    );
    let twice_node = format!("{}/**: {{}}\n", policies(&["        merge: optional"]));
    refused(
        &twice_node,
        (6, 1),
        "/**",
        &SettingsErrorKind::DuplicateKey { first_line: 1 },
        "the key is given twice in one map (first on line 1)",
    );
    refused(
        &cooperation(&[
            "      limits: {ttl_ms: 1}",
            "      policies: {merge: optional}",
            "      limits: {max_batch: 1}",
        ]),
        (6, 7),
        "/**.ros__parameters.cooperation.limits",
        &SettingsErrorKind::DuplicateKey { first_line: 4 },
        "the key is given twice in one map (first on line 4)",
    );
}

#[test]
fn one_parameter_given_by_two_spellings_is_refused() {
    // A module given twice: nested, then dotted.
    refused(
        &policies(&[
            "        avoidance:",
            "          change: optional",
            "        avoidance.change: required",
        ]),
        (7, 27),
        &format!("{POLICIES}.avoidance.change"),
        &SettingsErrorKind::Twice { first_line: 6 },
        "set twice, by two spellings of the key (first on line 6)",
    );
    // The behaviour alone, dotted from `cooperation` and nested.
    refused(
        &cooperation(&[
            "      policies.lane-change: optional",
            "      policies:",
            "        lane-change: optional",
        ]),
        (6, 22),
        &format!("{POLICIES}.lane-change"),
        &SettingsErrorKind::Twice { first_line: 4 },
        "set twice, by two spellings of the key (first on line 4)",
    );
    // A limit given twice.
    refused(
        &cooperation(&[
            "      policies: {merge: optional}",
            "      limits.ttl_ms: 5",
            "      limits:",
            "        ttl_ms: 5",
        ]),
        (7, 17),
        &format!("{LIMITS}.ttl_ms"),
        &SettingsErrorKind::Twice { first_line: 5 },
        "set twice, by two spellings of the key (first on line 5)",
    );
}

#[test]
fn empty_keys_and_empty_parts_of_dotted_keys_are_refused() {
    let message = "an empty key, or an empty part of a dotted key";
    refused(
        &policies(&["        \"\": optional"]),
        (5, 9),
        &format!("{POLICIES}."),
        &SettingsErrorKind::EmptyName,
        message,
    );
    refused(
        &cooperation(&["      policies..lane-change: optional"]),
        (4, 7),
        "/**.ros__parameters.cooperation.policies.",
        &SettingsErrorKind::EmptyName,
        message,
    );
    // The empty sequence is the behaviour alone, never `""` or a trailing dot.
    refused(
        &policies(&["        avoidance.: optional"]),
        (5, 9),
        &format!("{POLICIES}.avoidance."),
        &SettingsErrorKind::EmptyName,
        message,
    );
    refused(
        &policies(&["        avoidance:", "          '': optional"]),
        (6, 11),
        &format!("{POLICIES}.avoidance."),
        &SettingsErrorKind::EmptyName,
        message,
    );
}

#[test]
fn a_misspelt_key_is_refused_listing_the_keys_there() {
    let unknown = |given: &str, expected| SettingsErrorKind::UnknownKey {
        given: given.into(),
        expected,
    };
    refused(
        &cooperation(&["      polices:", "        merge: optional"]),
        (4, 7),
        "/**.ros__parameters.cooperation.polices",
        &unknown("polices", &["policies", "limits", "interfaces"]),
        "unknown key \"polices\"; expected one of `policies`, `limits`, `interfaces`",
    );
    refused(
        &lines(&["/**:", "  ros__parameters:", "    cooperaton: {}"]),
        (3, 5),
        "/**.ros__parameters.cooperaton",
        &unknown("cooperaton", &["cooperation"]),
        "unknown key \"cooperaton\"; expected `cooperation`",
    );
    refused(
        &lines(&["/**:", "  parameters: {}"]),
        (2, 3),
        "/**.parameters",
        &unknown("parameters", &["ros__parameters"]),
        "unknown key \"parameters\"; expected `ros__parameters`",
    );
    refused(
        &policies(&[
            "        merge: optional",
            "      limits:",
            "        ttl: 10",
        ]),
        (7, 9),
        &format!("{LIMITS}.ttl"),
        &unknown(
            "ttl",
            &["ttl_ms", "max_scenes", "retired_capacity", "max_batch"],
        ),
        "unknown key \"ttl\"; expected one of `ttl_ms`, `max_scenes`, `retired_capacity`, \
         `max_batch`",
    );
    // A parameter of another kind is refused too, not ignored.
    refused(
        &lines(&[
            "/**:",
            "  ros__parameters:",
            "    use_sim_time: true",
            "    cooperation: {policies: {merge: optional}}",
        ]),
        (3, 5),
        "/**.ros__parameters.use_sim_time",
        &unknown("use_sim_time", &["cooperation"]),
        "unknown key \"use_sim_time\"; expected `cooperation`",
    );
}

#[test]
fn an_empty_map_of_modules_is_refused() {
    refused(
        &cooperation(&["      policies: {}"]),
        (4, 17),
        POLICIES,
        &SettingsErrorKind::EmptyMap,
        "an empty map names no module",
    );
    refused(
        &policies(&["        merge: optional", "        avoidance: {}"]),
        (6, 20),
        &format!("{POLICIES}.avoidance"),
        &SettingsErrorKind::EmptyMap,
        "an empty map names no module",
    );
}

#[test]
fn a_file_without_policies_is_refused_at_its_parameters() {
    let message = "no module has a policy: `cooperation.policies` names every module that \
                   supports cooperation";
    for text in [
        cooperation(&["      limits: {ttl_ms: 5}"]),
        cooperation(&["      {}"]),
        lines(&["/**:", "  ros__parameters: {}"]),
        lines(&["/**:", "  ros__parameters:", "    cooperation: {}"]),
    ] {
        refused(
            &text,
            (2, 3),
            "/**.ros__parameters",
            &SettingsErrorKind::NoPolicies,
            message,
        );
    }
}

/// A character YAML does not allow is refused where it is, named as itself; the parser would
/// take a NUL for the end of the text and read nothing after it.
#[test]
fn a_character_yaml_does_not_allow_is_refused_where_it_is() {
    for (line, column, character) in [
        ("        lane\0change: optional", 13, '\0'),
        ("        lane-change: optional\0", 30, '\0'),
        ("        lane\u{7}change: optional", 13, '\u{7}'),
        ("        lane-change: opt\u{7f}ional", 25, '\u{7f}'),
        ("        lane-change: optional # \u{9b}", 33, '\u{9b}'),
    ] {
        let text = policies(&[line, "        merge: required"]);
        let code = u32::from(character);
        refused(
            &text,
            (5, column),
            "",
            &SettingsErrorKind::Unprintable { character },
            &format!("U+{code:04X} is a character YAML does not allow in a file"),
        );
    }
    // Tab, line breaks, NEL and printable characters pass this check.
    let text = policies(&["        lane-change: optional #\tcaf\u{e9}\u{85}"]);
    assert!(settings::parse(&text).is_ok(), "{text}");
}

/// A key longer than YAML lets a key on one line be is named as that, first in its map or
/// not, plain or quoted; a key of 1,024 characters is read.
#[test]
fn a_key_over_1024_characters_is_refused_as_too_long() {
    let long = "a".repeat(1025);
    for lines in [
        vec![format!("        {long}: optional")],
        vec![
            "        lane-change: optional".to_owned(),
            format!("        {long}: optional"),
        ],
        vec![format!("        \"{long}\": optional")],
    ] {
        let line = 4 + lines.len();
        let entries: Vec<&str> = lines.iter().map(String::as_str).collect();
        let quoted = usize::from(lines.iter().any(|l| l.contains('"')));
        refused(
            &policies(&entries),
            (line, 9),
            POLICIES,
            &SettingsErrorKind::KeyTooLong {
                chars: 1025 + 2 * quoted,
            },
            &format!(
                "a key of {} characters: YAML allows a key on one line at most 1024",
                1025 + 2 * quoted
            ),
        );
    }
    // At the limit the key is read, and is then no behaviour name (over 24 bytes).
    let text = policies(&[&format!("        {}: optional", "a".repeat(1024))]);
    let error = settings::parse(&text).expect_err("no behaviour");
    assert!(
        matches!(error.kind, SettingsErrorKind::InvalidBehavior(_)),
        "{error}"
    );
}

/// A key YAML reads as a boolean, null or a number is refused, naming what YAML reads it as;
/// quoted, the same name is a string and names an extension behaviour.
#[test]
fn a_key_yaml_reads_as_another_type_is_refused() {
    for (key, found, what) in [
        ("true", Found::Bool, "a boolean"),
        ("False", Found::Bool, "a boolean"),
        ("null", Found::Null, "null"),
        ("~", Found::Null, "null"),
        ("1", Found::Integer, "a whole number"),
        ("0x1f", Found::Integer, "a whole number"),
        ("2.5", Found::Float, "a floating-point number"),
        (".inf", Found::Float, "a floating-point number"),
    ] {
        let text = policies(&[&format!("        {key}: optional")]);
        refused(
            &text,
            (5, 9),
            &format!("{POLICIES}.{key}"),
            &SettingsErrorKind::KeyNotString { found },
            &format!("the key is {what} in YAML, not a name; quote it if the name is meant"),
        );
    }
    let text = policies(&["        \"true\": optional"]);
    let config = settings::parse(&text).expect("a quoted name is a string");
    let module = cooperation::Module::new("true".parse().expect("an extension name"));
    assert_eq!(config.policies.get(&module), Some(&Policy::Optional));
    // Under a behaviour, a sequence key too.
    let text = policies(&["        avoidance:", "          null: optional"]);
    let error = settings::parse(&text).expect_err("refused");
    assert_eq!(
        error.kind,
        SettingsErrorKind::KeyNotString { found: Found::Null }
    );
}
