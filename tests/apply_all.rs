//! `State::apply_all`, a sequence of inputs all or none (spec §4), against `State::apply` one
//! input at a time: the same transitions when every input is accepted, and when one is
//! refused, that input's rejection and a state exactly as before, which then behaves exactly
//! as the state before did. The inputs are random; the small states forget retired identifiers
//! after three and the crowd's tables grow past their small form, so that taking a sequence
//! back restores forgotten identifiers and hashed tables too.

use crate::common::inputs::*;
use crate::common::*;
use cooperation::*;
use proptest::prelude::*;

/// The longest sequence tried, less one: long enough to take back several writes, short enough
/// that whole sequences are often accepted.
const SEQUENCE: usize = 5;

/// The crowd's state: more scenes than a small table holds, few retired identifiers.
fn crowd_state() -> State {
    let mut config = config();
    config.limits.max_scenes = 64;
    config.limits.retired_capacity = 8;
    State::new(config).expect("valid")
}

/// What a state shows: its statuses and both factor lists, in their order.
fn shown(
    state: &State,
) -> (
    Vec<CooperationStatus>,
    Vec<VelocityFactor>,
    Vec<SteeringFactor>,
) {
    let mut statuses = Vec::new();
    state.statuses_into(&mut statuses);
    let mut lists = FactorLists::default();
    state.factors_into(&mut lists);
    (statuses, lists.velocity, lists.steering)
}

/// A sequence most of whose inputs `state` accepts: those of `candidates` it accepts one after
/// the other (at most [`SEQUENCE`]), then `last`, which it may refuse. Random inputs alone are
/// refused too often for long accepted sequences to come up.
fn mostly_accepted(state: &State, candidates: &[Input], last: Option<Input>) -> Vec<Input> {
    let mut probe = state.clone();
    let mut sequence: Vec<Input> = candidates
        .iter()
        .filter(|input| probe.apply(input).is_ok())
        .take(SEQUENCE)
        .cloned()
        .collect();
    sequence.extend(last);
    sequence
}

/// `state` after `prefix`, each input applied alone, its refusals skipped.
fn after(mut state: State, prefix: &[Input]) -> State {
    for input in prefix {
        let _ = state.apply(input);
    }
    state
}

/// The property: `apply_all(sequence)` on `state` is the inputs applied one by one when all are
/// accepted, and otherwise the first refusal with nothing changed; then `follow` behaves the
/// same on the result as on the state that one by one application (or nothing) leaves.
fn agrees_with_one_by_one(
    state: &State,
    sequence: &[Input],
    follow: &[Input],
) -> Result<(), TestCaseError> {
    let mut batch = state.clone();
    let together = batch.apply_all(sequence);
    let mut alone = state.clone();
    let mut first_refusal = None;
    let mut transitions = Vec::new();
    for (index, input) in sequence.iter().enumerate() {
        match alone.apply(input) {
            Ok(transition) => transitions.push(transition),
            Err(rejection) => {
                first_refusal = Some((index, rejection));
                break;
            }
        }
    }
    prop_assert_eq!(batch.check_invariants(), Ok(()));
    match (together, first_refusal) {
        (Ok(together), None) => {
            prop_assert_eq!(together, transitions);
            prop_assert_eq!(&batch, &alone);
        }
        (Err(refused), Some((index, rejection))) => {
            prop_assert_eq!(refused.index, index);
            prop_assert_eq!(*refused.rejection, rejection);
            prop_assert_eq!(&batch, state, "a refused sequence left a trace");
            alone = state.clone();
        }
        (together, alone) => {
            return Err(TestCaseError::fail(format!(
                "apply_all answered {together:?}; one by one, the first refusal was {alone:?}"
            )))
        }
    }
    // The state left behaves as the one it must equal: same outputs, same answers to whatever
    // comes next (a table taken back may be laid out otherwise, never seen otherwise).
    prop_assert_eq!(shown(&batch), shown(&alone));
    for input in follow {
        prop_assert_eq!(batch.apply(input), alone.apply(input));
        prop_assert_eq!(shown(&batch), shown(&alone));
    }
    prop_assert_eq!(&batch, &alone);
    Ok(())
}

/// The property for a random sequence and for a mostly accepted one, from `state`.
fn agrees_on_both(
    state: &State,
    candidates: &[Input],
    last: Option<Input>,
    follow: &[Input],
) -> Result<(), TestCaseError> {
    agrees_with_one_by_one(state, &candidates[..candidates.len().min(SEQUENCE)], follow)?;
    agrees_with_one_by_one(state, &mostly_accepted(state, candidates, last), follow)
}

proptest! {
    #[test]
    fn a_sequence_applies_as_its_inputs_one_by_one_or_not_at_all(
        prefix in proptest::collection::vec(any_input(), 0..24),
        candidates in proptest::collection::vec(any_input(), 0..24),
        last in proptest::option::of(any_input()),
        follow in proptest::collection::vec(any_input(), 0..8),
    ) {
        agrees_on_both(&after(state(), &prefix), &candidates, last, &follow)?;
    }

    #[test]
    fn a_crowds_sequence_applies_as_its_inputs_one_by_one_or_not_at_all(
        prefix in proptest::collection::vec(any_crowd_input(), 0..80),
        candidates in proptest::collection::vec(any_crowd_input(), 0..24),
        last in proptest::option::of(any_crowd_input()),
        follow in proptest::collection::vec(any_crowd_input(), 0..12),
    ) {
        agrees_on_both(&after(crowd_state(), &prefix), &candidates, last, &follow)?;
    }
}

/// Both outcomes are common among the mostly accepted sequences the properties run, so neither
/// half of the property holds only because its case never came up: whole sequences of several
/// inputs, and refused sequences with accepted inputs before the refused one, which are what
/// must be taken back.
#[test]
fn the_generators_refuse_after_accepting_and_accept_whole_sequences() {
    use proptest::strategy::ValueTree;
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let prefixes = proptest::collection::vec(any_input(), 0..24);
    let candidates = proptest::collection::vec(any_input(), 0..24);
    let lasts = proptest::option::of(any_input());
    let (mut whole, mut taken_back) = (0, 0);
    for _ in 0..256 {
        let prefix = prefixes.new_tree(&mut runner).expect("a prefix").current();
        let candidates = candidates
            .new_tree(&mut runner)
            .expect("candidates")
            .current();
        let last = lasts.new_tree(&mut runner).expect("a last input").current();
        let mut state = after(state(), &prefix);
        let sequence = mostly_accepted(&state, &candidates, last);
        match state.apply_all(&sequence) {
            Ok(_) => whole += usize::from(sequence.len() > 1),
            Err(refused) => taken_back += usize::from(refused.index > 0),
        }
    }
    assert!(
        whole > 25 && taken_back > 25,
        "whole {whole}, taken back {taken_back}"
    );
}

/// A sequence refused at its last input takes back what the ones before it wrote: two
/// retirements that made the retired set forget its oldest identifiers, a tick that aged and
/// expired scenes, a command and a policy.
#[test]
fn a_refused_sequence_takes_back_retirements_ticks_commands_and_policies() {
    let mut state = state();
    // The retired set full (10, 11, 12), and the most live scenes (1 to 4).
    churn(&mut state, 10..=12);
    for n in 1..=4 {
        let module = if n % 2 == 1 { LANE_CHANGE } else { AVOIDANCE };
        fires(
            &mut state,
            register(id(n), module, Decision::Activate),
            Rule::RegisterNew,
        );
    }
    let before = state.clone();
    let sequence = [
        Input::Remove {
            id: id(1),
            module: LANE_CHANGE,
        },
        Input::Remove {
            id: id(2),
            module: AVOIDANCE,
        },
        commands(&[(id(3), OperatorDecision::Activate)]),
        policies(&[(LANE_CHANGE, Policy::Required)]),
        Input::Tick {
            elapsed_ms: TTL_MS + 1,
        },
        // Refused: the scene expired with the tick.
        update(id(4), AVOIDANCE, Phase::Running, Decision::Activate),
    ];
    let refused = state
        .apply_all(&sequence)
        .expect_err("the last input is refused");
    assert_eq!(
        (refused.index, refused.rejection.rule()),
        (5, Rule::OwnerRetired)
    );
    assert_eq!(state, before);
    assert_eq!(
        state.retired_oldest_first().collect::<Vec<_>>(),
        before.retired_oldest_first().collect::<Vec<_>>()
    );
    assert_eq!(
        refused.to_string(),
        format!(
            "input 5 of the sequence: {}; no input of the sequence was applied",
            refused.rejection
        )
    );
}
