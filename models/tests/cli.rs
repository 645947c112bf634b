//! The checker command fails loudly: it stops at the first violation with its shortest
//! counterexample saved, and a run that would outgrow its budget ends with a report, the word
//! "incomplete" and a non-zero exit status, never as a process the system had to kill. The swarm
//! simulator exits 1 on a violation, with a trace that replays.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh folder under the system's temporary one, removed with what is in it when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let folder = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&folder);
        Self(folder)
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs `cooperation-models check` with `args`, counterexamples under a fresh folder; gives the
/// exit code, the standard output and the folder (removed when it is dropped).
fn check(name: &str, args: &[&str]) -> (Option<i32>, String, Scratch) {
    let out = Scratch::new(&format!("cooperation-cli-{name}"));
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .arg("check")
        .args(args)
        .arg("--out")
        .arg(&*out)
        .output()
        .expect("the checker runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    (output.status.code(), stdout, out)
}

fn saved(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |entries| {
        entries
            .filter_map(Result::ok)
            .filter(|e| e.path().extension().is_some_and(|x| x == "json"))
            .count()
    })
}

#[test]
fn a_correct_model_passes_with_status_zero() {
    let (code, stdout, _) = check("pass", &["--modules", "1", "--scenes", "2"]);
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("satisfied, 0 violated"), "{stdout}");
    assert!(!stdout.contains("incomplete"), "{stdout}");
}

/// `--strategy bfs` keeps symmetry through canonical states, with the depth-first counts, on
/// the default table; on the hashed table (whose history a renaming would lose) it turns
/// symmetry off and says so.
#[test]
fn breadth_first_keeps_symmetry_through_canonical_states() {
    let pin = cooperation_models::check::pins::SEQUENTIAL_2X2_SYMMETRY;
    let (code, stdout, _) = check(
        "canonical",
        &["--modules", "2", "--scenes", "2", "--strategy", "bfs"],
    );
    assert_eq!(code, Some(0), "{stdout}");
    assert!(
        stdout.contains("Bfs, 2 thread(s), symmetry on (canonical states)"),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("{} unique states", pin.unique)),
        "{stdout}"
    );
    let (code, stdout, _) = check(
        "canonical-hashed",
        &[
            "--modules",
            "1",
            "--scenes",
            "2",
            "--strategy",
            "bfs",
            "--table",
            "hashed",
        ],
    );
    assert_eq!(code, Some(0), "{stdout}");
    assert!(
        stdout.contains("Bfs, 2 thread(s), symmetry off"),
        "{stdout}"
    );
}

#[test]
fn the_first_violation_stops_the_check_with_a_saved_counterexample() {
    let (code, stdout, out) = check("first", &["--fault", "RetiredIdReused"]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("| VIOLATED | always | COOP-REG-RETIRED.1"),
        "{stdout}"
    );
    assert!(
        stdout.contains("incomplete: stopped at the first violated property"),
        "{stdout}"
    );
    assert!(
        stdout.contains("shortest counterexample, 3 steps"),
        "{stdout}"
    );
    assert!(
        saved(&out) > 0,
        "no counterexample saved in {}",
        out.display()
    );
}

/// The fault that, collecting every violation, grew a check to 24 GiB until the kernel killed
/// it: the memory budget ends it instead, with its report.
#[test]
fn a_space_exploding_fault_ends_within_the_memory_budget() {
    let args = [
        "--fault",
        "RetiredIdReused",
        "--keep-going",
        "--memory-gib",
        "1",
    ];
    let (code, stdout, out) = check("memory", &args);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("incomplete: stopped after reaching the memory budget"),
        "{stdout}"
    );
    assert!(
        stdout.contains("unknown (the search is incomplete)"),
        "{stdout}"
    );
    assert!(stdout.contains("| VIOLATED |"), "{stdout}");
    assert!(
        saved(&out) > 0,
        "no counterexample saved in {}",
        out.display()
    );
}

#[test]
fn the_state_budget_ends_a_correct_check_as_incomplete() {
    let (code, stdout, _) = check("states", &["--max-states", "20000"]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("incomplete: stopped after reaching the state budget"),
        "{stdout}"
    );
    assert!(stdout.contains("0 violated"), "{stdout}");
    assert!(
        !stdout.contains("| holds |"),
        "an incomplete search proves nothing: {stdout}"
    );
}

#[test]
fn bad_usage_exits_with_status_two() {
    let (code, _, _) = check("usage", &["--memory-gib", "lots"]);
    assert_eq!(code, Some(2));
}

/// A `--views` value the network model does not know is bad usage, said plainly.
#[test]
fn a_bad_views_value_is_bad_usage() {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .args(["check", "--model", "network", "--views", "decisions"])
        .output()
        .expect("the checker runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--views is ids or statuses, not \"decisions\""),
        "{stderr}"
    );
}

/// So is a number of operators the network model cannot have.
#[test]
fn a_bad_operator_count_is_bad_usage() {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .args(["check", "--model", "network", "--operators", "3"])
        .output()
        .expect("the checker runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("operators must be 1 to 2"), "{stderr}");
}

/// `--help` describes the network model's options.
#[test]
fn help_describes_the_network_options() {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .arg("--help")
        .output()
        .expect("the checker runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("--operators 1|2"), "{stdout}");
    assert!(stdout.contains("--views ids|statuses"), "{stdout}");
}

/// `--help` after a command, or `-h`, prints the usage and succeeds, rather than reading as an
/// option that lacks a value.
#[test]
fn help_after_a_command_prints_the_usage() {
    for args in [
        &["check", "--help"][..],
        &["reach", "-h"],
        &["check", "--model", "rtc", "-h"],
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
            .args(args)
            .output()
            .expect("the checker runs");
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert_eq!(output.status.code(), Some(0), "{args:?}: {stdout}");
        assert!(stdout.contains("usage:"), "{args:?}: {stdout}");
        assert!(
            stdout.contains("--model sequential|network|rtc"),
            "{stdout}"
        );
    }
}

/// `--depth` bounds the search, and the report says the check is complete to that depth only;
/// witnesses out of reach within two steps leave it unsatisfied (exit status 1).
#[test]
fn a_depth_bound_is_reported_as_such() {
    let (code, stdout, _) = check(
        "depth",
        &["--modules", "1", "--scenes", "2", "--depth", "2"],
    );
    assert_eq!(code, Some(1), "{stdout}");
    assert!(stdout.contains(", 0 violated, "), "{stdout}");
    assert!(
        stdout.contains("complete to depth 2 only (--depth): longer paths are unchecked"),
        "{stdout}"
    );
    assert!(
        stdout.contains("depth 3,"),
        "stateright counts the initial state: {stdout}"
    );
}

/// Runs `cooperation-models simulate` with `args`; gives the exit code, standard output and
/// standard error.
fn simulate(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .arg("simulate")
        .args(args)
        .output()
        .expect("the simulator runs");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

/// `simulate`'s limits, as its usage states them: seeds `A..B` with A below B, 1 to 8 modules,
/// 1 to 64 identifiers; anything else is bad usage (status 2), said plainly.
#[test]
fn simulate_refuses_what_its_usage_does_not_allow() {
    for (args, says) in [
        (&["--seeds", "5..5"][..], "--seeds takes A..B"),
        (&["--seeds", "7"][..], "--seeds takes A..B"),
        (&["--modules", "9"][..], "modules must be 1 to 8"),
        (&["--scenes", "65"][..], "scenes must be 1 to 64"),
    ] {
        let (code, _, stderr) = simulate(args);
        assert_eq!(code, Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

/// A passing swarm exits 0 with its report; a swarm that finds a violation exits 1, names the
/// walk's seed, and saves a trace that `replay` replays to the violation (status 1 too).
#[test]
fn simulate_exits_one_on_a_violation_with_a_trace_that_replays() {
    let large = [
        "--modules",
        "8",
        "--scenes",
        "64",
        "--live",
        "32",
        "--retired",
        "16",
    ];
    let (code, stdout, _) = simulate(&[&large[..], &["--seeds", "0..4"]].concat());
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("| COOP-REG-FULL.1 |"), "{stdout}");
    assert!(
        stdout.contains("no property violated in 4 walks"),
        "{stdout}"
    );

    let out = Scratch::new("cooperation-swarm");
    let faulty = [
        "--seeds",
        "0..4",
        "--fault",
        "CommandToggles",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    let (code, stdout, _) = simulate(&[&large[..], &faulty[..]].concat());
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("stopped at the first violation: walk"),
        "{stdout}"
    );
    assert_eq!(saved(&out), 1);
    let trace = std::fs::read_dir(&*out)
        .expect("saved")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|x| x == "json"))
        .expect("a trace");
    let replay = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .arg("replay")
        .arg(&trace)
        .output()
        .expect("replays");
    let replayed = String::from_utf8_lossy(&replay.stdout);
    assert_eq!(replay.status.code(), Some(1), "{replayed}");
    assert!(replayed.contains("the property is violated"), "{replayed}");
}

/// `--planner` is core or engine, and a fault of the core cannot be planted through the
/// engine: each is bad usage, said plainly.
#[test]
fn a_bad_planner_or_a_core_fault_through_the_engine_is_bad_usage() {
    for (args, said) in [
        (
            &["--planner", "node"][..],
            "--planner is core or engine, not \"node\"",
        ),
        (
            &["--planner", "engine", "--fault", "CommandToggles"],
            "--fault CommandToggles is a fault of the core's transition",
        ),
    ] {
        let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
            .args(["check", "--model", "network"])
            .args(args)
            .output()
            .expect("the checker runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(said), "{args:?}: {stderr}");
    }
}
