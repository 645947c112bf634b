//! Operators' calls and their limits (`COOP-CMD-*`, `COOP-POL-*`, `COOP-BATCH-*`).

use crate::common::*;
use cooperation::*;

/// `[COOP-CMD-APPLY.1]`: every named scene takes its command's decision; none withdraws it;
/// an empty batch applies and changes nothing.
#[test]
fn coop_cmd_apply_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        commands(&[
            (id(1), OperatorDecision::Activate),
            (id(2), OperatorDecision::Autonomous),
        ]),
        Rule::CommandApply,
    );
    assert_eq!(
        state.scene(id(1)).map(Scene::operator_decision),
        Some(OperatorDecision::Activate)
    );
    assert_eq!(
        state.scene(id(2)).map(Scene::operator_decision),
        Some(OperatorDecision::Autonomous)
    );
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Undecided)]),
        Rule::CommandApply,
    );
    assert_eq!(
        state.scene(id(1)).map(Scene::operator_decision),
        Some(OperatorDecision::Undecided)
    );
    let before = state.clone();
    fires(&mut state, commands(&[]), Rule::CommandApply);
    assert_eq!(state, before);
}

/// `[COOP-CMD-UNKNOWN.1]`: a command for an unknown identifier rejects the whole batch, and is
/// not kept for a scene that registers later.
#[test]
fn coop_cmd_unknown_1() {
    let mut state = with_scenes();
    let rejection = rejects(
        &mut state,
        commands(&[
            (id(1), OperatorDecision::Activate),
            (id(9), OperatorDecision::Activate),
        ]),
        Rule::CommandUnknown,
    );
    assert_eq!(
        rejection,
        Rejection::Commands {
            index: 1,
            failure: CommandFailure::UnknownScene,
            outcomes: vec![
                CommandOutcome::Withheld,
                CommandOutcome::Failed(CommandFailure::UnknownScene)
            ],
            failed: vec![id(9)],
        }
    );
    fires(
        &mut state,
        register(id(9), LANE_CHANGE, Decision::Deactivate),
        Rule::RegisterNew,
    );
    assert_eq!(
        state.scene(id(9)).map(Scene::operator_decision),
        Some(OperatorDecision::Undecided)
    );
}

/// `[COOP-CMD-RETIRED.1]`: a command for a retired identifier rejects the batch.
#[test]
fn coop_cmd_retired_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        update(id(2), AVOIDANCE, Phase::Failed, Decision::Activate),
        Rule::OwnerFinish,
    );
    let rejection = rejects(
        &mut state,
        commands(&[(id(2), OperatorDecision::Activate)]),
        Rule::CommandRetired,
    );
    assert!(matches!(
        rejection,
        Rejection::Commands {
            index: 0,
            failure: CommandFailure::RetiredScene(RetireReason::Failed),
            ..
        }
    ));
}

/// `[COOP-CMD-NOT-CANCELLABLE.1]`: an aborting scene accepts no command.
#[test]
fn coop_cmd_not_cancellable_1() {
    let mut state = with_scenes();
    walk(
        &mut state,
        id(1),
        LANE_CHANGE,
        &[Phase::Running, Phase::Aborting],
    );
    let rejection = rejects(
        &mut state,
        commands(&[
            (id(2), OperatorDecision::Activate),
            (id(1), OperatorDecision::Deactivate),
        ]),
        Rule::CommandNotCancellable,
    );
    assert!(matches!(
        rejection,
        Rejection::Commands {
            index: 1,
            failure: CommandFailure::NotCancellable(Phase::Aborting),
            ..
        }
    ));
}

/// `[COOP-CMD-DUPLICATE.1]`: a batch naming one scene twice is rejected, even if both agree;
/// the first failing command names the rule.
#[test]
fn coop_cmd_duplicate_1() {
    let mut state = with_scenes();
    let rejection = rejects(
        &mut state,
        commands(&[
            (id(1), OperatorDecision::Activate),
            (id(1), OperatorDecision::Activate),
            (id(9), OperatorDecision::Activate),
        ]),
        Rule::CommandDuplicate,
    );
    assert_eq!(
        rejection,
        Rejection::Commands {
            index: 1,
            failure: CommandFailure::DuplicateId,
            outcomes: vec![
                CommandOutcome::Withheld,
                CommandOutcome::Failed(CommandFailure::DuplicateId),
                CommandOutcome::Failed(CommandFailure::UnknownScene),
            ],
            failed: vec![id(1), id(9)],
        }
    );
}

/// `[COOP-POL-SET.1]`: a policy change reaches every scene of its module and no other, and
/// changes no scene.
#[test]
fn coop_pol_set_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        register(id(3), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Activate)]),
        Rule::CommandApply,
    );
    let scenes_before: Vec<Scene> = state.scenes().map(|(_, scene)| scene.clone()).collect();
    assert_eq!(state.merged_decision(id(3)), Some(Decision::Activate));
    fires(
        &mut state,
        policies(&[(LANE_CHANGE, Policy::Required)]),
        Rule::PolicySet,
    );
    let scenes_after: Vec<Scene> = state.scenes().map(|(_, scene)| scene.clone()).collect();
    assert_eq!(scenes_before, scenes_after);
    assert_eq!(state.policy(LANE_CHANGE), Some(Policy::Required));
    assert_eq!(state.policy(AVOIDANCE), Some(Policy::Required));
    assert_eq!(
        state.merged_decision(id(3)),
        Some(Decision::Deactivate),
        "undecided: policy applies"
    );
    assert_eq!(
        state.merged_decision(id(1)),
        Some(Decision::Activate),
        "operator decision stands"
    );
    assert_eq!(
        state.merged_decision(id(2)),
        Some(Decision::Deactivate),
        "other module unchanged"
    );
    fires(
        &mut state,
        policies(&[(AVOIDANCE, Policy::Optional)]),
        Rule::PolicySet,
    );
    assert_eq!(state.merged_decision(id(2)), Some(Decision::Activate));
    assert_eq!(state.merged_decision(id(3)), Some(Decision::Deactivate));
}

/// `[COOP-POL-UNKNOWN.1]`: a policy for a module that was not configured rejects the batch.
#[test]
fn coop_pol_unknown_1() {
    let mut state = with_scenes();
    let rejection = rejects(
        &mut state,
        policies(&[
            (LANE_CHANGE, Policy::Required),
            (INTERSECTION, Policy::Optional),
        ]),
        Rule::PolicyUnknown,
    );
    assert_eq!(
        rejection,
        Rejection::UnknownPolicyModule {
            index: 1,
            module: INTERSECTION
        }
    );
}

/// `[COOP-POL-DUPLICATE.1]`: a batch naming a module twice is rejected.
#[test]
fn coop_pol_duplicate_1() {
    let mut state = with_scenes();
    let rejection = rejects(
        &mut state,
        policies(&[
            (LANE_CHANGE, Policy::Required),
            (LANE_CHANGE, Policy::Required),
        ]),
        Rule::PolicyDuplicate,
    );
    assert_eq!(
        rejection,
        Rejection::DuplicatePolicyModule {
            index: 1,
            module: LANE_CHANGE
        }
    );
}

/// `[COOP-BATCH-LIMIT.1]`: a batch longer than `max_batch` is rejected before any entry is
/// looked at; a batch of exactly `max_batch` is accepted.
#[test]
fn coop_batch_limit_1() {
    let mut state = with_scenes();
    let five = [(id(9), OperatorDecision::Activate); 5];
    let rejection = rejects(&mut state, commands(&five), Rule::BatchLimit);
    assert_eq!(rejection, Rejection::BatchLimit { len: 5, limit: 4 });
    let rejection = rejects(
        &mut state,
        policies(&[(INTERSECTION, Policy::Optional); 5]),
        Rule::BatchLimit,
    );
    assert_eq!(rejection, Rejection::BatchLimit { len: 5, limit: 4 });
    fires(
        &mut state,
        register(id(3), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        register(id(4), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    let four: Vec<_> = (1..=4)
        .map(|n| (id(n), OperatorDecision::Autonomous))
        .collect();
    fires(&mut state, commands(&four), Rule::CommandApply);
}
