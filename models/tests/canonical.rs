//! Canonical states (`model::sequential`'s `canonical`): breadth-first search over successors
//! renamed to their representatives meets the classes that depth-first search with symmetry
//! meets, so it reaches the same counts; and a path found among canonical states turns into
//! inputs that replay on the model without renaming (every planted fault's, too:
//! `models/tests/faults.rs`).

use std::collections::{HashMap, VecDeque};

use cooperation_models::check::pins::{self, Pin};
use cooperation_models::check::run::{check, Report, Settings, Strategy};
use cooperation_models::model::sequential::{identity, Names};
use cooperation_models::{Bounds, SequentialModel, Step as SequentialStep};
use stateright::{Model, Representative};

/// Breadth first with symmetry on: canonical states.
const CANONICAL: Settings = Settings {
    threads: 2,
    strategy: Strategy::Bfs,
    symmetry: true,
};

fn canonical_check(bounds: Bounds) -> Report {
    let model = SequentialModel::new(bounds).expect("valid bounds");
    let report = check(&model, CANONICAL, &mut std::io::sink());
    assert!(report.complete, "{bounds:?}: the search did not complete");
    let broken: Vec<&str> = report
        .outcomes
        .iter()
        .filter(|o| !o.holds)
        .map(|o| o.name)
        .collect();
    assert_eq!(broken, Vec::<&str>::new(), "{bounds:?}");
    report
}

/// The depth-first symmetric pin's counts, unique and generated, reached breadth first.
fn same_counts(report: &Report, pin: Pin) {
    assert_eq!(report.unique, pin.unique, "unique states, as {}", pin.test);
    if let Some(generated) = pin.generated {
        assert_eq!(report.generated, generated, "generated, as {}", pin.test);
    }
}

#[test]
fn canonical_breadth_first_reaches_the_symmetric_depth_first_counts() {
    same_counts(
        &canonical_check(Bounds::new(1, 2)),
        pins::SEQUENTIAL_1X2_SYMMETRY,
    );
    same_counts(
        &canonical_check(Bounds::new(2, 2)),
        pins::SEQUENTIAL_2X2_SYMMETRY,
    );
}

/// The CI configuration, 2 × 3, breadth first over canonical states: the depth-first
/// symmetric counts (`pins::SEQUENTIAL_2X3_CANONICAL`).
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn two_modules_three_scenes_canonical() {
    let report = canonical_check(Bounds::new(2, 3));
    same_counts(&report, pins::SEQUENTIAL_2X3_CANONICAL);
    same_counts(&report, pins::SEQUENTIAL_2X3);
}

/// 3 × 3 breadth first over canonical states: the depth-first symmetric counts
/// (`pins::SEQUENTIAL_3X3_CANONICAL`); breadth first keeps its frontier whole, a few GB here
/// against the depth-first search's few hundred MB.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn three_modules_three_scenes_canonical() {
    let report = canonical_check(Bounds::new(3, 3));
    same_counts(&report, pins::SEQUENTIAL_3X3_CANONICAL);
    same_counts(&report, pins::SEQUENTIAL_3X3);
    eprintln!(
        "3x3 canonical: {} unique, {} generated, depth {}, {:.1} s",
        report.unique,
        report.generated,
        report.depth,
        report.elapsed.as_secs_f64()
    );
}

/// A path among canonical states, turned into unrenamed inputs, replays through states that
/// are the canonical ones up to renaming; on the way, some renaming is not the identity (so
/// the translation is exercised, not skipped).
#[test]
fn a_canonical_path_replays_unrenamed() {
    let model = SequentialModel::new(Bounds::new(2, 3))
        .expect("valid")
        .with_canonical_states(true);
    assert!(model.canonical_states());
    let hashed = model
        .clone()
        .with_table(cooperation::TableLayout::Colliding);
    assert!(
        !hashed.canonical_states(),
        "no canonical states on the hashed table"
    );
    let raw_model = SequentialModel::new(Bounds::new(2, 3)).expect("valid");
    let alphabet = model.alphabet().len();
    let mut renamed_somewhere = false;
    // A fixed pseudo-random sequence of walks (xorshift), each to a stalled step or 40 steps.
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    for _ in 0..200 {
        let mut state = model.init_states().remove(0);
        let mut actions = Vec::new();
        let mut path = vec![state.clone()];
        for _ in 0..40 {
            let mut enabled = Vec::new();
            model.actions(&state, &mut enabled);
            if enabled.is_empty() {
                break;
            }
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let action = (seed % alphabet as u64) as usize;
            state = model.next_step(&state, action).expect("in the alphabet");
            actions.push(action);
            path.push(state.clone());
        }
        let raw = model.raw_inputs(&actions);
        assert_eq!(raw.len(), actions.len());
        renamed_somewhere |= actions
            .iter()
            .zip(&raw)
            .any(|(action, input)| model.alphabet().get(*action) != Some(input));
        let replayed = raw_model.replay(&raw).expect("replays");
        assert_eq!(replayed.len(), path.len());
        for (raw_step, canonical) in replayed.iter().zip(&path) {
            // The representative the checker fingerprints is the same for both.
            assert_eq!(fingerprint(raw_step), fingerprint(canonical));
            if canonical.stalled {
                // A stalled step is its own representative, fingerprinted by its rule alone.
                assert!(raw_step.stalled && raw_step.last == canonical.last);
            } else {
                assert_eq!(&raw_step.canonical_step(), canonical);
            }
        }
    }
    assert!(renamed_somewhere, "no walk renamed an identifier");
}

/// The fingerprint the checker takes of a step's representative is its class's: over the
/// first 3,000 canonical states breadth first at 2 × 3 (stalled ones aside, fingerprinted by
/// their rule), every renaming of a state has its fingerprint, and two states' representatives
/// have the same fingerprint exactly when the canonical states themselves hash alike.
#[test]
// A step's cells cache what its parts give (see `Step`); its hash and equality never change.
#[allow(clippy::mutable_key_type)]
fn a_representatives_fingerprint_is_its_class() {
    let model = SequentialModel::new(Bounds::new(2, 3))
        .expect("valid")
        .with_canonical_states(true);
    let mut classes: HashMap<SequentialStep, u64> = HashMap::new();
    let mut frontier: VecDeque<SequentialStep> = model.init_states().into();
    let mut actions = Vec::new();
    while let Some(state) = frontier.pop_front() {
        if classes.len() >= 3_000 {
            break;
        }
        model.actions(&state, &mut actions);
        for action in actions.drain(..) {
            let next = model.next_step(&state, action).expect("in the alphabet");
            if !next.stalled && !classes.contains_key(&next) {
                classes.insert(next.clone(), fingerprint(&next));
                frontier.push_back(next);
            }
        }
    }
    assert!(classes.len() >= 3_000, "{} classes", classes.len());
    let mut renamed = 0;
    for (state, print) in &classes {
        for names in permutations_of_three() {
            if let Some(other) = state.renamed(&names) {
                assert_eq!(
                    fingerprint(&other),
                    *print,
                    "{state:?} renamed by {names:?}"
                );
                renamed += usize::from(other != *state);
            }
        }
    }
    assert!(
        renamed > classes.len(),
        "{renamed} renamings differ from their state"
    );
    // The canonical state's own fingerprint (which leaves out what the step's fingerprint
    // leaves out: the retirement order, where no identifier is forgotten) and the
    // representative's name the same classes.
    let mut by_state: HashMap<u64, u64> = HashMap::new();
    let mut by_representative: HashMap<u64, u64> = HashMap::new();
    for (state, print) in &classes {
        let own = hash(state);
        assert_eq!(*by_state.entry(own).or_insert(*print), *print, "{state:?}");
        assert_eq!(
            *by_representative.entry(*print).or_insert(own),
            own,
            "{state:?}"
        );
    }
    assert!(by_state.len() > 1_000, "{} classes", by_state.len());
}

/// Every renaming of identifiers 1, 2 and 3 among themselves.
fn permutations_of_three() -> Vec<Names> {
    let orders = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    orders
        .iter()
        .map(|order| {
            let mut names = identity();
            names[..3].copy_from_slice(order);
            names
        })
        .collect()
}

/// The fingerprint the checker takes of a step's representative (with a fixed hasher).
fn fingerprint(step: &SequentialStep) -> u64 {
    hash(&step.representative())
}

/// A step's hash, with a fixed hasher.
fn hash(step: &SequentialStep) -> u64 {
    use std::hash::BuildHasher;
    std::hash::BuildHasherDefault::<std::hash::DefaultHasher>::default().hash_one(step)
}
