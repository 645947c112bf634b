//! The network model's actions in words, and the owner's inputs it offers.

use cooperation::{Decision, Geometry, Input, Phase, Report, SceneId};

use super::{NetAction, NetworkModel, Views, MODULE};
use crate::model::describe::{describe, short};

impl NetworkModel {
    /// One action in words.
    #[must_use]
    pub fn describe(&self, action: &NetAction) -> String {
        match action {
            NetAction::Owner(i) => self
                .owner
                .get(*i)
                .map_or_else(|| format!("owner input {i}"), describe),
            NetAction::Publish(k) => format!("planner sends its statuses to operator {}", k + 1),
            NetAction::PublishAll => "the planner's engine publishes its statuses".to_owned(),
            NetAction::Receive(k, m) => format!("operator {} receives status message {m}", k + 1),
            NetAction::Send(k, id, decision) => {
                format!(
                    "operator {} sends set_commands [{} {decision}]",
                    k + 1,
                    short(*id)
                )
            }
            NetAction::Deliver(k, m) => {
                format!("planner receives operator {}'s command message {m}", k + 1)
            }
            NetAction::ReceiveDuplicate(k, m) => {
                format!(
                    "operator {} receives a duplicate of status message {m}",
                    k + 1
                )
            }
            NetAction::DuplicateCommand(k, m) => format!(
                "network duplicates operator {}'s command message {m}",
                k + 1
            ),
            NetAction::LoseStatus(k, m) => {
                format!("network loses status message {m} to operator {}", k + 1)
            }
            NetAction::LoseCommand(k, m) => {
                format!("network loses operator {}'s command message {m}", k + 1)
            }
        }
    }
}

/// The scene owner's inputs: each identifier registers (its module declines), runs (its module
/// goes on) and completes; with status views it can also abort (its module declines), which
/// makes it not cancellable.
pub(super) fn owner_inputs(ids: &[SceneId], views: Views) -> Vec<Input> {
    let geometry = Geometry::velocity(0.0);
    let mut updates = vec![
        (Phase::Running, Decision::Activate),
        (Phase::Succeeded, Decision::Activate),
    ];
    if views == Views::Statuses {
        updates.push((Phase::Aborting, Decision::Deactivate));
    }
    let mut owner = Vec::new();
    for &id in ids {
        owner.push(Input::Register {
            id,
            module: MODULE,
            report: Report::new(Decision::Deactivate, geometry),
        });
        for &(phase, decision) in &updates {
            owner.push(Input::Update {
                id,
                module: MODULE,
                phase,
                report: Report::new(decision, geometry),
            });
        }
    }
    owner
}
