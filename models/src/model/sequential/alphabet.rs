//! The model's inputs: every input over its identifiers and modules, valid or not.

use cooperation::{
    Command, Config, Decision, Geometry, Input, Module, OperatorDecision, Phase, Policy,
    PolicySetting, Report, SceneId,
};

use super::STRANGER;

/// Every input over the model's identifiers and modules: registrations, updates to every phase
/// with either decision (and one of the wrong kind), removals, commands (single, duplicate,
/// paired, empty, over the limit), policies (single, duplicate, empty, over the limit), time.
pub(super) fn alphabet(config: &Config, ids: &[SceneId]) -> Vec<Input> {
    let modules: Vec<Module> = config.policies.keys().copied().collect();
    let first = modules.first().copied().unwrap_or(STRANGER);
    let velocity = Geometry::velocity(0.0);
    let over_limit = config.limits.max_batch + 1;
    let mut inputs = Vec::new();
    for &id in ids {
        for &module in modules.iter().chain([&STRANGER]) {
            for decision in Decision::ALL {
                inputs.push(Input::Register {
                    id,
                    module,
                    report: Report::new(decision, velocity),
                });
            }
        }
        // An owner asking for an operator decision (`[COOP-REQUESTED.1]`): registering so, and
        // updating so while waiting or running; every other update withdraws the request.
        for &module in &modules {
            inputs.push(Input::Register {
                id,
                module,
                report: Report::new(Decision::Activate, velocity).requesting(),
            });
            for phase in [Phase::Waiting, Phase::Running] {
                inputs.push(Input::Update {
                    id,
                    module,
                    phase,
                    report: Report::new(Decision::Activate, velocity).requesting(),
                });
            }
        }
        for &module in &modules {
            for phase in Phase::ALL {
                for decision in Decision::ALL {
                    inputs.push(Input::Update {
                        id,
                        module,
                        phase,
                        report: Report::new(decision, velocity),
                    });
                }
            }
            inputs.push(Input::Remove { id, module });
        }
        let steering = Geometry::steering(cooperation::Direction::Left, 0.0, 1.0);
        inputs.push(Input::Update {
            id,
            module: first,
            phase: Phase::Running,
            report: Report::new(Decision::Activate, steering),
        });
        for decision in OperatorDecision::ALL {
            inputs.push(Input::SetCommands {
                commands: vec![Command { id, decision }],
            });
        }
        let twice = Command {
            id,
            decision: OperatorDecision::Activate,
        };
        inputs.push(Input::SetCommands {
            commands: vec![twice, twice],
        });
    }
    // Every ordered pair, so that the alphabet is closed under renaming identifiers, as
    // symmetry reduction needs: a class's representative then meets every input any member
    // of the class could.
    for &a in ids {
        for &b in ids.iter().filter(|&&b| b != a) {
            inputs.push(Input::SetCommands {
                commands: vec![
                    Command {
                        id: a,
                        decision: OperatorDecision::Activate,
                    },
                    Command {
                        id: b,
                        decision: OperatorDecision::Deactivate,
                    },
                ],
            });
        }
    }
    inputs.push(Input::SetCommands {
        commands: Vec::new(),
    });
    // One over-limit batch, naming the first identifier. Its renamings are not in the
    // alphabet, but the batch limit refuses every one of them before reading an identifier,
    // so they would all do what this one does.
    if let Some(&id) = ids.first() {
        let command = Command {
            id,
            decision: OperatorDecision::Autonomous,
        };
        inputs.push(Input::SetCommands {
            commands: vec![command; over_limit],
        });
    }
    for &module in modules.iter().chain([&STRANGER]) {
        for policy in Policy::ALL {
            inputs.push(Input::SetPolicies {
                policies: vec![PolicySetting { module, policy }],
            });
        }
    }
    let setting = PolicySetting {
        module: first,
        policy: Policy::Required,
    };
    inputs.push(Input::SetPolicies {
        policies: vec![setting, setting],
    });
    inputs.push(Input::SetPolicies {
        policies: Vec::new(),
    });
    inputs.push(Input::SetPolicies {
        policies: vec![setting; over_limit],
    });
    inputs.push(Input::Tick { elapsed_ms: 1 });
    inputs
}
