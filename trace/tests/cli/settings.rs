//! `--settings FILE`: the configuration from a ROS 2 parameter file, in place of a trace's
//! `config` line or a `--config` JSON file.

use std::path::Path;

use super::{data, run, stderr, stdout};

/// Writes `text` to a file named `name` in the tests' scratch directory.
fn scratch(name: &str, text: &str) -> String {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

/// The seed trace with its `config` line made a comment (so that line numbers stay).
fn seed_without_config() -> (String, String) {
    let seed = std::fs::read_to_string(data("seed.jsonl")).unwrap();
    let config_line = seed.lines().find(|l| l.starts_with("{\"config\"")).unwrap();
    let without = seed.replacen(config_line, "# configured by --settings", 1);
    (seed, without)
}

/// The seed's configuration as a settings file: lane-change, optional.
const SEED_SETTINGS: &str = "\
/**:
  ros__parameters:
    cooperation:
      policies:
        lane-change: optional
";

#[test]
fn a_settings_file_replaces_the_config_line() {
    let (seed, without) = seed_without_config();
    let file = scratch("seed.param.yaml", SEED_SETTINGS);
    let with_line = run(&["replay", &data("seed.jsonl").to_string_lossy()], "");
    assert_eq!(with_line.status.code(), Some(0), "{}", stderr(&with_line));
    for mode in ["replay", "validate"] {
        let output = run(&[mode, "--settings", &file, "-"], &without);
        assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
        if mode == "replay" {
            assert_eq!(stdout(&output), stdout(&with_line));
        } else {
            assert!(
                stdout(&output).starts_with("conforms"),
                "{}",
                stdout(&output)
            );
        }
    }
    // With both, the config line is refused, as with --config.
    let output = run(&["replay", "--settings", &file, "-"], &seed);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("line 3: field `config`"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn the_example_settings_file_configures_a_replay() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../config/cooperation.param.yaml");
    let (_, without) = seed_without_config();
    let output = run(
        &["replay", "--settings", example.to_str().unwrap(), "-"],
        &without,
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
}

#[test]
fn a_settings_error_names_the_file_line_and_key() {
    let (_, without) = seed_without_config();
    let file = scratch(
        "misspelt.param.yaml",
        &SEED_SETTINGS.replace("policies", "polices"),
    );
    let output = run(&["replay", "--settings", &file, "-"], &without);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(stdout(&output), "");
    assert_eq!(
        stderr(&output),
        format!(
            "error: {file}: line 4, column 7: /**.ros__parameters.cooperation.polices: unknown \
             key \"polices\"; expected one of `policies`, `limits`, `interfaces`\n"
        )
    );
}

#[test]
fn a_settings_limit_is_bounded_as_a_config_lines_is() {
    let (_, without) = seed_without_config();
    // 65 536 live scenes at most, as `MAX_LIMITS` says.
    let within = scratch(
        "within.param.yaml",
        &format!("{SEED_SETTINGS}      limits:\n        max_scenes: 65536\n"),
    );
    let output = run(&["replay", "--settings", &within, "-"], &without);
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let above = scratch(
        "above.param.yaml",
        &format!("{SEED_SETTINGS}      limits:\n        max_scenes: 65537\n"),
    );
    let output = run(&["replay", "--settings", &above, "-"], &without);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {above}: line 7, column 21: /**.ros__parameters.cooperation.limits.max_scenes: \
             65537 is more than the 65536 allowed here\n"
        )
    );
}

#[test]
fn a_settings_file_that_cannot_be_read_is_refused() {
    let (_, without) = seed_without_config();
    let not_utf8 = Path::new(env!("CARGO_TARGET_TMPDIR")).join("not-utf8.param.yaml");
    std::fs::write(&not_utf8, b"/**:\n  \xff\n").unwrap();
    let not_utf8 = not_utf8.to_str().unwrap();
    let output = run(&["replay", "--settings", not_utf8, "-"], &without);
    assert_eq!(output.status.code(), Some(2));
    assert_eq!(
        stderr(&output),
        format!("error: {not_utf8}: the file is not UTF-8 at byte 7\n")
    );
    let output = run(
        &["replay", "--settings", "/nonexistent/a.yaml", "-"],
        &without,
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).starts_with("error: /nonexistent/a.yaml: "),
        "{}",
        stderr(&output)
    );
}

#[test]
fn config_and_settings_together_are_a_usage_error() {
    let json = scratch("both.json", "{\"policies\": []}");
    let yaml = scratch("both.param.yaml", SEED_SETTINGS);
    for (args, message) in [
        (
            vec!["replay", "--config", &json, "--settings", &yaml, "-"],
            "--config and --settings both give the configuration; give one",
        ),
        (
            vec!["validate", "--settings", &yaml, "--config", &json, "-"],
            "--config and --settings both give the configuration; give one",
        ),
        (
            vec!["replay", "--settings", &yaml, "--settings", &yaml, "-"],
            "--settings is given twice",
        ),
        (vec!["replay", "--settings"], "--settings needs a file"),
    ] {
        let output = run(&args, "");
        assert_eq!(output.status.code(), Some(2), "{args:?}");
        assert_eq!(
            stderr(&output),
            format!("error: {message} (see cooperation-trace --help)\n"),
            "{args:?}"
        );
    }
    let help = run(&["--help"], "");
    assert!(stdout(&help).contains("[--config FILE | --settings FILE]"));
    assert!(stdout(&help).contains("--settings the configuration as a ROS 2 parameter file"));
}
