//! A planning module's side of cooperation: open a scene when a decision is needed, report
//! the module's judgment every planning cycle, drive with the merged decision, and close the
//! scene when done. Run it with `cargo run --example planner_module`.

use cooperation::{
    Behavior, Config, Decision, Direction, Geometry, Input, Module, Phase, Policy, Report, Rule,
    SceneId, State,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let lane_change = Module::new(Behavior::LaneChange);
    let mut state = State::new(Config::new([(lane_change, Policy::Required)]))?;

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
            Phase::WaitingForExecution
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
            let response = state.set_commands(vec![Command {
                id,
                decision: OperatorDecision::Activate,
            }]);
            println!("  operator approves: success = {}", response.status.success);
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
