//! A planning module's side of cooperation: open a scene when a decision is needed, report
//! the module's judgment every planning cycle, drive with the merged decision, publish the
//! factor streams, and close the scene when done. The modules and their default policies come
//! from a settings file, `adapters/examples/planner_module.param.yaml`, one of them a user extension.
//! Run it with `cargo run -p cooperation-adapters --example planner_module`.

use cooperation::{
    Behavior, Decision, Detail, Direction, Distance, Geometry, Input, Module, Phase, Policy, Pose,
    Report, Rule, SceneId, Sequence, State, VelocityFactor, VelocityStatus,
};

/// The settings file, beside this example.
const SETTINGS: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/examples/planner_module.param.yaml"
);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The caller reads the file; the library only parses its text.
    let config = cooperation_adapters::settings::parse(&std::fs::read_to_string(SETTINGS)?)?;
    let lane_change = Module::new(Behavior::LaneChange);
    let crosswalk = Module::new(Behavior::Crosswalk);
    // A behaviour of this planner's own, beside the AD API's.
    let valet: Module = Module::new("valet-parking".parse()?);
    for (module, policy) in &config.policies {
        println!("{module}: {policy} by default");
    }
    assert_eq!(config.policies.get(&valet), Some(&Policy::Optional));
    let mut state = State::new(config)?;

    // A valet-parking scene: the planner holds back until the bay is clear, and says so.
    state.apply(&Input::Register {
        id: SceneId::from_u128(0x5cee_0003),
        module: valet,
        report: Report::new(Decision::Deactivate, Geometry::velocity(40.0))
            .with_detail(Detail::new("parking bay occupied")),
    })?;

    // A crosswalk scene, telling the operator why it stops.
    let crossing = SceneId::from_u128(0x5cee_0002);
    state.apply(&Input::Register {
        id: crossing,
        module: crosswalk,
        report: Report::new(Decision::Deactivate, Geometry::velocity(25.0))
            .with_detail(Detail::new("pedestrian waiting at the kerb")),
    })?;
    publish_velocity_factors(&state)?;

    // The module chose this identifier (a random UUID in a real planner).
    let id = SceneId::from_u128(0x5cee_0001);
    let mut distance = 80.0;
    let geometry = |d: f32| Geometry::steering(Direction::Left, d, d + 40.0);
    state.apply(&Input::Register {
        id,
        module: lane_change,
        report: Report::new(Decision::Activate, geometry(distance)),
    })?;

    for cycle in 1..=6 {
        // Every planning cycle: report the phase and the module's own judgment...
        let phase = if cycle < 4 {
            Phase::Waiting
        } else {
            Phase::Running
        };
        let safe = cycle != 2;
        let decision = if safe {
            Decision::Activate
        } else {
            Decision::Deactivate
        };
        distance -= 10.0;
        let update = Input::Update {
            id,
            module: lane_change,
            phase,
            report: Report::new(decision, geometry(distance)),
        };
        state.apply(&update)?;
        // ...then plan with the merged decision, never with the module's own.
        let merged = state.merged_decision(id).ok_or("the scene is live")?;
        println!("cycle {cycle}: module says {decision}, planner drives with {merged}");

        // An operator approves in cycle 3 (in a real system this arrives through set_commands).
        if cycle == 3 {
            use cooperation::{Command, OperatorDecision};
            let commands = vec![Command {
                id,
                decision: OperatorDecision::Activate,
            }];
            let approved = state.apply(&Input::SetCommands { commands })?;
            println!("  operator approves: {}", approved.rule);
        }
        // Time passes between cycles; the caller measures it, the library never reads a clock.
        state.apply(&Input::Tick { elapsed_ms: 100 })?;
    }

    // The lane change completes: the scene retires, and its identifier can never come back.
    let done = Input::Update {
        id,
        module: lane_change,
        phase: Phase::Succeeded,
        report: Report::new(Decision::Activate, geometry(0.0)),
    };
    let transition = state.apply(&done)?;
    assert_eq!(transition.rule, Rule::OwnerFinish);
    let retirement = state
        .retirement(id)
        .ok_or("a retired scene is remembered")?;
    println!(
        "finished: scene of {} retired ({})",
        retirement.module, retirement.reason
    );

    // A module bug (reusing the identifier) is a typed rejection that changes nothing.
    let again = Input::Register {
        id,
        module: lane_change,
        report: Report::new(Decision::Activate, geometry(50.0)),
    };
    let rejection = state
        .apply(&again)
        .err()
        .ok_or("a retired identifier is refused")?;
    println!(
        "reusing the identifier: {} ({})",
        rejection,
        rejection.rule()
    );
    Ok(())
}

/// What the planner publishes on `/api/planning/velocity_factors`: the cooperating scenes'
/// factors and its own factors of modules that do not cooperate (here an obstacle ahead), in
/// one stream, nearest first.
fn publish_velocity_factors(state: &State) -> Result<(), Box<dyn std::error::Error>> {
    let obstacle = VelocityFactor {
        pose: Pose::IDENTITY,
        distance: Distance(60.0),
        status: VelocityStatus::Approaching,
        behavior: Behavior::RunOut,
        sequence: Sequence::Empty,
        detail: Detail::new("slowing for a parked truck"),
        cooperation: None,
    };
    let mut factors = Vec::new();
    state.velocity_factors_with(&[obstacle], &mut factors)?;
    for factor in &factors {
        let cooperation = match factor.cooperation {
            Some(status) => format!("operator {}", status.operator_decision),
            None => "does not cooperate".to_owned(),
        };
        println!(
            "velocity factor: {} at {} m, {cooperation}: {:?}",
            factor.behavior,
            factor.distance.0,
            factor.detail.as_str()
        );
    }
    Ok(())
}
