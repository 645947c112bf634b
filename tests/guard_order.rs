//! Inputs that more than one guard of spec §5 refuses: the rule that answers is the first in
//! the order the spec checks them (§5.1 to §5.6), taken here from the spec's text, not from the
//! code. Each case lists every rule whose *When* holds for it; the expected rule is the first
//! of those in the spec's order.

use crate::common::*;
use cooperation::*;

/// §5.1, in the order its rules are listed.
const REGISTER_ORDER: [Rule; 5] = [
    Rule::RegisterRetired,
    Rule::RegisterLive,
    Rule::OwnerModule,
    Rule::RegisterModule,
    Rule::RegisterFull,
];

/// §5.2: `[COOP-OWN-MODULE.1]`, then unknown, then retired; then, for an update, kind,
/// transition, and the accepting rules.
const UPDATE_ORDER: [Rule; 6] = [
    Rule::OwnerModule,
    Rule::OwnerUnknown,
    Rule::OwnerRetired,
    Rule::OwnerKind,
    Rule::OwnerTransition,
    Rule::OwnerFinish,
];

/// Applies `input`, which the rules `holding` all apply to, and requires the first of them in
/// `order` to answer it, changing nothing if it is a rejection.
fn first_in_spec_order(state: &mut State, order: &[Rule], input: Input, holding: &[Rule]) {
    let expected = *order
        .iter()
        .find(|rule| holding.contains(rule))
        .expect("a rule holds");
    if expected.is_rejection() {
        rejects(state, input, expected);
    } else {
        fires(state, input, expected);
    }
}

fn steering() -> Geometry {
    Geometry::steering(Direction::Left, 1.0, 2.0)
}

/// §5.1 at the scene limit: a retired identifier, a live one, and an unconfigured module, each
/// with the limit reached too.
#[test]
fn registration_guards_in_spec_order() {
    let mut state = state();
    churn(&mut state, 5..=5);
    for n in 1..=4 {
        fires(
            &mut state,
            register(id(n), LANE_CHANGE, Decision::Activate),
            Rule::RegisterNew,
        );
    }
    use Rule::*;
    let cases = [
        // A retired identifier, for an unconfigured module, at the limit.
        (
            id(5),
            INTERSECTION,
            &[RegisterRetired, RegisterModule, RegisterFull][..],
        ),
        // A retired identifier, for another configured module, at the limit.
        (id(5), AVOIDANCE, &[RegisterRetired, RegisterFull]),
        // A live identifier again, at the limit.
        (id(1), LANE_CHANGE, &[RegisterLive, RegisterFull]),
        // A live identifier under another module, unconfigured.
        (id(1), INTERSECTION, &[OwnerModule, RegisterModule]),
        // A new identifier of an unconfigured module, at the limit.
        (id(9), INTERSECTION, &[RegisterModule, RegisterFull]),
    ];
    for (id, module, holding) in cases {
        let input = register(id, module, Decision::Activate);
        first_in_spec_order(&mut state, &REGISTER_ORDER, input, holding);
    }
}

/// §5.2: a kind mismatch together with a forbidden phase change, or with a finishing one; the
/// wrong module with both; a retired identifier named with another module and the other kind.
#[test]
fn update_guards_in_spec_order() {
    let mut state = with_scenes();
    churn(&mut state, 3..=3);
    use Rule::*;
    let update_to = |module, phase, geometry| {
        update_with(id(1), module, phase, Decision::Activate, false, geometry)
    };
    let cases = [
        // Waiting, updated to aborting (forbidden) with steering geometry (the other kind).
        (
            update_to(LANE_CHANGE, Phase::Aborting, steering()),
            &[OwnerKind, OwnerTransition][..],
        ),
        // The same, under another module.
        (
            update_to(AVOIDANCE, Phase::Aborting, steering()),
            &[OwnerModule, OwnerKind, OwnerTransition],
        ),
        // Failed is allowed from waiting and would retire the scene; the kind is wrong.
        (
            update_to(LANE_CHANGE, Phase::Failed, steering()),
            &[OwnerKind, OwnerFinish],
        ),
        // Retired from lane change; named with avoidance, the other kind, a forbidden phase.
        (
            update_with(
                id(3),
                AVOIDANCE,
                Phase::Aborting,
                Decision::Activate,
                false,
                steering(),
            ),
            &[OwnerRetired],
        ),
    ];
    for (input, holding) in cases {
        first_in_spec_order(&mut state, &UPDATE_ORDER, input, holding);
    }
    assert_eq!(
        state.scene(id(1)).map(Scene::phase),
        Some(Phase::Waiting),
        "nothing retired it"
    );
}

/// §5.4: the batch limit before any command; then the first failing command in batch order
/// names the rule, whatever fails later; each command is classified duplicate, then not
/// cancellable, then retired, then unknown.
#[test]
fn command_guards_in_spec_order() {
    let mut state = with_scenes();
    walk(
        &mut state,
        id(2),
        AVOIDANCE,
        &[Phase::Running, Phase::Aborting],
    );
    churn(&mut state, 3..=3);
    let activate = |n: u128| (id(n), OperatorDecision::Activate);
    let over = [
        activate(9),
        activate(9),
        activate(2),
        activate(3),
        activate(1),
    ];
    rejects(&mut state, commands(&over), Rule::BatchLimit);
    let failed = CommandOutcome::Failed;
    let aborting = CommandFailure::NotCancellable(Phase::Aborting);
    let retired = CommandFailure::RetiredScene(RetireReason::Removed);
    let cases = [
        // Unknown first; a duplicate later.
        (
            vec![activate(9), activate(1), activate(1)],
            Rule::CommandUnknown,
            vec![
                failed(CommandFailure::UnknownScene),
                CommandOutcome::Withheld,
                failed(CommandFailure::DuplicateId),
            ],
        ),
        // An unknown identifier twice: the second is a duplicate before it is unknown.
        (
            vec![activate(9), activate(9)],
            Rule::CommandUnknown,
            vec![
                failed(CommandFailure::UnknownScene),
                failed(CommandFailure::DuplicateId),
            ],
        ),
        // An aborting scene twice.
        (
            vec![activate(2), activate(2)],
            Rule::CommandNotCancellable,
            vec![failed(aborting), failed(CommandFailure::DuplicateId)],
        ),
        // Retired, then not cancellable, then unknown.
        (
            vec![activate(3), activate(2), activate(9)],
            Rule::CommandRetired,
            vec![
                failed(retired),
                failed(aborting),
                failed(CommandFailure::UnknownScene),
            ],
        ),
    ];
    for (batch, rule, outcomes) in cases {
        match rejects(&mut state, commands(&batch), rule) {
            Rejection::Commands {
                outcomes: found, ..
            } => assert_eq!(found, outcomes, "{batch:?}"),
            other => panic!("{other}"),
        }
    }
}

/// §5.5: the batch limit before any setting; then the first failing setting in batch order.
#[test]
fn policy_guards_in_spec_order() {
    let mut state = with_scenes();
    let required = |module| (module, Policy::Required);
    let over = [
        required(INTERSECTION),
        required(LANE_CHANGE),
        required(LANE_CHANGE),
        required(AVOIDANCE),
        required(AVOIDANCE),
    ];
    rejects(&mut state, policies(&over), Rule::BatchLimit);
    let cases = [
        (
            vec![required(INTERSECTION), required(INTERSECTION)],
            Rejection::UnknownPolicyModule {
                index: 0,
                module: INTERSECTION,
            },
        ),
        (
            vec![
                required(LANE_CHANGE),
                required(LANE_CHANGE),
                required(INTERSECTION),
            ],
            Rejection::DuplicatePolicyModule {
                index: 1,
                module: LANE_CHANGE,
            },
        ),
        (
            vec![
                required(AVOIDANCE),
                required(INTERSECTION),
                required(AVOIDANCE),
            ],
            Rejection::UnknownPolicyModule {
                index: 1,
                module: INTERSECTION,
            },
        ),
    ];
    for (batch, expected) in cases {
        let rejection = rejects(&mut state, policies(&batch), expected.rule());
        assert_eq!(rejection, expected);
    }
}
