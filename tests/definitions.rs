//! One test per definition of spec §6, named after its tag.

use crate::common::*;
use crate::spec_tables::*;
use cooperation::*;

/// `[COOP-RETIRE.1]`: the retired set keeps the newest `retired_capacity` identifiers; a
/// forgotten identifier is unknown again.
#[test]
fn coop_retire_1() {
    let mut state = state();
    churn(&mut state, 1..=4);
    let remembered: Vec<SceneId> = state.retired_oldest_first().map(|(id, _)| id).collect();
    assert_eq!(remembered, [id(2), id(3), id(4)]);
    assert_eq!(state.retirement(id(1)), None);
    rejects(
        &mut state,
        commands(&[(id(1), OperatorDecision::Activate)]),
        Rule::CommandUnknown,
    );
    rejects(
        &mut state,
        commands(&[(id(2), OperatorDecision::Activate)]),
        Rule::CommandRetired,
    );
    fires(
        &mut state,
        register(id(1), AVOIDANCE, Decision::Activate),
        Rule::RegisterNew,
    );
}

/// `[COOP-MERGE.1]`: the planner's merged decision follows the table for live scenes only.
#[test]
fn coop_merge_1() {
    let mut state = with_scenes();
    assert_eq!(state.merged_decision(id(1)), Some(Decision::Deactivate));
    assert_eq!(
        state.merged_decision(id(2)),
        Some(Decision::Deactivate),
        "required, undecided"
    );
    fires(
        &mut state,
        commands(&[(id(2), OperatorDecision::Autonomous)]),
        Rule::CommandApply,
    );
    assert_eq!(state.merged_decision(id(2)), Some(Decision::Activate));
    assert_eq!(state.merged_decision(id(9)), None);
    // Every row of the spec's table, and every row the design page's example table (as the
    // spec quotes it) stands for, through a live scene (`one_scene`).
    let merged =
        |operator, policy, module| one_scene(policy, module, operator).merged_decision(id(1));
    let spec = spec();
    let rows = table(&spec, "| operator | policy | module | merged |");
    assert_eq!(rows.len(), 16, "the whole domain");
    for row in &rows {
        let [o, p, m, expected] = row.as_slice() else {
            panic!("4 cells: {row:?}")
        };
        let (policy, module) = (
            policy(p).expect("a policy"),
            decision(m).expect("a decision"),
        );
        assert_eq!(
            merged(operator(o), policy, module),
            decision(expected),
            "{row:?}"
        );
    }
    let example = table(
        &spec,
        "| Operator decision | Policy | Module decision | Merged |",
    );
    for row in &example {
        for policy in expand(policy(&row[1]), &Policy::ALL) {
            for module in expand(decision(&row[2]), &Decision::ALL) {
                let expected = decision(&row[3]);
                assert_eq!(
                    merged(operator(&row[0]), policy, module),
                    expected,
                    "{row:?}"
                );
            }
        }
    }
}

/// `[COOP-CANCELLABLE.1]`: waiting and running scenes are cancellable; aborting is not.
#[test]
fn coop_cancellable_1() {
    let mut state = with_scenes();
    let cancellable = |state: &State| state.status(id(1)).map(|status| status.cancellable);
    assert_eq!(cancellable(&state), Some(true));
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    assert_eq!(cancellable(&state), Some(true));
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Aborting, Decision::Activate),
        Rule::OwnerUpdate,
    );
    assert_eq!(cancellable(&state), Some(false));
    let expected = [true, true, false, false, false];
    assert_eq!(Phase::ALL.map(Phase::is_cancellable), expected);
}

/// `[COOP-FORCE-ACTIVATED.1]`: operator activate over a module deactivate, while cancellable.
#[test]
fn coop_force_activated_1() {
    let mut state = with_scenes();
    assert_eq!(state.force_activated(id(1)), Some(false));
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Activate)]),
        Rule::CommandApply,
    );
    assert_eq!(state.force_activated(id(1)), Some(true));
    assert_eq!(state.merged_decision(id(1)), Some(Decision::Activate));
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    assert_eq!(
        state.force_activated(id(1)),
        Some(false),
        "module agrees now"
    );
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Aborting, Decision::Deactivate),
        Rule::OwnerUpdate,
    );
    assert_eq!(state.force_activated(id(1)), Some(false), "not cancellable");
    assert_eq!(state.force_activated(id(9)), None);
}

/// `[COOP-REQUESTED.1]`: a requested scene is held back while undecided, whatever its module's
/// policy; an explicit operator decision is followed; other scenes and the policy are untouched;
/// an operator activation of a requested scene is forced even when the module agrees.
#[test]
fn coop_requested_1() {
    let mut state = with_scenes();
    let (one, two) = (id(1), id(2));
    assert_eq!(state.policy(LANE_CHANGE), Some(Policy::Optional));
    let activate = |requested| {
        update_requested(
            one,
            LANE_CHANGE,
            Phase::Running,
            Decision::Activate,
            requested,
        )
    };
    fires(&mut state, activate(false), Rule::OwnerUpdate);
    assert_eq!(state.merged_decision(one), Some(Decision::Activate));
    fires(&mut state, activate(true), Rule::OwnerUpdate);
    assert!(state.scene(one).is_some_and(Scene::is_requested));
    assert_eq!(
        state.merged_decision(one),
        Some(Decision::Deactivate),
        "held for the operator"
    );
    assert_eq!(
        state.policy(LANE_CHANGE),
        Some(Policy::Optional),
        "policy untouched"
    );
    assert_eq!(state.force_activated(one), Some(false));
    fires(
        &mut state,
        commands(&[(one, OperatorDecision::Autonomous)]),
        Rule::CommandApply,
    );
    assert_eq!(
        state.merged_decision(one),
        Some(Decision::Activate),
        "autonomous follows the module"
    );
    fires(
        &mut state,
        commands(&[(one, OperatorDecision::Activate)]),
        Rule::CommandApply,
    );
    assert_eq!(state.merged_decision(one), Some(Decision::Activate));
    assert_eq!(
        state.force_activated(one),
        Some(true),
        "activation of a requested scene is forced"
    );
    fires(
        &mut state,
        commands(&[(one, OperatorDecision::Undecided)]),
        Rule::CommandApply,
    );
    assert_eq!(state.merged_decision(one), Some(Decision::Deactivate));
    // The next update without the request lets the policy apply again.
    fires(&mut state, activate(false), Rule::OwnerUpdate);
    assert_eq!(state.merged_decision(one), Some(Decision::Activate));
    // A registration can carry the request from the start.
    let three = id(3);
    let register = Input::Register {
        id: three,
        module: LANE_CHANGE,
        report: Report::new(Decision::Activate, Geometry::velocity(1.0)).requesting(),
    };
    fires(&mut state, register, Rule::RegisterNew);
    assert_eq!(state.merged_decision(three), Some(Decision::Deactivate));
    let other = state.scene(two).map(Scene::is_requested);
    assert_eq!(other, Some(false), "other scenes unaffected");
}

/// `[COOP-FORCE-DEACTIVATED.1]`: operator deactivate over a module activate, while running.
#[test]
fn coop_force_deactivated_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        commands(&[(id(2), OperatorDecision::Deactivate)]),
        Rule::CommandApply,
    );
    assert_eq!(
        state.force_deactivated(id(2)),
        Some(false),
        "waiting, not running"
    );
    fires(
        &mut state,
        update(id(2), AVOIDANCE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    assert_eq!(state.force_deactivated(id(2)), Some(true));
    assert_eq!(state.merged_decision(id(2)), Some(Decision::Deactivate));
    fires(
        &mut state,
        commands(&[(id(2), OperatorDecision::Undecided)]),
        Rule::CommandApply,
    );
    assert_eq!(
        state.force_deactivated(id(2)),
        Some(false),
        "the policy, not the operator"
    );
    assert_eq!(state.merged_decision(id(2)), Some(Decision::Deactivate));
    assert_eq!(state.force_deactivated(id(9)), None);
}

/// `[COOP-OUT-STATUS.1]`: one status per live scene, in identifier order.
#[test]
fn coop_out_status_1() {
    let mut state = state();
    fires(
        &mut state,
        register(id(5), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        register(id(2), AVOIDANCE, Decision::Deactivate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        commands(&[(id(5), OperatorDecision::Deactivate)]),
        Rule::CommandApply,
    );
    let mut out = Vec::new();
    state.statuses_into(&mut out);
    assert_eq!(
        out,
        [
            CooperationStatus {
                id: id(2),
                module_decision: Decision::Deactivate,
                operator_decision: OperatorDecision::Undecided,
                cancellable: true
            },
            CooperationStatus {
                id: id(5),
                module_decision: Decision::Activate,
                operator_decision: OperatorDecision::Deactivate,
                cancellable: true
            },
        ]
    );
}

/// `[COOP-OUT-ORDER.1]`: velocity and steering factors, each nearest first, ties by identifier,
/// NaN of either sign last.
#[test]
fn coop_out_order_1() {
    let mut state = State::new(Config {
        limits: Limits {
            max_scenes: 16,
            ..Limits::default()
        },
        ..config()
    })
    .expect("valid");
    let velocity = [
        (1, 30.0),
        (2, f32::NAN),
        (3, -5.0),
        (4, 30.0),
        (5, -f32::NAN),
        (6, f32::NEG_INFINITY),
        (7, f32::INFINITY),
        (8, -0.0),
        (9, 0.0),
        (12, f32::from_bits(0xffc0_0001)),
    ];
    for (n, distance) in velocity {
        let input = Input::Register {
            id: id(n),
            module: LANE_CHANGE,
            report: Report::new(Decision::Activate, Geometry::velocity(distance)),
        };
        fires(&mut state, input, Rule::RegisterNew);
    }
    for (n, start) in [(10, 50.0), (11, 0.5)] {
        let input = Input::Register {
            id: id(n),
            module: AVOIDANCE,
            report: Report::new(
                Decision::Activate,
                Geometry::steering(Direction::Right, start, start + 20.0),
            ),
        };
        fires(&mut state, input, Rule::RegisterNew);
    }
    let mut velocity_out = Vec::new();
    state.velocity_factors_into(&mut velocity_out);
    let order: Vec<SceneId> = velocity_out
        .iter()
        .map(|f| f.scene().expect("a scene's factor"))
        .collect();
    // As the spec says: ascending, -0.0 before 0.0, equal distances by identifier, every NaN
    // last (a negative one too: IEEE 754 total order would put it first), positive NaNs before
    // negative ones, negative NaNs in total order (the larger payload first).
    let expected = [6, 3, 8, 9, 1, 4, 7, 2, 12, 5].map(id);
    assert_eq!(order, expected);
    let mut lists = FactorLists::default();
    state.factors_into(&mut lists);
    let order: Vec<SceneId> = lists
        .velocity
        .iter()
        .map(|f| f.scene().expect("a scene's factor"))
        .collect();
    assert_eq!(order, expected, "factors_into, which sorts keys");
    assert!(velocity_out
        .iter()
        .all(|f| f.behavior == Behavior::LaneChange));
    let mut steering_out = Vec::new();
    state.steering_factors_into(&mut steering_out);
    let order: Vec<SceneId> = steering_out
        .iter()
        .map(|f| f.scene().expect("a scene's factor"))
        .collect();
    assert_eq!(order, [id(11), id(10)]);
    assert!(steering_out
        .iter()
        .all(|f| f.sequence == Sequence::Change && f.direction == Direction::Right));
}

/// `[COOP-POL-GET.2]`: every configured module's current policy, in module order.
#[test]
fn coop_pol_get_2() {
    let mut state = with_scenes();
    fires(
        &mut state,
        policies(&[(LANE_CHANGE, Policy::Required)]),
        Rule::PolicySet,
    );
    let list: Vec<PolicySetting> = state.policies().collect();
    assert_eq!(
        list,
        [
            PolicySetting {
                module: AVOIDANCE,
                policy: Policy::Required
            },
            PolicySetting {
                module: LANE_CHANGE,
                policy: Policy::Required
            },
        ]
    );
    // Extension names take their place among the built-in ones, by string, behaviour first.
    let module = |b: &str, s: &str| Module::with_sequence(b.parse().unwrap(), s.parse().unwrap());
    let listed = [
        module("aaa", ""),
        module("avoidance", "back"),
        module("avoidance", "change"),
        module("avoidance", "return"),
        module("lane-change", ""),
        module("lane-change-assist", ""),
        module("lane-change-assist", "change"),
        module("zz", "approach"),
    ];
    let mut given = listed;
    given.reverse();
    let state = State::new(Config::new(given.map(|m| (m, Policy::Optional)))).unwrap();
    let modules: Vec<Module> = state.policies().map(|setting| setting.module).collect();
    assert_eq!(modules, listed);
}

/// `State::relabel` renames identifiers without changing behaviour, and refuses collisions.
#[test]
fn relabel_renames_and_refuses_collisions() {
    let mut state = with_scenes();
    fires(
        &mut state,
        Input::Remove {
            id: id(2),
            module: AVOIDANCE,
        },
        Rule::OwnerRemove,
    );
    let swap = |n: SceneId| {
        if n == id(1) {
            id(2)
        } else if n == id(2) {
            id(1)
        } else {
            n
        }
    };
    let swapped = state.relabel(swap).expect("a bijection");
    assert_eq!(swapped.scene(id(2)).map(Scene::module), Some(LANE_CHANGE));
    assert_eq!(swapped.retirement(id(1)).map(|r| r.module), Some(AVOIDANCE));
    assert_eq!(swapped.check_invariants(), Ok(()));
    assert_eq!(swapped.relabel(swap), Some(state.clone()));
    let mut a = state.clone();
    let mut b = swapped.clone();
    a.apply(&commands(&[(id(1), OperatorDecision::Activate)]))
        .expect("applies");
    b.apply(&commands(&[(id(2), OperatorDecision::Activate)]))
        .expect("applies");
    assert_eq!(b.relabel(swap), Some(a));
    assert_eq!(state.relabel(|_| id(1)), None);
    let ids: Vec<SceneId> = state.retired_by_id().map(|(id, _)| id).collect();
    assert_eq!(ids, [id(2)]);
}
