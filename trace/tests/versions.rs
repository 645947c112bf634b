//! Versions of the trace format: version 2 (the spec's and the AD API's words) and version 1
//! (the library's Rust variant names), which is still read.

use cooperation_trace::{
    parse_config, parse_record, parse_record_of, replay, ErrorKind, Options, Record, Version,
};

const SEED: &str = include_str!("data/seed.jsonl");
const SEED_V1: &str = include_str!("data/seed-v1.jsonl");

/// What `replay --json` prints for `trace`.
fn replayed(trace: &str) -> String {
    let mut out = Vec::new();
    replay(trace.as_bytes(), &mut out, &Options::default(), true).expect("replays");
    String::from_utf8(out).expect("UTF-8")
}

#[test]
fn a_version_1_trace_replays_as_its_version_2_form() {
    assert!(SEED_V1.contains("\"LaneChange\"") && SEED_V1.contains("\"Deactivate\""));
    assert!(!SEED.contains("\"LaneChange\""));
    let expected = replayed(SEED);
    assert!(expected.contains("\"deactivate\"") && !expected.contains("\"Deactivate\""));
    assert_eq!(replayed(SEED_V1), expected);
    // Declared, either way (one line more, as a comment would be).
    let expected = replayed(&format!("# one line\n{SEED}"));
    assert_eq!(
        replayed(&format!("{{\"version\": 1}}\n{SEED_V1}")),
        expected
    );
    assert_eq!(replayed(&format!("{{\"version\": 2}}\n{SEED}")), expected);
}

#[test]
fn a_version_2_trace_reads_only_version_2_words() {
    let error = replay(
        format!("{{\"version\": 2}}\n{SEED_V1}").as_bytes(),
        std::io::sink(),
        &Options::default(),
        false,
    )
    .expect_err("version-1 words");
    assert_eq!(error.line, Some(4), "{error}");
    assert!(
        error
            .to_string()
            .contains("\"LaneChange\" is not a behavior"),
        "{error}"
    );
}

#[test]
fn every_version_1_word_is_read() {
    let line = r#"{"at_ms": 0, "input": {"Register": {"id": "00000000-0000-0000-0000-000000000001", "module": {"behavior": "UserDefinedAttentionArea", "sequence": "Return"}, "decision": "Activate", "geometry": {"Steering": {"poses": [{"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}, {"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}], "distances": [1.0, 2.0], "direction": "Straight", "status": "Turning"}}}}}"#;
    assert!(parse_record(1, line).is_err());
    let upgraded = parse_record_of(Version::V1, 1, line).expect("version 1");
    let v2 = line
        .replace("UserDefinedAttentionArea", "user-defined-attention-area")
        .replace("\"Return\"", "\"return\"")
        .replace("Activate", "activate")
        .replace("Straight", "straight")
        .replace("Turning", "turning");
    assert_eq!(upgraded, parse_record(1, &v2).expect("version 2"));
    let observed = r#"{"observed": [{"id": "00000000-0000-0000-0000-000000000001", "module_decision": "Deactivate", "operator_decision": "Undecided", "cancellable": true, "phase": "WaitingForExecution", "policy": "Required"}]}"#;
    let v2 = observed
        .replace("Deactivate", "deactivate")
        .replace("Undecided", "none")
        .replace("WaitingForExecution", "waiting")
        .replace("Required", "required");
    assert_eq!(
        parse_record_of(Version::V1, 1, observed).expect("version 1"),
        parse_record(1, &v2).expect("version 2")
    );
}

#[test]
fn a_version_1_configuration_file_is_read() {
    let v1 = r#"{"policies": [{"module": {"behavior": "LaneChange", "sequence": "Empty"}, "policy": "Optional"}]}"#;
    let v2 = r#"{"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}"#;
    assert_eq!(
        parse_config(v1).expect("version 1"),
        parse_config(v2).expect("version 2")
    );
}

#[test]
fn the_version_record_is_first_alone_and_known() {
    assert_eq!(
        parse_record(1, r#"{"version": 2}"#).expect("a record"),
        Record::Version(Version::V2)
    );
    let error = |trace: &str| {
        replay(
            trace.as_bytes(),
            std::io::sink(),
            &Options::default(),
            false,
        )
        .expect_err("refused")
    };
    let unknown = error("{\"version\": 3}\n");
    assert_eq!(unknown.kind, ErrorKind::UnknownVersion { given: 3 });
    assert_eq!(
        unknown.to_string(),
        "line 1: trace format version 3 is not known; this reader knows versions 1 and 2"
    );
    let late = error(&format!("{SEED}{{\"version\": 2}}\n"));
    assert_eq!(late.kind, ErrorKind::MisplacedVersion);
    assert_eq!(
        late.to_string(),
        format!(
            "line {}: a `version` record goes only on the trace's first record",
            SEED.lines().count() + 1
        )
    );
    let mixed = error("{\"version\": 2, \"at_ms\": 0}\n");
    assert_eq!(
        mixed.to_string(),
        "line 1: field `at_ms` cannot go with `version` in one record"
    );
    // Comments may come before it.
    assert!(replay(
        format!("# a comment\n{{\"version\": 2}}\n{SEED}").as_bytes(),
        std::io::sink(),
        &Options::default(),
        false
    )
    .is_ok());
}
