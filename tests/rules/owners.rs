//! Registration and the owners' inputs (`COOP-REG-*`, `COOP-OWN-*`).

use crate::common::*;
use cooperation::*;

/// `[COOP-REG-NEW.1]`: a new scene is live, waiting, undecided, age 0.
#[test]
fn coop_reg_new_1() {
    let mut state = state();
    let transition = fires(
        &mut state,
        register(id(7), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    assert!(transition.retired.is_empty());
    let scene = state.scene(id(7)).expect("live");
    assert_eq!(scene.module(), LANE_CHANGE);
    assert_eq!(scene.phase(), Phase::Waiting);
    assert_eq!(scene.module_decision(), Decision::Activate);
    assert_eq!(scene.operator_decision(), OperatorDecision::Undecided);
    assert_eq!(scene.age_ms(), 0);
    assert_eq!(scene.geometry(), &Geometry::velocity(10.0));
    assert_eq!(state.scene_count(), 1);
}

/// `[COOP-REG-LIVE.1]`: registering a live identifier again is rejected.
#[test]
fn coop_reg_live_1() {
    let mut state = with_scenes();
    let rejection = rejects(
        &mut state,
        register(id(1), LANE_CHANGE, Decision::Activate),
        Rule::RegisterLive,
    );
    assert_eq!(rejection, Rejection::AlreadyLive { id: id(1) });
}

/// `[COOP-REG-RETIRED.1]`: a retired identifier is never registered again, whatever module.
#[test]
fn coop_reg_retired_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        Input::Remove {
            id: id(1),
            module: LANE_CHANGE,
        },
        Rule::OwnerRemove,
    );
    for module in [LANE_CHANGE, AVOIDANCE, INTERSECTION] {
        let rejection = rejects(
            &mut state,
            register(id(1), module, Decision::Activate),
            Rule::RegisterRetired,
        );
        let retirement = Retirement {
            module: LANE_CHANGE,
            reason: RetireReason::Removed,
        };
        assert_eq!(
            rejection,
            Rejection::Revival {
                id: id(1),
                retirement
            }
        );
    }
}

/// `[COOP-REG-MODULE.1]`: a module without a policy cannot have scenes.
#[test]
fn coop_reg_module_1() {
    let mut state = state();
    let rejection = rejects(
        &mut state,
        register(id(3), INTERSECTION, Decision::Activate),
        Rule::RegisterModule,
    );
    assert_eq!(
        rejection,
        Rejection::UnsupportedModule {
            id: id(3),
            module: INTERSECTION
        }
    );
}

/// `[COOP-REG-FULL.1]`: no more than `max_scenes` live scenes; retiring one makes room.
#[test]
fn coop_reg_full_1() {
    let mut state = state();
    for n in 1..=4 {
        fires(
            &mut state,
            register(id(n), LANE_CHANGE, Decision::Activate),
            Rule::RegisterNew,
        );
    }
    let rejection = rejects(
        &mut state,
        register(id(5), LANE_CHANGE, Decision::Activate),
        Rule::RegisterFull,
    );
    assert_eq!(rejection, Rejection::SceneLimit { limit: 4 });
    fires(
        &mut state,
        Input::Remove {
            id: id(1),
            module: LANE_CHANGE,
        },
        Rule::OwnerRemove,
    );
    fires(
        &mut state,
        register(id(5), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
}

/// `[COOP-OWN-MODULE.1]`: registering, updating or removing another module's scene is rejected.
#[test]
fn coop_own_module_1() {
    let mut state = with_scenes();
    let wrong = Rejection::WrongModule {
        id: id(1),
        owner: LANE_CHANGE,
        named: AVOIDANCE,
    };
    let inputs = [
        register(id(1), AVOIDANCE, Decision::Activate),
        update(id(1), AVOIDANCE, Phase::Running, Decision::Activate),
        Input::Remove {
            id: id(1),
            module: AVOIDANCE,
        },
    ];
    for input in inputs {
        assert_eq!(rejects(&mut state, input, Rule::OwnerModule), wrong);
    }
    assert_eq!(state.scene(id(1)).map(Scene::module), Some(LANE_CHANGE));
}

/// `[COOP-OWN-UNKNOWN.1]`: an update or removal never registers implicitly.
#[test]
fn coop_own_unknown_1() {
    let mut state = with_scenes();
    for input in [
        update(id(9), LANE_CHANGE, Phase::Waiting, Decision::Activate),
        Input::Remove {
            id: id(9),
            module: LANE_CHANGE,
        },
    ] {
        assert_eq!(
            rejects(&mut state, input, Rule::OwnerUnknown),
            Rejection::OwnerUnknown { id: id(9) }
        );
    }
    assert!(state.scene(id(9)).is_none());
}

/// `[COOP-OWN-RETIRED.1]`: a retired scene is not updated, refreshed or removed again.
#[test]
fn coop_own_retired_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Succeeded, Decision::Activate),
        Rule::OwnerFinish,
    );
    let retirement = Retirement {
        module: LANE_CHANGE,
        reason: RetireReason::Succeeded,
    };
    for input in [
        update(id(1), LANE_CHANGE, Phase::Succeeded, Decision::Activate),
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Input::Remove {
            id: id(1),
            module: LANE_CHANGE,
        },
    ] {
        let rejection = rejects(&mut state, input, Rule::OwnerRetired);
        assert_eq!(
            rejection,
            Rejection::OwnerRetired {
                id: id(1),
                retirement
            }
        );
    }
}

/// `[COOP-OWN-KIND.1]`: a velocity scene is never updated with steering geometry.
#[test]
fn coop_own_kind_1() {
    let mut state = with_scenes();
    let input = Input::Update {
        id: id(1),
        module: LANE_CHANGE,
        phase: Phase::Running,
        report: Report::new(
            Decision::Activate,
            Geometry::steering(Direction::Left, 1.0, 2.0),
        ),
    };
    let rejection = rejects(&mut state, input, Rule::OwnerKind);
    assert_eq!(
        rejection,
        Rejection::KindMismatch {
            id: id(1),
            registered: FactorKind::Velocity,
            given: FactorKind::Steering
        }
    );
}

/// `[COOP-OWN-TRANSITION.1]`: a forbidden phase change changes nothing, not even the decision
/// or the age.
#[test]
fn coop_own_transition_1() {
    let mut state = with_scenes();
    fires(&mut state, Input::Tick { elapsed_ms: 30 }, Rule::TimeAge);
    let rejection = rejects(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Aborting, Decision::Activate),
        Rule::OwnerTransition,
    );
    assert_eq!(
        rejection,
        Rejection::PhaseTransition {
            id: id(1),
            from: Phase::Waiting,
            to: Phase::Aborting
        }
    );
    let scene = state.scene(id(1)).expect("live");
    assert_eq!(
        (scene.module_decision(), scene.age_ms()),
        (Decision::Deactivate, 30)
    );
}

/// `[COOP-OWN-FINISH.1]`: succeeded and failed retire the scene with their reason.
#[test]
fn coop_own_finish_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    let transition = fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Succeeded, Decision::Activate),
        Rule::OwnerFinish,
    );
    assert_eq!(transition.retired, [id(1)]);
    let transition = fires(
        &mut state,
        update(id(2), AVOIDANCE, Phase::Failed, Decision::Activate),
        Rule::OwnerFinish,
    );
    assert_eq!(transition.retired, [id(2)]);
    assert_eq!(state.scene_count(), 0);
    assert_eq!(
        state.retirement(id(1)).map(|r| r.reason),
        Some(RetireReason::Succeeded)
    );
    assert_eq!(
        state.retirement(id(2)).map(|r| r.reason),
        Some(RetireReason::Failed)
    );
    assert_eq!(state.merged_decision(id(1)), None);
}

/// `[COOP-OWN-UPDATE.1]`: phase, decision and geometry change, age resets, the operator
/// decision stands.
#[test]
fn coop_own_update_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Activate)]),
        Rule::CommandApply,
    );
    fires(&mut state, Input::Tick { elapsed_ms: 60 }, Rule::TimeAge);
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    let scene = state.scene(id(1)).expect("live");
    assert_eq!(scene.phase(), Phase::Running);
    assert_eq!(scene.module_decision(), Decision::Activate);
    assert_eq!(scene.geometry(), &Geometry::velocity(5.0));
    assert_eq!(scene.age_ms(), 0);
    assert_eq!(scene.operator_decision(), OperatorDecision::Activate);
    assert_eq!(state.scene(id(2)).map(Scene::age_ms), Some(60));
}

/// `[COOP-OWN-REMOVE.1]`: removal retires the scene in any live phase.
#[test]
fn coop_own_remove_1() {
    let mut state = with_scenes();
    walk(
        &mut state,
        id(2),
        AVOIDANCE,
        &[Phase::Running, Phase::Aborting],
    );
    let transition = fires(
        &mut state,
        Input::Remove {
            id: id(2),
            module: AVOIDANCE,
        },
        Rule::OwnerRemove,
    );
    assert_eq!(transition.retired, [id(2)]);
    assert_eq!(
        state.retirement(id(2)),
        Some(Retirement {
            module: AVOIDANCE,
            reason: RetireReason::Removed
        })
    );
    assert!(state.scene(id(1)).is_some());
}
