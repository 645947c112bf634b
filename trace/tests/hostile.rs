//! Hostile and malformed traces: every one ends in a typed error naming its line and field,
//! or replays within the stated bounds; none panics.

use std::io::{self, BufRead, BufReader};
use std::ops::ControlFlow;

use cooperation::{Limits, Rule};
use cooperation_trace::*;
use proptest::prelude::*;

const CONFIG: &str = r#"{"config": {"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}}"#;

const MODULE: &str = r#"{"behavior": "lane-change", "sequence": ""}"#;

const GEOMETRY: &str = r#"{"Velocity": {"pose": {"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}, "distance": 10.0, "status": "approaching"}}"#;

fn uuid(n: u128) -> String {
    cooperation::SceneId::from_u128(n).to_string()
}

fn register(at_ms: u64, n: u128) -> String {
    format!(
        r#"{{"at_ms": {at_ms}, "input": {{"Register": {{"id": "{}", "module": {MODULE}, "decision": "activate", "geometry": {GEOMETRY}}}}}}}"#,
        uuid(n)
    )
}

fn replay_text(text: &str) -> Result<Summary, TraceError> {
    replay(text.as_bytes(), io::sink(), &Options::default(), false)
}

/// The error for a trace of the config line followed by `line`, which is line 2.
fn error_of(line: &str) -> TraceError {
    let text = format!("{CONFIG}\n{line}\n");
    let error = replay_text(&text).expect_err(line);
    assert_eq!(error.line, Some(2), "{error}");
    assert!(error.to_string().starts_with("line 2: "), "{error}");
    // Validation reads the same records the same way.
    assert_eq!(
        validate(text.as_bytes(), &Options::default()).expect_err(line),
        error
    );
    error
}

fn json_field(error: &TraceError) -> &str {
    match &error.kind {
        ErrorKind::Json { field, .. } => field,
        other => panic!("not a JSON error: {other:?}"),
    }
}

#[test]
fn malformed_records_name_line_and_field() {
    for (line, field, words) in [
        ("{not json}", "", "key must be a string"),
        (r#"{"at_ms": 1} {"#, "", "trailing characters"),
        (r#"{"at_ms": -1}"#, "at_ms", "expected u64"),
        (r#"{"at_ms": 1.5}"#, "at_ms", "expected u64"),
        (r#"{"at_ms": "1"}"#, "at_ms", "expected u64"),
        (
            r#"{"at_ms": 18446744073709551616}"#,
            "at_ms",
            "expected u64",
        ),
        (
            r#"{"at_ms": 1, "at_ms": 2}"#,
            "at_ms",
            "duplicate field `at_ms`",
        ),
        (
            r#"{"at_ms": 1, "inptu": {}}"#,
            "inptu",
            "unknown field `inptu`",
        ),
        (
            r#"{"input": {"Remove": {"id": "nope", "module": {"behavior": "lane-change", "sequence": ""}}}}"#,
            "input.Remove.id",
            "is not a UUID",
        ),
        (
            r#"{"input": {"Remove": {"id": "00000000-0000-0000-0000-000000000001", "module": {"behavior": "", "sequence": ""}}}}"#,
            "input.Remove.module.behavior",
            "\"\" is not a behavior: it is empty",
        ),
        (
            r#"{"input": {"Remove": {"id": "00000000-0000-0000-0000-000000000001"}}}"#,
            "input.Remove",
            "missing field `module`",
        ),
        (
            r#"{"input": {"SetCommands": {"commands": [{"id": "00000000-0000-0000-0000-000000000001", "decision": "Yes"}]}}}"#,
            "input.SetCommands.commands[0].decision",
            "unknown variant `Yes`",
        ),
        (
            r#"{"observed": [{"id": "00000000-0000-0000-0000-000000000001", "module_decision": "activate", "operator_decision": "none"}]}"#,
            "observed[0]",
            "missing field `cancellable`",
        ),
        (
            r#"{"observed": [{"id": "00000000-0000-0000-0000-000000000001", "module_decision": "activate", "operator_decision": "none", "cancellable": 1}]}"#,
            "observed[0].cancellable",
            "invalid type: integer `1`",
        ),
        (r#"{"observed": {}}"#, "observed", "invalid type: map"),
        (
            r#"{"factors": "Sideways", "observed": []}"#,
            "factors",
            "unknown variant",
        ),
        (
            &format!("{{\"observed\": {}{}}}", "[".repeat(200), "]".repeat(200)),
            // serde_json stops at 128 levels, the record's object included.
            &format!("observed{}", "[0]".repeat(126)),
            "recursion limit exceeded",
        ),
    ] {
        let error = error_of(line);
        assert_eq!(json_field(&error), field, "{line}: {error}");
        assert!(error.to_string().contains(words), "{line}: {error}");
    }
}

#[test]
fn records_of_the_wrong_shape_are_refused() {
    let removal = r#""input": {"Remove": {"id": "00000000-0000-0000-0000-000000000001", "module": {"behavior": "lane-change", "sequence": ""}}}"#;
    for (line, kind) in [
        ("not json", ErrorKind::NotAnObject),
        ("[1, 2]", ErrorKind::NotAnObject),
        ("5", ErrorKind::NotAnObject),
        ("{}", ErrorKind::EmptyRecord),
        (
            r#"{"at_ms": null}"#,
            ErrorKind::Json {
                field: "at_ms".into(),
                message: "invalid type: null, expected u64 (column 14)".into(),
            },
        ),
        (
            &format!(r#"{{{removal}, "observed": []}}"#),
            ErrorKind::Ambiguous {
                first: "input",
                second: "observed",
            },
        ),
        (
            r#"{"config": {"policies": []}, "at_ms": 3}"#,
            ErrorKind::Ambiguous {
                first: "config",
                second: "at_ms",
            },
        ),
        (
            r#"{"at_ms": 3, "factors": "Velocity"}"#,
            ErrorKind::FactorsWithoutObserved,
        ),
        (
            r#"{"at_ms": 3, "input": {"Tick": {"elapsed_ms": 5}}}"#,
            ErrorKind::TickInput,
        ),
        (
            r#"{"config": {"policies": []}}"#,
            ErrorKind::MisplacedConfig,
        ),
        (
            r#"{"observed": [{"id": "00000000-0000-0000-0000-000000000001", "module_decision": "activate", "operator_decision": "none", "cancellable": true}, {"id": "00000000000000000000000000000001", "module_decision": "activate", "operator_decision": "none", "cancellable": true}]}"#,
            ErrorKind::DuplicateObserved {
                index: 1,
                id: cooperation::SceneId::from_u128(1),
            },
        ),
    ] {
        assert_eq!(error_of(line).kind, kind, "{line}");
    }
}

#[test]
fn configurations_are_checked() {
    let config = |body: &str| format!("{{\"config\": {body}}}\n{{\"at_ms\": 0}}\n");
    let first_line = |text: &str| {
        let error = replay_text(text).expect_err(text);
        assert_eq!(error.line, Some(1), "{error}");
        error.kind
    };
    let lane_change = format!(r#"{{"module": {MODULE}, "policy": "optional"}}"#);
    assert_eq!(
        first_line(&config(&format!(
            r#"{{"policies": [{lane_change}, {lane_change}]}}"#
        ))),
        ErrorKind::DuplicateModule {
            index: 1,
            module: cooperation::Module::new(cooperation::Behavior::LaneChange),
        }
    );
    assert_eq!(
        first_line(&config(r#"{"policies": [], "limits": {"max_batch": 0}}"#)),
        ErrorKind::InvalidConfig(cooperation::ConfigError::NoBatch)
    );
    assert_eq!(
        first_line(&config(
            r#"{"policies": [], "limits": {"retired_capacity": 1048577}}"#
        )),
        ErrorKind::LimitTooLarge {
            field: "retired_capacity",
            given: 1_048_577,
            max: 1_048_576,
        }
    );
    let error = replay_text(&config(r#"{"policies": [], "limits": {"ttl": 5}}"#)).unwrap_err();
    assert_eq!(json_field(&error), "config.limits.ttl");
    let error = replay_text(&config(r#"{"limits": {}}"#)).unwrap_err();
    assert_eq!(json_field(&error), "config");
    assert!(error.to_string().contains("missing field `policies`"));
    // The same checks for a configuration file.
    let error = parse_config("{\"policies\": [],\n \"limits\": {\"max_scenes\": -1}}").unwrap_err();
    assert_eq!(error.line, None);
    assert_eq!(json_field(&error), "config.limits.max_scenes");
    assert!(error.to_string().contains("at line 2 column"), "{error}");
    // A record before any configuration.
    let error = replay_text("{\"at_ms\": 0}\n").unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (Some(1), ErrorKind::MissingConfig)
    );
}

/// Checks the replayer's bounds after every step.
struct Bounds {
    limits: Limits,
    steps: u64,
    rules: std::collections::BTreeMap<Rule, u64>,
    max_tracked: usize,
}

impl Sink for Bounds {
    fn step(&mut self, step: &Step, replayer: &Replayer) -> Result<ControlFlow<()>, TraceError> {
        let state = replayer.state().unwrap();
        assert!(state.scene_count() <= self.limits.max_scenes);
        assert!(state.retired_oldest_first().count() <= self.limits.retired_capacity);
        let bound =
            2 * (self.limits.max_scenes + self.limits.retired_capacity + self.limits.max_batch);
        assert!(replayer.tracked_scenes() <= bound + self.limits.max_batch + 1);
        self.max_tracked = self.max_tracked.max(replayer.tracked_scenes());
        self.steps += 1;
        *self.rules.entry(step.rule()).or_default() += 1;
        Ok(ControlFlow::Continue(()))
    }

    fn observed(
        &mut self,
        _: usize,
        _: &Observation,
        _: &Replayer,
    ) -> Result<ControlFlow<()>, TraceError> {
        Ok(ControlFlow::Continue(()))
    }
}

/// Endless new identifiers, command floods of unknown identifiers and over-long batches: the
/// state stays within the core's limits and the replayer's memory of causes within its bound.
#[test]
fn endless_new_identifiers_stay_bounded() {
    let limits = Limits {
        ttl_ms: 50,
        max_scenes: 8,
        retired_capacity: 16,
        max_batch: 4,
    };
    let mut text = format!(
        r#"{{"config": {{"policies": [{{"module": {MODULE}, "policy": "required"}}], "limits": {}}}}}"#,
        serde_json::to_string(&limits).unwrap()
    );
    text.push('\n');
    let mut n = 0u128;
    for round in 0..3_000u64 {
        // Registrations of fresh identifiers, beyond the scene limit between expiries.
        for _ in 0..3 {
            n += 1;
            text += &register(round * 20, n);
            text.push('\n');
        }
        // A flood of commands for identifiers nobody registered, then an over-long batch.
        let commands = |count: u128, from: u128| {
            (from..from + count)
                .map(|k| format!(r#"{{"id": "{}", "decision": "activate"}}"#, uuid(k)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let unknown = 1 << 100 | u128::from(round) << 8;
        text += &format!(
            "{{\"input\": {{\"SetCommands\": {{\"commands\": [{}]}}}}}}\n",
            commands(4, unknown)
        );
        text += &format!(
            "{{\"input\": {{\"SetCommands\": {{\"commands\": [{}]}}}}}}\n",
            commands(5, unknown + 16)
        );
    }
    let mut bounds = Bounds {
        limits,
        steps: 0,
        rules: Default::default(),
        max_tracked: 0,
    };
    let (replayer, summary) = run(text.as_bytes(), &Options::default(), &mut bounds).unwrap();
    assert_eq!(summary.steps, bounds.steps);
    // Every round: three registrations (some refused as the scenes are full), a tick that
    // expires the oldest, an unknown-command flood and an over-long batch.
    let count = |rule| bounds.rules.get(&rule).copied().unwrap_or(0);
    assert_eq!(count(Rule::CommandUnknown), 3_000);
    assert_eq!(count(Rule::BatchLimit), 3_000);
    assert_eq!(count(Rule::RegisterNew) + count(Rule::RegisterFull), 9_000);
    assert!(count(Rule::RegisterFull) > 0, "{:?}", bounds.rules);
    assert!(count(Rule::TimeExpire) > 2_000, "{:?}", bounds.rules);
    // 9 000 registered identifiers and 27 000 commanded ones went through; at most the bound
    // is remembered.
    assert!(
        bounds.max_tracked <= 2 * (8 + 16 + 4) + 5,
        "{}",
        bounds.max_tracked
    );
    let state = replayer.state().unwrap();
    assert!(state.scene_count() <= 8);
    // The most recent over-long batch is still explained by its rule.
    assert_eq!(
        replayer.cause(cooperation::SceneId::from_u128(1 << 100 | 2_999 << 8 | 16)),
        Some(Cause {
            rule: Rule::BatchLimit,
            step: summary.steps,
            line: summary.lines,
        })
    );
}

/// Time at the ends of `u64`: a tick of `u64::MAX` ms, no overflow, then backwards is refused.
#[test]
fn time_near_u64_max() {
    let max = u64::MAX;
    let text = format!(
        "{CONFIG}\n{}\n{{\"at_ms\": {max}}}\n{}\n{{\"at_ms\": {max}, \"observed\": []}}\n",
        register(0, 1),
        register(max, 2),
    );
    let mut steps = Vec::new();
    struct Collect<'a>(&'a mut Vec<(Rule, cooperation::Input)>);
    impl Sink for Collect<'_> {
        fn step(&mut self, step: &Step, _: &Replayer) -> Result<ControlFlow<()>, TraceError> {
            self.0.push((step.rule(), step.input.clone()));
            Ok(ControlFlow::Continue(()))
        }
        fn observed(
            &mut self,
            _: usize,
            _: &Observation,
            _: &Replayer,
        ) -> Result<ControlFlow<()>, TraceError> {
            Ok(ControlFlow::Continue(()))
        }
    }
    let (replayer, _) = run(
        text.as_bytes(),
        &Options::default(),
        &mut Collect(&mut steps),
    )
    .unwrap();
    let rules: Vec<Rule> = steps.iter().map(|(rule, _)| *rule).collect();
    assert_eq!(
        rules,
        [Rule::RegisterNew, Rule::TimeExpire, Rule::RegisterNew]
    );
    assert_eq!(steps[1].1, cooperation::Input::Tick { elapsed_ms: max });
    assert_eq!(replayer.clock_ms(), Some(max));
    assert_eq!(replayer.state().unwrap().scene_count(), 1);
    // The observation after it departs: scene 2 is live.
    let Verdict::Departs(departure) = validate(text.as_bytes(), &Options::default()).unwrap()
    else {
        panic!("departs");
    };
    assert_eq!(departure.at_ms, Some(max));
    assert_eq!(departure.differences.len(), 1);
    assert_eq!(departure.differences[0].field, Field::Scene);
    // Back by one millisecond.
    let back = format!("{text}{{\"at_ms\": {}}}\n", max - 1);
    let error = replay_text(&back).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (
            Some(6),
            ErrorKind::TimeBackwards {
                previous_ms: max,
                at_ms: max - 1
            }
        )
    );
}

/// Differences name every departing field, in scene order, with their causes; an observed
/// scene the spec never had, and one it retired, say so.
#[test]
fn differences_explain_each_field() {
    let status = |n: u128, module: &str, operator: &str, cancellable: bool| {
        format!(
            r#"{{"id": "{}", "module_decision": "{module}", "operator_decision": "{operator}", "cancellable": {cancellable}}}"#,
            uuid(n)
        )
    };
    let remove = format!(
        r#"{{"input": {{"Remove": {{"id": "{}", "module": {MODULE}}}}}}}"#,
        uuid(3)
    );
    let text = format!(
        "{CONFIG}\n{}\n{}\n{}\n{remove}\n{{\"observed\": [{}, {}, {}]}}\n",
        register(0, 1),
        register(0, 2),
        register(0, 3),
        status(1, "deactivate", "autonomous", false),
        status(3, "activate", "none", true),
        status(4, "activate", "none", true),
    );
    let Verdict::Departs(departure) = validate(text.as_bytes(), &Options::default()).unwrap()
    else {
        panic!("departs");
    };
    assert_eq!((departure.line, departure.after_step), (6, 4));
    let found: Vec<(u128, Field, &str, &str, Option<Rule>)> = departure
        .differences
        .iter()
        .map(|d| {
            (
                d.id.to_u128(),
                d.field,
                d.expected.as_str(),
                d.observed.as_str(),
                d.cause.map(|c| c.rule),
            )
        })
        .collect();
    assert_eq!(
        found,
        [
            (
                1,
                Field::ModuleDecision,
                "activate",
                "deactivate",
                Some(Rule::RegisterNew)
            ),
            (
                1,
                Field::OperatorDecision,
                "none",
                "autonomous",
                Some(Rule::RegisterNew)
            ),
            (
                1,
                Field::Cancellable,
                "true",
                "false",
                Some(Rule::RegisterNew)
            ),
            (2, Field::Scene, "live", "absent", Some(Rule::RegisterNew)),
            (
                3,
                Field::Scene,
                "absent: retired (removed)",
                "live",
                Some(Rule::OwnerRemove)
            ),
            (4, Field::Scene, "absent: not registered", "live", None),
        ]
    );
}

/// An observation of one factor list compares only the scenes of that kind.
#[test]
fn factor_observations_cover_their_kind_only() {
    let steering = r#"{"Steering": {"poses": [{"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}, {"position": [0.0, 0.0, 0.0], "orientation": [0.0, 0.0, 0.0, 1.0]}], "distances": [1.0, 2.0], "direction": "left", "status": "turning"}}"#;
    let register_steering = format!(
        r#"{{"input": {{"Register": {{"id": "{}", "module": {MODULE}, "decision": "activate", "geometry": {steering}}}}}}}"#,
        uuid(2)
    );
    let velocity_status = format!(
        r#"{{"id": "{}", "module_decision": "activate", "operator_decision": "none", "cancellable": true}}"#,
        uuid(1)
    );
    let base = format!("{CONFIG}\n{}\n{register_steering}\n", register(0, 1));
    let conforming =
        format!("{base}{{\"factors\": \"Velocity\", \"observed\": [{velocity_status}]}}\n");
    assert!(validate(conforming.as_bytes(), &Options::default())
        .unwrap()
        .conforms());
    let wrong_list =
        format!("{base}{{\"factors\": \"Steering\", \"observed\": [{velocity_status}]}}\n");
    let Verdict::Departs(departure) = validate(wrong_list.as_bytes(), &Options::default()).unwrap()
    else {
        panic!("departs");
    };
    let expected: Vec<(&str, &str)> = departure
        .differences
        .iter()
        .map(|d| (d.expected.as_str(), d.observed.as_str()))
        .collect();
    assert_eq!(
        expected,
        [
            ("not a steering factor: a velocity scene", "live"),
            ("live", "absent"),
        ]
    );
}

fn seed_like() -> String {
    let mut text = include_str!("data/two-modules-conforming.jsonl").to_owned();
    text += include_str!("data/policy-clobber-departs.jsonl");
    text
}

/// Reads anything, to its end or its first error, without panicking; any error names a line
/// unless it is about the output.
fn survives(bytes: &[u8]) {
    let limits = ReadLimits {
        max_line_bytes: 4_096,
        max_lines: 400,
    };
    let options = Options {
        limits,
        config: None,
    };
    for json in [false, true] {
        let mut out = Vec::new();
        if let Err(error) = replay(bytes, &mut out, &options, json) {
            assert!(error.line.is_some(), "{error}");
            assert!(!error.to_string().is_empty());
        }
    }
    if let Ok(Verdict::Departs(departure)) = validate(bytes, &options) {
        assert!(!departure.differences.is_empty());
        let _ = verdict_text(&Verdict::Departs(departure.clone()));
        verdict_json(&Verdict::Departs(departure)).unwrap();
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2_048)) {
        survives(&bytes);
    }

    #[test]
    fn mutated_traces_never_panic(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        cut in any::<prop::sample::Index>(),
    ) {
        let mut bytes = seed_like().into_bytes();
        for (at, byte) in edits {
            let at = at.index(bytes.len());
            bytes[at] = byte;
        }
        bytes.truncate(cut.index(bytes.len() + 1));
        survives(&bytes);
    }

    #[test]
    fn shuffled_lines_never_panic(order in Just(seed_like().lines().map(str::to_owned).collect::<Vec<_>>()).prop_shuffle()) {
        survives(order.join("\n").as_bytes());
    }
}

/// `BufRead` over a slice is what the fuzz target will hand in; the line reader only asks for
/// `BufRead`.
#[test]
fn any_bufread_will_do() {
    fn assert_bufread<R: BufRead>(_: &R) {}
    assert_bufread(&BufReader::new(io::empty()));
    let summary = replay_text("").unwrap();
    assert_eq!(
        summary,
        Summary {
            steps: 0,
            observations: 0,
            lines: 0
        }
    );
    assert_eq!(
        validate(&b"# only a comment\n"[..], &Options::default()).unwrap(),
        Verdict::Conforms {
            steps: 0,
            observations: 0
        }
    );
}
