//! An operator interface's side of cooperation: read the statuses the planner publishes, act
//! on scenes by identifier (the AD API's `set_commands`), change a module's policy, and handle
//! every answer. Run it with `cargo run --example operator_ui`.

use cooperation::{
    Behavior, Command, CommandOutcome, Config, Decision, Geometry, Input, Module, OperatorDecision,
    Policy, PolicySetting, Rejection, Report, SceneId, State,
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
    let applied = state.apply(&Input::SetCommands { commands: batch })?;
    println!("set_commands: applied ({})", applied.rule);

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
    match state.apply(&Input::SetCommands { commands: stale }) {
        Ok(transition) => println!("set_commands: applied ({})", transition.rule),
        Err(rejection) => {
            println!("set_commands: refused by {}: {rejection}", rejection.rule());
            if let Rejection::Commands { outcomes, .. } = &rejection {
                for (n, outcome) in outcomes.iter().enumerate() {
                    match outcome {
                        CommandOutcome::Withheld => {
                            println!("  command {n}: valid, withheld with the batch");
                        }
                        CommandOutcome::Failed(why) => println!("  command {n}: {why}"),
                    }
                }
            }
        }
    }

    // Give a scene back to its module's policy, then make the policy optional.
    let withdraw = Command {
        id: ids[1],
        decision: OperatorDecision::Undecided,
    };
    let withdrawn = state.apply(&Input::SetCommands {
        commands: vec![withdraw],
    });
    println!(
        "withdraw the intersection decision: {:?}",
        withdrawn.map(|t| t.rule)
    );
    let policies = vec![PolicySetting {
        module: intersection,
        policy: Policy::Optional,
    }];
    let set = state.apply(&Input::SetPolicies { policies });
    println!("set_policies: {:?}", set.map(|t| t.rule));
    // The AD API's get_policies.
    for setting in state.policies() {
        println!("  {} is {}", setting.module, setting.policy);
    }
    println!(
        "intersection now drives with {:?}",
        state.merged_decision(ids[1])
    );
    Ok(())
}
