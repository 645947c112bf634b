//! The binary when its output cannot be written, and the size of what it prints about
//! hostile input.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_cooperation-trace");

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).expect("UTF-8 output")
}

/// Runs the binary through the shell with `redirect` applied to it.
fn run_redirected(args: &[&str], redirect: &str) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(format!("exec \"$0\" \"$@\" {redirect}"))
        .arg(BIN)
        .args(args)
        .stdin(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .expect("sh runs")
}

/// Runs the binary on `file` with `args`, its standard output a pipe whose reader has gone:
/// the shell makes the pipe, so no other process holds its reading end, and the binary's
/// input comes a second late, once the reader has exited. Gives the binary's exit code, which
/// the shell writes last on standard error, and what the binary wrote there.
fn run_broken_pipe(args: &[&str], file: &Path) -> (Option<i32>, String) {
    let output = Command::new("sh")
        .arg("-c")
        .arg(r#"f=$1; shift; (sleep 1; cat "$f") | { "$0" "$@"; echo "exit $?" >&2; } | :"#)
        .arg(BIN)
        .arg(file)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .expect("sh runs");
    let text = stderr(&output);
    let (shown, code) = text
        .trim_end()
        .rsplit_once("exit ")
        .expect("the shell reports the exit code");
    (code.parse().ok(), shown.to_owned())
}

fn run(args: &[&str], stdin: &[u8]) -> Output {
    let mut child = Command::new(BIN)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let _ = child.stdin.take().expect("stdin").write_all(stdin);
    child.wait_with_output().expect("the binary finishes")
}

#[test]
fn a_closed_standard_output_is_a_write_error() {
    let seed = data("seed.jsonl");
    let seed = seed.to_str().unwrap();
    let departs = data("policy-clobber-departs.jsonl");
    let departs = departs.to_str().unwrap();
    for args in [
        &["replay", seed][..],
        &["replay", "--json", seed],
        &["validate", seed],
        &["validate", "--json", departs],
        &["--help"],
        // Refused before the trace is opened.
        &["replay", "/nonexistent/trace.jsonl"],
    ] {
        let output = run_redirected(args, ">&-");
        assert_eq!(
            output.status.code(),
            Some(2),
            "{args:?}: {}",
            stderr(&output)
        );
        assert!(
            stderr(&output).starts_with("error: cannot write the output"),
            "{args:?}: {}",
            stderr(&output)
        );
        // Output thrown away on purpose is written.
        let output = run_redirected(args, ">/dev/null");
        if args.contains(&"/nonexistent/trace.jsonl") {
            continue;
        }
        let expected = if args.contains(&departs) { 1 } else { 0 };
        assert_eq!(
            output.status.code(),
            Some(expected),
            "{args:?}: {}",
            stderr(&output)
        );
        assert_eq!(stderr(&output), "", "{args:?}");
    }
}

#[test]
fn a_broken_pipe_is_a_write_error() {
    let seed = data("seed.jsonl");
    let departs = data("policy-clobber-departs.jsonl");
    let cases = [
        (&["replay", "-"][..], &seed),
        (&["replay", "--json", "-"], &seed),
        (&["validate", "-"], &seed),
        (&["validate", "-"], &departs),
    ];
    // Each waits a second for its input: all at once.
    std::thread::scope(|scope| {
        let runs: Vec<_> = cases
            .iter()
            .map(|&(args, input)| (args, scope.spawn(move || run_broken_pipe(args, input))))
            .collect();
        for (args, run) in runs {
            let (code, shown) = run.join().expect("the run finishes");
            assert_eq!(code, Some(2), "{args:?}: {shown}");
            assert!(
                shown.starts_with("error: cannot write the output"),
                "{args:?}: {shown}"
            );
        }
    });
}

#[test]
fn messages_about_hostile_input_stay_short() {
    let seed = std::fs::read_to_string(data("seed.jsonl")).unwrap();
    let long = "x".repeat(500_000);
    for trace in [
        format!("{seed}{{\"{long}\": 1}}\n"),
        format!("{seed}{{\"at_ms\": 700, \"input\": {{\"Remove\": {{\"{long}\": 1}}}}}}\n"),
        format!("{seed}{{\"at_ms\": 700, \"factors\": \"{long}\", \"observed\": []}}\n"),
    ] {
        let output = run(&["validate", "-"], trace.as_bytes());
        assert_eq!(output.status.code(), Some(2));
        let error = stderr(&output);
        assert!(error.len() < 512, "{} bytes", error.len());
        assert!(error.starts_with("error: -: line 17: "), "{error}");
    }
    // Arguments are shorter: the system limits each one (to 128 KiB on Linux).
    let long = "x".repeat(100_000);
    for args in [
        vec!["replay".to_owned(), format!("--{long}"), "-".to_owned()],
        vec![long.clone()],
        vec!["replay".to_owned(), "a".to_owned(), long.clone()],
    ] {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let output = run(&args, b"");
        assert_eq!(output.status.code(), Some(2));
        assert!(stderr(&output).len() < 512, "{}", stderr(&output).len());
    }
    // A line that is not UTF-8 is located.
    let mut trace = seed.into_bytes();
    trace.extend_from_slice(b"{\"at_ms\": 7\xff}\n");
    let output = run(&["replay", "-"], &trace);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).contains("line 17: the line is not UTF-8 at byte 11 (column 12)"),
        "{}",
        stderr(&output)
    );
}

#[test]
fn the_configuration_file_is_bounded_and_checked() {
    let body = r#"{"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}"#;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let trace = "{\"at_ms\": 0}\n";
    let at_limit = dir.join("config-at-limit.json");
    std::fs::write(
        &at_limit,
        format!("{body}{}", " ".repeat((1 << 20) - body.len())),
    )
    .unwrap();
    let output = run(
        &["replay", "--config", at_limit.to_str().unwrap(), "-"],
        trace.as_bytes(),
    );
    assert_eq!(output.status.code(), Some(0), "{}", stderr(&output));
    let over = dir.join("config-over-limit.json");
    std::fs::write(
        &over,
        format!("{body}{}", " ".repeat((1 << 20) - body.len() + 1)),
    )
    .unwrap();
    let output = run(
        &["replay", "--config", over.to_str().unwrap(), "-"],
        trace.as_bytes(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output)
            .ends_with("config-over-limit.json: the file is longer than 1048576 bytes\n"),
        "{}",
        stderr(&output)
    );
    let latin1 = dir.join("config-latin1.json");
    std::fs::write(&latin1, b"{\"policies\": [], \"caf\xe9\": 1}").unwrap();
    let output = run(
        &["replay", "--config", latin1.to_str().unwrap(), "-"],
        trace.as_bytes(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output).ends_with("config-latin1.json: the file is not UTF-8 at byte 21\n"),
        "{}",
        stderr(&output)
    );
    let twice = dir.join("config-twice.json");
    std::fs::write(&twice, r#"{"policies": [], "policies": []}"#).unwrap();
    let output = run(
        &["replay", "--config", twice.to_str().unwrap(), "-"],
        trace.as_bytes(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(
        stderr(&output)
            .contains("field `config.policies`: duplicate field `policies`: given twice"),
        "{}",
        stderr(&output)
    );
}
