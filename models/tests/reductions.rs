//! Each reduction of the sequential model's search, cross-checked against the search without it
//! where both can run (docs/models.md, *Reductions*): the same verdict for every
//! property, on the shipped code and on every injected fault, and the counts related exactly as
//! the argument says.

use std::collections::BTreeSet;
use std::sync::{Arc, Mutex};

use cooperation::Rule;
use cooperation_models::check::run::{check_for, Report, Settings, Stop, Strategy};
use cooperation_models::{Bounds, Fault, SequentialModel, Step};
use stateright::{Checker, Model, Path};

fn settings(symmetry: bool) -> Settings {
    Settings {
        threads: 1,
        strategy: if symmetry {
            Strategy::Dfs
        } else {
            Strategy::Bfs
        },
        symmetry,
    }
}

fn run(model: &SequentialModel, symmetry: bool, stop: Stop) -> Report {
    let report = check_for(model, settings(symmetry), stop, &mut std::io::sink());
    assert!(report.complete, "the search did not complete");
    report
}

/// Every property's name with whether it held.
fn verdicts(report: &Report) -> Vec<(&'static str, bool)> {
    report.outcomes.iter().map(|o| (o.name, o.holds)).collect()
}

/// Runs the search to its end on one thread, calling `visit` with every state it keeps.
fn visit_every_state(
    model: &SequentialModel,
    symmetry: bool,
    visit: impl Fn(&Step) + Send + Sync + 'static,
) {
    let builder = model
        .clone()
        .checker()
        .threads(1)
        .visitor(move |path: Path<Step, usize>| visit(path.last_state()));
    if symmetry {
        assert!(builder.symmetry().spawn_dfs().join().is_done());
    } else {
        assert!(builder.spawn_bfs().join().is_done());
    }
}

/// How many stalled steps a search keeps, and their rules, found by visiting every state it
/// keeps.
fn stalled_rules(model: &SequentialModel, symmetry: bool) -> (usize, BTreeSet<Rule>) {
    let seen = Arc::new(Mutex::new((0, BTreeSet::new())));
    let record = Arc::clone(&seen);
    visit_every_state(model, symmetry, move |step| {
        if step.stalled {
            let mut seen = record.lock().expect("not poisoned");
            seen.0 += 1;
            seen.1.extend(step.last);
        }
    });
    let seen = seen.lock().expect("not poisoned");
    (seen.0, seen.1.clone())
}

/// How many states a search expands (those not stalled), and how many successors the argument
/// says the merged search is handed from them: from each, every step that is not stalled and
/// one stalled step for each rule its inputs stall on, counted by walking every input with
/// [`SequentialModel::next_step`], which hands over every step.
fn handed(model: &SequentialModel, symmetry: bool) -> (usize, usize) {
    let seen = Arc::new(Mutex::new((0, 0)));
    let record = Arc::clone(&seen);
    let walker = model.clone();
    visit_every_state(model, symmetry, move |step| {
        if step.stalled {
            return;
        }
        let (mut moved, mut stalled) = (0, BTreeSet::new());
        for action in 0..walker.alphabet().len() {
            let next = walker.next_step(step, action).expect("in the alphabet");
            if next.stalled {
                stalled.extend(next.last);
            } else {
                moved += 1;
            }
        }
        let mut seen = record.lock().expect("not poisoned");
        seen.0 += 1;
        seen.1 += moved + stalled.len();
    });
    let seen = seen.lock().expect("not poisoned");
    *seen
}

/// Merging stalled steps by rule: at 1 × 2 and 2 × 2, with and without symmetry, every property
/// has the same verdict; the unmerged search is handed every input's step, one (the initial
/// state) plus the inputs per state times the non-stalled states; the merged search expands the
/// same number of states, is handed from each only its first stalled step of each rule (the
/// later ones are that state again), and keeps exactly one stalled step per rule that the
/// unmerged search stalls on; the unmerged search keeps every stalled step it reaches.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn merging_stalled_steps_keeps_every_verdict_and_the_counts_the_argument_gives() {
    for (modules, scenes) in [(1, 2), (2, 2)] {
        for symmetry in [true, false] {
            let merged = SequentialModel::new(Bounds::new(modules, scenes)).expect("valid");
            let kept = merged.clone().with_stalled_merged(false);
            let (reduced, full) = (
                run(&merged, symmetry, Stop::first_violation()),
                run(&kept, symmetry, Stop::first_violation()),
            );
            let at = format!("{modules} x {scenes}, symmetry {symmetry}");
            assert!(reduced.passed() && full.passed(), "{at}");
            assert_eq!(verdicts(&reduced), verdicts(&full), "{at}");

            let inputs = merged.alphabet().len();
            assert_eq!((full.generated - 1) % inputs, 0, "{at}");
            let expanded = (full.generated - 1) / inputs;
            assert_eq!(
                handed(&merged, symmetry),
                (expanded, reduced.generated - 1),
                "{at}: the merged search's expanded states and generated successors"
            );
            assert!(
                reduced.generated < full.generated,
                "{at}: no stalled step was left out"
            );

            let (leaves, rules) = stalled_rules(&kept, symmetry);
            assert_eq!(full.unique, expanded + leaves, "{at}");
            assert_eq!(
                reduced.unique,
                expanded + rules.len(),
                "{at}: one stalled step per rule"
            );
            assert!(leaves > rules.len(), "{at}: the reduction reduced nothing");
        }
    }
}

/// The same verdicts with every injected fault: the properties a fault violates, and the rules
/// it leaves reachable, do not depend on the reduction. Each fault at the smallest bounds of
/// `tests/faults.rs` that show it with one module, and the one that needs two at 2 × 2.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn merging_stalled_steps_keeps_every_faults_verdicts() {
    for fault in Fault::ALL {
        let bounds = match fault {
            Fault::IdMovesModule => Bounds::new(2, 2),
            Fault::ForgetsEarly => Bounds {
                live: 1,
                ..Bounds::new(1, 3)
            },
            Fault::CommandBroadcast => Bounds {
                live: 2,
                ..Bounds::new(1, 2)
            },
            _ => Bounds::new(1, 2),
        };
        let merged = SequentialModel::new(bounds)
            .expect("valid")
            .with_fault(fault);
        let kept = merged.clone().with_stalled_merged(false);
        let reduced = run(&merged, true, Stop::every_violation());
        let full = run(&kept, true, Stop::every_violation());
        assert!(!reduced.passed(), "{fault:?} is caught at {bounds:?}");
        assert_eq!(verdicts(&reduced), verdicts(&full), "{fault:?}");
    }
}
