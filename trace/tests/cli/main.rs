//! The `cooperation-trace` binary on the checked-in traces: its output and exit codes.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use serde_json::Value;

mod settings;

const SCENE: &str = "00000000-0000-0000-0000-000000005678";

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Runs the binary with `args`, feeding `stdin` to it.
fn run(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_cooperation-trace"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    // The binary may stop reading early (an error, a departure): a broken pipe is fine.
    let _ = child
        .stdin
        .take()
        .expect("stdin")
        .write_all(stdin.as_bytes());
    child.wait_with_output().expect("the binary finishes")
}

fn run_file(args: &[&str], file: &str) -> Output {
    let path = data(file);
    let mut all = args.to_vec();
    all.push(path.to_str().expect("UTF-8 path"));
    run(&all, "")
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).expect("UTF-8 output")
}

fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).expect("UTF-8 output")
}

fn json_lines(output: &Output) -> Vec<Value> {
    stdout(output)
        .lines()
        .map(|line| serde_json::from_str(line).expect("one JSON object per line"))
        .collect()
}

#[test]
fn replay_prints_each_step_rule_and_table() {
    let output = run_file(&["replay"], "seed.jsonl");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let text = stdout(&output);
    let headings: Vec<&str> = text.lines().filter(|l| l.starts_with("step ")).collect();
    assert_eq!(
        headings,
        [
            format!("step 1, line 9, at 0 ms: register {SCENE} lane-change deactivate steering -> COOP-REG-NEW.1"),
            "step 2, line 12, at 500 ms: time +500 ms -> COOP-TIME-AGE.1".into(),
            format!("step 3, line 12, at 500 ms: set_commands [{SCENE} activate] -> COOP-CMD-APPLY.1"),
            "step 4, line 16, at 600 ms: time +100 ms -> COOP-TIME-AGE.1".into(),
            format!("step 5, line 16, at 600 ms: update {SCENE} lane-change waiting deactivate -> COOP-OWN-UPDATE.1"),
        ]
    );
    // After the last step: module deactivate, operator activate, merged activate, forced.
    let last_row: Vec<&str> = text
        .lines()
        .last()
        .expect("a table row")
        .split_whitespace()
        .collect();
    assert_eq!(
        last_row,
        [
            SCENE,
            "lane-change",
            "waiting",
            "deactivate",
            "activate",
            "yes",
            "optional",
            "activate",
            "activated"
        ]
    );
    // After the first step: merged is the module's deactivate; no operator decision.
    let first_row: Vec<&str> = text
        .lines()
        .nth(2)
        .expect("a table row")
        .split_whitespace()
        .collect();
    assert_eq!(
        first_row,
        [
            SCENE,
            "lane-change",
            "waiting",
            "deactivate",
            "none",
            "yes",
            "optional",
            "deactivate",
            "-"
        ]
    );
}

#[test]
fn replay_json_is_one_object_per_step() {
    let output = run_file(&["replay", "--json"], "seed.jsonl");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let steps = json_lines(&output);
    let rules: Vec<&str> = steps.iter().map(|s| s["rule"].as_str().unwrap()).collect();
    assert_eq!(
        rules,
        [
            "COOP-REG-NEW.1",
            "COOP-TIME-AGE.1",
            "COOP-CMD-APPLY.1",
            "COOP-TIME-AGE.1",
            "COOP-OWN-UPDATE.1"
        ]
    );
    let generated: Vec<bool> = steps
        .iter()
        .map(|s| s["generated"].as_bool().unwrap())
        .collect();
    assert_eq!(generated, [false, true, false, true, false]);
    assert_eq!(steps[1]["input"]["Tick"]["elapsed_ms"], 500);
    let scene = |step: usize| &steps[step]["scenes"][0];
    assert_eq!(scene(0)["id"], SCENE);
    assert_eq!(scene(0)["module_decision"], "deactivate");
    assert_eq!(scene(0)["operator_decision"], "none");
    assert_eq!(scene(0)["cancellable"], true);
    assert_eq!(scene(0)["policy"], "optional");
    assert_eq!(scene(0)["merged_decision"], "deactivate");
    assert_eq!(scene(2)["operator_decision"], "activate");
    assert_eq!(scene(4)["merged_decision"], "activate");
    assert_eq!(scene(4)["force_activated"], true);
    assert_eq!(scene(4)["force_deactivated"], false);
    for step in &steps {
        assert_eq!(step["accepted"], true);
        assert_eq!(step["rejection"], Value::Null);
    }
}

/// A replay's JSON scenes are statuses in the form `observed` takes: appending them to the
/// trace as an observation gives a trace that conforms.
#[test]
fn replay_json_scenes_serve_as_observations() {
    let output = run_file(&["replay", "--json"], "two-modules-conforming.jsonl");
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let steps = json_lines(&output);
    let trace = std::fs::read_to_string(data("two-modules-conforming.jsonl")).unwrap();
    // The state after step 9 (the policy change), observed right after it.
    let step = &steps[8];
    assert_eq!(step["rule"], "COOP-POL-SET.1");
    let line = step["line"].as_u64().unwrap() as usize;
    let observation = serde_json::json!({ "observed": step["scenes"] }).to_string();
    let mut lines: Vec<&str> = trace.lines().collect();
    lines.insert(line, &observation);
    let output = run(&["validate", "-"], &lines.join("\n"));
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert_eq!(
        stdout(&output),
        "conforms: 14 steps, 6 observations agree with the spec\n"
    );
}

#[test]
fn validate_conforming_traces_exit_zero() {
    let output = run_file(&["validate"], "seed-conforming.jsonl");
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert_eq!(
        stdout(&output),
        "conforms: 7 steps, 3 observations agree with the spec\n"
    );
    let output = run_file(&["validate", "--json"], "two-modules-conforming.jsonl");
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert_eq!(
        json_lines(&output),
        [serde_json::json!({"verdict": "conforms", "steps": 14, "observations": 5})]
    );
}

/// Statuses as the AD API reports them (rosbridge JSON; UUIDs as numbers and as base64) are
/// read as well as the core's form, and a departure in that form is found.
#[test]
fn validate_reads_statuses_in_the_ad_api_form() {
    let output = run_file(&["validate"], "seed-conforming-wire.jsonl");
    assert_eq!(output.status.code(), Some(0), "{}", stdout(&output));
    assert_eq!(
        stdout(&output),
        "conforms: 7 steps, 3 observations agree with the spec\n"
    );
    let text = std::fs::read_to_string(data("seed-conforming-wire.jsonl")).expect("reads");
    // The operator's ACTIVATE (2) reported as UNDECIDED (4) after the command.
    let departed = text.replacen(
        r#""cooperator": {"decision": 2}"#,
        r#""cooperator": {"decision": 4}"#,
        1,
    );
    assert_ne!(departed, text);
    let output = run(&["validate", "-"], &departed);
    assert_eq!(output.status.code(), Some(1), "{}", stdout(&output));
    assert!(
        stdout(&output).contains("operator_decision: expected activate, observed none"),
        "{}",
        stdout(&output)
    );
    // A malformed AD API status names its field.
    let broken = text.replacen(
        r#""autonomous": {"decision": 1}"#,
        r#""autonomous": {"decision": 9}"#,
        1,
    );
    let output = run(&["validate", "-"], &broken);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("autonomous"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn validate_reports_the_first_departure() {
    let output = run_file(&["validate"], "policy-clobber-departs.jsonl");
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        format!(
            "departs at line 11 (after step 8, at 500 ms)\n  \
             scene {SCENE} operator_decision: expected activate, observed none\n    \
             rule involved: COOP-CMD-APPLY.1 (step 4, line 7)\n  \
             last input before it: COOP-POL-SET.1 (step 7, line 9)\n"
        )
    );
    let output = run_file(&["validate", "--json"], "policy-clobber-departs.jsonl");
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        json_lines(&output),
        [serde_json::json!({
            "verdict": "departs",
            "line": 11,
            "after_step": 8,
            "at_ms": 500,
            "last_input": {"rule": "COOP-POL-SET.1", "step": 7, "line": 9},
            "differences": [{
                "scene": SCENE,
                "field": "operator_decision",
                "expected": "activate",
                "observed": "none",
                "rule": {"rule": "COOP-CMD-APPLY.1", "step": 4, "line": 7},
            }],
        })]
    );
}

/// Validation stops at the first departure: a malformed line after it is never read.
#[test]
fn validate_stops_at_the_first_departure() {
    let trace = std::fs::read_to_string(data("policy-clobber-departs.jsonl")).unwrap();
    let output = run(&["validate", "-"], &format!("{trace}not JSON\n"));
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(stdout(&output).starts_with("departs at line 11 "));
}

#[test]
fn malformed_lines_exit_two_naming_line_and_field() {
    let seed = std::fs::read_to_string(data("seed.jsonl")).unwrap();
    let broken = seed.replacen("\"deactivate\"", "\"Maybe\"", 1);
    for mode in ["replay", "validate"] {
        let output = run(&[mode, "-"], &broken);
        assert_eq!(output.status.code(), Some(2), "{mode}");
        let error = stderr(&output);
        assert!(
            error.starts_with(
                "error: -: line 9: field `input.Register.decision`: unknown variant `Maybe`"
            ),
            "{error}"
        );
    }
    // Replay prints the steps before the malformed line, then fails.
    let bad_input = format!("{seed}{{\"at_ms\": 700, \"input\": {{\"Frob\": {{}}}}}}\n");
    let output = run(&["replay", "-"], &bad_input);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        stdout(&output)
            .lines()
            .filter(|l| l.starts_with("step "))
            .count(),
        5,
        "the five steps; a malformed record is refused whole, its time included"
    );
    assert!(
        stderr(&output).contains("line 17: field `input`: unknown variant `Frob`, expected one of"),
        "{}",
        stderr(&output)
    );
    // Time going backwards.
    let backwards = format!("{seed}{{\"at_ms\": 599}}\n");
    let output = run(&["validate", "-"], &backwards);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        stderr(&output),
        "error: -: line 17: field `at_ms`: time goes backwards, from 600 ms to 599 ms\n"
    );
}

#[test]
fn config_file_replaces_the_config_line() {
    let seed = std::fs::read_to_string(data("seed.jsonl")).unwrap();
    let config_line = seed.lines().find(|l| l.starts_with("{\"config\"")).unwrap();
    let config: Value = serde_json::from_str(config_line).unwrap();
    let file = Path::new(env!("CARGO_TARGET_TMPDIR")).join("seed-config.json");
    std::fs::write(&file, config["config"].to_string()).unwrap();
    let file = file.to_str().unwrap();
    // The config line becomes a comment, so that line numbers stay.
    let without = seed.replacen(config_line, "# configured by --config", 1);
    let output = run(&["replay", "--config", file, "-"], &without);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    assert_eq!(
        stdout(&output),
        stdout(&run_file(&["replay"], "seed.jsonl"))
    );
    // Without it, the first record lacks a configuration.
    let output = run(&["replay", "-"], &without);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("line 9: no configuration"));
    // With both, the config line is refused.
    let output = run(&["replay", "--config", file, "-"], &seed);
    assert_eq!(output.status.code(), Some(2));
    assert!(stderr(&output).contains("line 3: field `config`"));
}

#[test]
fn usage_errors_exit_two_and_help_exits_zero() {
    for args in [
        &[][..],
        &["frob"],
        &["replay"],
        &["replay", "--frob", "x"],
        &["replay", "a", "b"],
        &["validate", "--config"],
        &["replay", "/nonexistent/trace.jsonl"],
    ] {
        let output = run(args, "");
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert!(stderr(&output).starts_with("error: "), "{args:?}");
    }
    let output = run(&["--help"], "");
    assert_eq!(output.status.code(), Some(0));
    assert!(stdout(&output).contains("usage: cooperation-trace replay"));
}
