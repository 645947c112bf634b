//! The swarm simulation (`cooperation-models simulate`): at a real planner's sizes it reaches
//! what no exhaustive run does (the hashed scene index, the scene limit, forgetting retired
//! identifiers) with every property holding; a walk is a function of its seed; an injected
//! fault is caught and its trace replays.

use cooperation::Rule;
use cooperation_models::check::simulate::{run, Findings, Progress, Swarm};
use cooperation_models::{Bounds, Fault, SequentialModel};

/// Inputs per walk.
const DEPTH: usize = 10_000;

/// 8 modules, 64 identifiers, at most 32 live, 16 retired remembered.
fn large() -> Bounds {
    Bounds {
        modules: 8,
        scenes: 64,
        live: 32,
        retired: 16,
    }
}

fn swarm(model: &SequentialModel, seeds: std::ops::Range<u64>, threads: usize) -> Findings {
    let swarm = Swarm {
        seeds,
        depth: DEPTH,
        threads,
    };
    run(model, &swarm, &Progress::default()).expect("runs")
}

/// The CI run of the swarm: every property holds in every state of 64 walks of 10,000 inputs at
/// 8 modules × 64 identifiers, and the walks reach more than 16 live scenes (the hashed index),
/// the scene limit, scenes expiring, and the retired set forgetting; every rule fires.
#[test]
fn a_short_swarm_reaches_the_large_table_the_scene_limit_and_forgetting() {
    let model = SequentialModel::new(large()).expect("valid");
    let found = swarm(&model, 0..64, 2);
    assert!(found.violation.is_none(), "{:?}", found.violation);
    assert_eq!(found.walks, 64);
    assert_eq!(found.states, 64 * (DEPTH as u64 + 1));
    assert!(found.most_live > 16, "most live: {}", found.most_live);
    assert!(found.fired(Rule::RegisterFull) > 0, "the scene limit");
    assert!(found.fired(Rule::TimeExpire) > 0, "expiry");
    assert!(found.forgetting > 0, "forgetting");
    for rule in Rule::ALL {
        assert!(found.fired(rule) > 0, "{rule} never fired");
    }
    assert_eq!(found.reached.len(), model_properties_sometimes(&model));
}

/// How many `sometimes` properties the model has.
fn model_properties_sometimes(model: &SequentialModel) -> usize {
    use stateright::Model;
    model
        .properties()
        .iter()
        .filter(|p| matches!(p.expectation, stateright::Expectation::Sometimes))
        .count()
}

/// A walk depends on its seed alone: the same seeds give the same walks with one thread and
/// with two, and a seed range split in two gives what the whole range gives.
#[test]
fn walks_depend_on_their_seeds_alone() {
    let model = SequentialModel::new(Bounds {
        live: 8,
        retired: 4,
        ..large()
    })
    .expect("valid");
    let one = swarm(&model, 10..14, 1);
    let two = swarm(&model, 10..14, 2);
    let (first, second) = (swarm(&model, 10..12, 1), swarm(&model, 12..14, 1));
    assert_eq!((one.walks, one.states), (two.walks, two.states));
    assert_eq!(one.fired, two.fired);
    assert_eq!(one.most_live, two.most_live);
    assert_eq!(one.forgetting, two.forgetting);
    let halves: Vec<u64> = first
        .fired
        .iter()
        .zip(&second.fired)
        .map(|(a, b)| a + b)
        .collect();
    assert_eq!(halves, one.fired);
}

/// A fault is caught at the large bounds; the violating walk's trace breaks the same property
/// when replayed, passes on the shipped code, and the walk's seed finds it again.
#[test]
fn the_swarm_catches_a_fault_and_its_trace_replays() {
    let model = SequentialModel::new(large())
        .expect("valid")
        .with_fault(Fault::CommandToggles);
    let found = swarm(&model, 0..16, 2);
    let violation = found.violation.expect("the fault is caught");
    assert!(
        !violation.trace.holds_at_end().expect("replays"),
        "the trace replays to the violation"
    );
    assert!(
        violation
            .trace
            .without_fault()
            .holds_at_end()
            .expect("replays"),
        "the shipped code passes the same inputs"
    );
    let again = swarm(&model, violation.seed..violation.seed + 1, 1);
    let again = again.violation.expect("the seed finds it again");
    assert_eq!(again.trace, violation.trace);
}
