//! The checked-in seed trace replays the design page's 11-step sequence exactly as the core's
//! seed test (`tests/seed.rs`) drives it.

use std::ops::ControlFlow;

use cooperation::*;
use cooperation_trace::{run, Observation, Options, Replayer, Sink, Step, TraceError};

const SEED: &str = include_str!("data/seed.jsonl");

/// Keeps every step and the state after it.
#[derive(Default)]
struct Recorder {
    steps: Vec<(Step, State)>,
}

impl Sink for Recorder {
    fn step(&mut self, step: &Step, replayer: &Replayer) -> Result<ControlFlow<()>, TraceError> {
        let state = replayer.state().expect("configured").clone();
        self.steps.push((step.clone(), state));
        Ok(ControlFlow::Continue(()))
    }

    fn observed(
        &mut self,
        _: usize,
        _: &Observation,
        _: &Replayer,
    ) -> Result<ControlFlow<()>, TraceError> {
        Ok(ControlFlow::Continue(()))
    }
}

const LANE_CHANGE: Module = Module::new(Behavior::LaneChange);

/// The seed's scene and geometry (the seed test's identifier; poses with a unit quaternion).
fn scene() -> (SceneId, Geometry) {
    let pose = Pose {
        position: [0.0; 3],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };
    let geometry = Geometry::Steering {
        poses: [pose; 2],
        distances: [Distance(40.0), Distance(80.0)],
        direction: Direction::Left,
        status: SteeringStatus::Approaching,
    };
    (SceneId::from_u128(0x5678), geometry)
}

/// The owner's inputs of the seed, built in one place.
fn register(id: SceneId, decision: Decision, geometry: Geometry) -> Input {
    Input::Register {
        id,
        module: LANE_CHANGE,
        report: Report::new(decision, geometry),
    }
}

fn update(id: SceneId, phase: Phase, decision: Decision, geometry: Geometry) -> Input {
    Input::Update {
        id,
        module: LANE_CHANGE,
        phase,
        report: Report::new(decision, geometry),
    }
}

fn replay_seed() -> Vec<(Step, State)> {
    let mut recorder = Recorder::default();
    run(SEED.as_bytes(), &Options::default(), &mut recorder).expect("the seed trace replays");
    recorder.steps
}

#[test]
fn seed_trace_is_the_design_page_sequence() {
    let steps = replay_seed();
    let rules: Vec<Rule> = steps.iter().map(|(step, _)| step.rule()).collect();
    assert_eq!(
        rules,
        [
            Rule::RegisterNew,
            Rule::TimeAge,
            Rule::CommandApply,
            Rule::TimeAge,
            Rule::OwnerUpdate,
        ]
    );
    let (id, geometry) = scene();
    let [(register_step, registered), _, (command, commanded), _, (update_step, updated)] =
        steps.as_slice()
    else {
        panic!("five steps");
    };
    // 1-2. The module creates the scene; its decision is not to change lanes.
    assert_eq!(
        register_step.input,
        register(id, Decision::Deactivate, geometry)
    );
    assert_eq!(registered.policy(LANE_CHANGE), Some(Policy::Optional));
    // 3-4. No operator decision yet: the merged decision is the module's.
    assert_eq!(registered.merged_decision(id), Some(Decision::Deactivate));
    // 5-6. The status the operator receives.
    let mut factors = Vec::new();
    registered.steering_factors_into(&mut factors);
    let [factor] = factors.as_slice() else {
        panic!("one steering factor: {factors:?}");
    };
    assert_eq!(factor.behavior, Behavior::LaneChange);
    assert_eq!(
        factor.cooperation,
        Some(CooperationStatus {
            id,
            module_decision: Decision::Deactivate,
            operator_decision: OperatorDecision::Undecided,
            cancellable: true,
        })
    );
    // 7-8. The operator's command applies; the operator decision is activate.
    assert_eq!(
        command.input,
        Input::SetCommands {
            commands: vec![Command {
                id,
                decision: OperatorDecision::Activate
            }]
        }
    );
    assert_eq!(
        commanded.scene(id).map(Scene::operator_decision),
        Some(OperatorDecision::Activate)
    );
    // 9. The module decision is updated: still the obstacle.
    assert_eq!(
        update_step.input,
        update(id, Phase::Waiting, Decision::Deactivate, geometry)
    );
    // 10-11. The merged decision follows the operator: the vehicle changes lanes.
    assert_eq!(updated.merged_decision(id), Some(Decision::Activate));
    assert_eq!(updated.force_activated(id), Some(true));
}

/// The replayer adds nothing of its own: its final state is the one the same inputs give when
/// applied to the core directly, ticks included.
#[test]
fn seed_trace_ends_where_the_core_does() {
    let steps = replay_seed();
    let (id, geometry) = scene();
    let mut state = State::new(Config::new([(LANE_CHANGE, Policy::Optional)])).unwrap();
    for input in [
        register(id, Decision::Deactivate, geometry),
        Input::Tick { elapsed_ms: 500 },
        Input::SetCommands {
            commands: vec![Command {
                id,
                decision: OperatorDecision::Activate,
            }],
        },
        Input::Tick { elapsed_ms: 100 },
        update(id, Phase::Waiting, Decision::Deactivate, geometry),
    ] {
        state.apply(&input).unwrap();
    }
    assert_eq!(steps.last().map(|(_, state)| state), Some(&state));
}
