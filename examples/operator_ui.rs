//! An operator interface's side of cooperation: read the statuses the planner publishes, act
//! on scenes by identifier through `set_commands`, change a module's policy, and handle every
//! answer. Run it with `cargo run --example operator_ui`.

use cooperation::{
    Behavior, Command, CommandOutcome, Config, Decision, Geometry, Input, Module, OperatorDecision,
    Policy, PolicySetting, Report, SceneId, State,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let crosswalk = Module::new(Behavior::Crosswalk);
    let intersection = Module::new(Behavior::Intersection);
    let mut state = State::new(Config::new([
        (crosswalk, Policy::Optional),
        (intersection, Policy::Required),
    ]))?;
    // Two scenes opened by the planner (in a real system: its modules, on their own cycle).
    for (n, module, decision, distance) in [
        (1, crosswalk, Decision::Deactivate, 35.0),
        (2, intersection, Decision::Activate, 120.0),
    ] {
        let geometry = Geometry::velocity(distance);
        state.apply(&Input::Register {
            id: SceneId::from_u128(n),
            module,
            report: Report::new(decision, geometry),
        })?;
    }

    // What the planner publishes: velocity factors, nearest first, each with its status.
    let mut factors = Vec::new();
    state.velocity_factors_into(&mut factors);
    for factor in &factors {
        // A factor of a module that does not cooperate has no status: nothing to decide.
        let Some(status) = factor.cooperation else {
            continue;
        };
        let merged = state.merged_decision(status.id).ok_or("live")?;
        println!(
            "{} at {:>5.1} m: module {}, operator {}, cancellable {} -> planner {merged}",
            factor.behavior,
            factor.distance.0,
            status.module_decision,
            status.operator_decision,
            status.cancellable
        );
    }

    // The operator overrides the crosswalk stop and approves the intersection, in one batch.
    let ids: Vec<SceneId> = factors
        .iter()
        .filter_map(|f| f.cooperation.map(|status| status.id))
        .collect();
    let batch = ids
        .iter()
        .map(|&id| Command {
            id,
            decision: OperatorDecision::Activate,
        })
        .collect();
    let response = state.set_commands(batch);
    println!(
        "set_commands: success {}, code {}",
        response.status.success, response.status.code
    );

    // A batch naming a scene that does not exist applies nothing, and says which and why.
    let stale = vec![
        Command {
            id: ids[0],
            decision: OperatorDecision::Deactivate,
        },
        Command {
            id: SceneId::from_u128(99),
            decision: OperatorDecision::Deactivate,
        },
    ];
    let response = state.set_commands(stale);
    println!(
        "set_commands: success {}, code {}: {}",
        response.status.success, response.status.code, response.status.message
    );
    for (n, outcome) in response.outcomes.iter().enumerate() {
        match outcome {
            CommandOutcome::Applied => println!("  command {n}: applied"),
            CommandOutcome::Withheld => println!("  command {n}: valid, withheld with the batch"),
            CommandOutcome::Failed(why) => println!("  command {n}: {why}"),
        }
    }

    // Give a scene back to its module's policy, then make the policy optional.
    let withdraw = Command {
        id: ids[1],
        decision: OperatorDecision::Undecided,
    };
    let response = state.set_commands(vec![withdraw]);
    println!(
        "withdraw the intersection decision: success {}",
        response.status.success
    );
    let response = state.set_policies(vec![PolicySetting {
        module: intersection,
        policy: Policy::Optional,
    }]);
    println!(
        "set_policies: success {} ({:?})",
        response.status.success,
        response.result.map(|t| t.rule)
    );
    let (_, policies) = state.get_policies();
    for setting in policies {
        println!("  {} is {}", setting.module, setting.policy);
    }
    println!(
        "intersection now drives with {:?}",
        state.merged_decision(ids[1])
    );
    Ok(())
}
