//! The design page's example table (as quoted in the spec) and its 11-step sequence.

use crate::common::*;
use crate::spec_tables::*;
use cooperation::*;

/// The design page's lane-change example table, read from spec §6.2, holds for every value
/// each `-` stands for.
#[test]
fn seed_example_table_holds() {
    let rows = table(
        &spec(),
        "| Operator decision | Policy | Module decision | Merged |",
    );
    assert_eq!(rows.len(), 7, "the design page's table has 7 rows");
    let mut combinations = 0;
    for row in rows {
        let [operator_word, policy_word, module_word, merged_word, _] = row.as_slice() else {
            panic!("a row has 5 cells: {row:?}");
        };
        let merged = decision(merged_word).expect("merged is never '-'");
        for policy in expand(policy(policy_word), &Policy::ALL) {
            for module in expand(decision(module_word), &Decision::ALL) {
                assert_eq!(
                    merge(operator(operator_word), policy, module),
                    merged,
                    "{row:?}"
                );
                combinations += 1;
            }
        }
    }
    assert_eq!(
        combinations, 16,
        "the example table covers the whole domain"
    );
}

/// The design page's sequence: a lane change the module declines because of an obstacle,
/// overridden by the operator, with the optional policy.
#[test]
fn seed_sequence_11_steps() {
    let mut state = state();
    let scene = id(0x5678);
    // 1. The module creates a scene with a unique identifier.
    // 2. Its module decision: do not change lanes (obstacle).
    let geometry = Geometry::steering(Direction::Left, 40.0, 80.0);
    let input = Input::Register {
        id: scene,
        module: LANE_CHANGE,
        report: Report::new(Decision::Deactivate, geometry),
    };
    fires(&mut state, input, Rule::RegisterNew);
    assert_eq!(state.policy(LANE_CHANGE), Some(Policy::Optional));
    // 3. The merged decision: no operator decision yet, so the module's.
    // 4. The vehicle keeps the lane.
    assert_eq!(state.merged_decision(scene), Some(Decision::Deactivate));
    // 5. The scene sends a cooperation status; 6. the operator receives it.
    let mut factors = Vec::new();
    state.steering_factors_into(&mut factors);
    let [factor] = factors.as_slice() else {
        panic!("one steering factor: {factors:?}")
    };
    assert_eq!(factor.behavior, Behavior::LaneChange);
    assert_eq!(
        factor.cooperation,
        Some(CooperationStatus {
            id: scene,
            module_decision: Decision::Deactivate,
            operator_decision: OperatorDecision::Undecided,
            cancellable: true,
        })
    );
    // 7. The operator sends a command to change lanes; 8. the scene updates its operator decision.
    let commands = vec![Command {
        id: factor.scene().expect("a scene's factor"),
        decision: OperatorDecision::Activate,
    }];
    let transition = state.apply(&Input::SetCommands { commands });
    assert_eq!(transition.map(|t| t.rule), Ok(Rule::CommandApply));
    assert_eq!(
        state.scene(scene).map(Scene::operator_decision),
        Some(OperatorDecision::Activate)
    );
    // 9. The module decision is updated from the situation: still the obstacle.
    let update = Input::Update {
        id: scene,
        module: LANE_CHANGE,
        phase: Phase::Waiting,
        report: Report::new(Decision::Deactivate, geometry),
    };
    fires(&mut state, update, Rule::OwnerUpdate);
    // 10. The merged decision now follows the operator; 11. the vehicle changes lanes.
    assert_eq!(state.merged_decision(scene), Some(Decision::Activate));
    assert_eq!(state.force_activated(scene), Some(true));
}
