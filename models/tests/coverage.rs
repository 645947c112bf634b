//! The rule-pair coverage of the sequential model (docs/verification.md, *Small scopes*):
//! measured at the small bounds, it holds the pairs the argument needs, grows only with the
//! bounds, is the same with and without symmetry reduction and on any number of threads, and
//! runs with every fault injected; the command reports it, saves it, and says when it stopped
//! early.

use std::process::Command;

use cooperation::Rule::{
    CommandApply, CommandRetired, OwnerFinish, OwnerUpdate, PolicySet, RegisterFull, RegisterNew,
    TimeExpire,
};
use cooperation::{Input, Rule};
use cooperation_models::check::budget::Halt;
use cooperation_models::check::coverage::{explore, named, Found, Pairs, Progress, Record, Scope};
use cooperation_models::check::run::{check, Settings, Strategy};
use cooperation_models::{Bounds, Fault, SequentialModel};

fn measure(model: &SequentialModel, symmetry: bool, threads: usize) -> Found {
    let found = explore(model, symmetry, threads, &Progress::default(), &Halt::new())
        .expect("the search runs");
    assert!(found.complete, "the search did not complete");
    found
}

fn model(modules: usize, scenes: usize) -> SequentialModel {
    SequentialModel::new(Bounds::new(modules, scenes)).expect("valid bounds")
}

/// Pairs whose absence would be a gap in the model: an owner's update after the operator
/// decided, on the same scene (the decision must stand); a command for a scene that has just
/// finished (the race a network delivers); the scene limit refusing one scene while another
/// runs on; a finished scene making room for a new one. One live scene suffices for each.
const AT_ONE_LIVE: [(Rule, Rule, Scope); 5] = [
    (CommandApply, OwnerUpdate, Scope::Same),
    (OwnerFinish, CommandRetired, Scope::Same),
    (RegisterFull, OwnerUpdate, Scope::Different),
    (OwnerFinish, RegisterNew, Scope::Different),
    (PolicySet, CommandApply, Scope::Unscoped),
];

/// Pairs that need two live scenes: two scenes expiring on successive ticks, an update
/// followed by another scene's expiry, the operator deciding two scenes in turn.
const AT_TWO_LIVE: [(Rule, Rule, Scope); 3] = [
    (TimeExpire, TimeExpire, Scope::Unscoped),
    (OwnerUpdate, TimeExpire, Scope::Unscoped),
    (CommandApply, CommandApply, Scope::Different),
];

fn missing(pairs: &Pairs, wanted: &[(Rule, Rule, Scope)]) -> Vec<(Rule, Rule, Scope)> {
    wanted
        .iter()
        .copied()
        .filter(|(first, then, scope)| !pairs.contains(*first, *then, *scope))
        .collect()
}

#[test]
fn the_small_bounds_hold_the_pairs_the_argument_needs_and_grow_only() {
    let one = measure(&model(1, 2), true, 2).pairs;
    let two = measure(&model(2, 2), true, 2).pairs;
    for scope in Scope::ALL {
        assert!(one.count(scope) > 0, "no pair {}", scope.name());
    }
    assert!(
        one.without(&two).is_empty(),
        "a pair of 1 x 2 is lost at 2 x 2"
    );
    assert_eq!(missing(&one, &AT_ONE_LIVE), []);
    assert_eq!(missing(&two, &AT_ONE_LIVE), []);
    // One live scene at these bounds: nothing can need two.
    assert_eq!(missing(&two, &AT_TWO_LIVE), AT_TWO_LIVE);
}

#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_live_scenes_add_the_pairs_that_need_them() {
    let three = measure(&model(1, 3), true, 2).pairs;
    let two = measure(&model(1, 2), true, 2).pairs;
    assert_eq!(missing(&three, &AT_ONE_LIVE), []);
    assert_eq!(missing(&three, &AT_TWO_LIVE), []);
    assert!(
        two.without(&three).is_empty(),
        "a pair of 1 x 2 is lost at 1 x 3"
    );
}

/// Symmetry reduction loses nothing: the pairs and the states (each class counted with its
/// renamings) are those of the search without it, and the states it expands are the ones the
/// checker expands, so its transitions are the successors the checker is handed when every
/// stalled step is handed over (`with_stalled_merged(false)`: the merged search leaves out the
/// stalled steps it was handed already).
#[test]
fn symmetry_gives_the_pairs_and_states_of_the_search_without_it() {
    for (modules, scenes) in [(1, 2), (2, 2)] {
        let model = model(modules, scenes);
        let (reduced, full) = (measure(&model, true, 2), measure(&model, false, 2));
        let at = format!("{modules} x {scenes}");
        assert_eq!(reduced.pairs, full.pairs, "{at}");
        assert_eq!(reduced.concrete, full.states, "{at}");
        assert!(
            reduced.states < full.states,
            "{at}: symmetry reduced nothing"
        );
        let settings = Settings {
            threads: 1,
            strategy: Strategy::Dfs,
            symmetry: true,
        };
        let unmerged = model.clone().with_stalled_merged(false);
        let report = check(&unmerged, settings, &mut std::io::sink());
        assert!(report.passed(), "{at}");
        assert_eq!(reduced.transitions + 1, report.generated as u64, "{at}");
    }
}

#[test]
fn one_and_two_threads_measure_the_same() {
    let model = model(2, 2);
    let (one, two) = (measure(&model, true, 1), measure(&model, true, 2));
    assert_eq!(
        (one.pairs, one.states, one.arrivals, one.transitions),
        (two.pairs, two.states, two.arrivals, two.transitions)
    );
}

#[test]
fn every_fault_runs_to_completion() {
    for fault in Fault::ALL {
        let model = model(1, 2).with_fault(fault);
        let found = measure(&model, true, 2);
        assert!(!found.pairs.is_empty(), "{fault:?}");
    }
}

#[test]
fn a_halted_search_reports_itself_incomplete() {
    let halt = Halt::new();
    halt.set();
    let progress = Progress::default();
    let found = explore(&model(1, 2), true, 2, &progress, &halt).expect("runs");
    assert!(!found.complete);
}

#[test]
fn pairs_keep_every_rule_and_scope_and_read_back() {
    let mut pairs = Pairs::default();
    for (n, first) in Rule::ALL.into_iter().enumerate() {
        let then = Rule::ALL[(n * 7 + 3) % Rule::ALL.len()];
        let scope = Scope::ALL[n % 3];
        pairs.insert(first, then, scope);
        assert!(pairs.contains(first, then, scope));
    }
    assert_eq!(pairs.len(), Rule::ALL.len());
    assert_eq!(pairs.iter().count(), Rule::ALL.len());
    assert_eq!(
        Scope::ALL.iter().map(|s| pairs.count(*s)).sum::<usize>(),
        Rule::ALL.len()
    );
    let text = serde_json::to_string(&pairs).expect("writes");
    let back: Pairs = serde_json::from_str(&text).expect("reads");
    assert_eq!(back, pairs);
}

#[test]
fn scopes_compare_the_identifiers_named() {
    assert_eq!(Scope::of(0b01, 0b11), Scope::Same);
    assert_eq!(Scope::of(0b01, 0b10), Scope::Different);
    assert_eq!(Scope::of(0, 0b10), Scope::Unscoped);
    assert_eq!(Scope::of(0b01, 0), Scope::Unscoped);
    let model = model(1, 3);
    let tick = model
        .alphabet()
        .iter()
        .find(|i| matches!(i, Input::Tick { .. }));
    assert_eq!(tick.map(named), Some(0));
    let pair = model.alphabet().iter().find(
        |i| matches!(i, Input::SetCommands { commands } if commands.len() == 2 && commands[0].id != commands[1].id),
    );
    assert_eq!(pair.map(|i| named(i).count_ones()), Some(2));
}

fn coverage(args: &[&str]) -> (Option<i32>, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-models"))
        .arg("coverage")
        .args(args)
        .output()
        .expect("the command runs");
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stdout).into_owned(),
    )
}

#[test]
fn the_command_reports_saves_and_compares() {
    let file = std::env::temp_dir().join(format!("coverage-{}.json", std::process::id()));
    let path = file.to_str().expect("a path");
    let (code, stdout) = coverage(&["--modules", "1", "--scenes", "2", "--write", path]);
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("| same scene |"), "{stdout}");
    let record: Record =
        serde_json::from_str(&std::fs::read_to_string(&file).expect("saved")).expect("reads");
    assert!(record.complete);
    assert_eq!(record.pairs, measure(&model(1, 2), true, 2).pairs);
    assert_eq!(record.counts, Scope::ALL.map(|s| record.pairs.count(s)));

    let (code, stdout) = coverage(&["--modules", "2", "--scenes", "2", "--against", path]);
    assert_eq!(code, Some(0), "{stdout}");
    assert!(stdout.contains("- 0 pairs there, not here"), "{stdout}");
    let _ = std::fs::remove_file(&file);

    let (code, stdout) = coverage(&["--scenes", "3", "--timeout", "0"]);
    assert_eq!(code, Some(1), "{stdout}");
    assert!(
        stdout.contains("incomplete: stopped by the time limit"),
        "{stdout}"
    );
}
