//! The network model's planner as a node runs it ([`NetworkModel::through_engine`]): the
//! service engine (`cooperation_adapters::engine`), fed the owner's reports as a planning
//! module's sync through its RTC interface, answering each delivered command as an AD API
//! `set_commands` request, and publishing when the engine says a publication is due. What an
//! operator is told is read back from the steering factors the engine writes, with the AD API's
//! constants as the spec's oracle states them (`spec::messages`), not with the adapters'
//! conversions.
//!
//! The host's clock stands still: time, and the periodic publications it brings, are the
//! engine model's. So an operator learns of the planner only through the publications that a
//! change makes due.
//!
//! [`NetworkModel::through_engine`]: super::NetworkModel::through_engine

use std::hash::{Hash, Hasher};

use cooperation::{
    Command, Config, CooperationStatus, Decision, Input, OperatorDecision, Phase, SceneId, State,
};
use cooperation_adapters::engine::{self, Engine, Now, Publication, Reply, Request};
use cooperation_adapters::rtc::{CooperateStatus, Lifecycle};
use cooperation_adapters::sync::{SyncRequest, SyncStatus};
use cooperation_adapters::{wire, Time, Uuid};

use serde::{Deserialize, Serialize};

use super::{NetStep, NetworkModel, Seen};
use crate::model::engine::EngineFault;
use crate::model::spec::messages::decision;

/// What the network model's planner is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PlannerKind {
    /// The library's core, its transition called directly (or through a planted [`Fault`](crate::Fault)).
    #[default]
    #[serde(rename = "core")]
    Core,
    /// The service engine, as a node runs it ([`NetworkModel::through_engine`]), with a fault
    /// planted in what it writes, if any.
    #[serde(rename = "engine")]
    Engine {
        /// The planted fault: only [`EngineFault::UndecidedAsUnknown`] is one the operators'
        /// views read.
        written_fault: Option<EngineFault>,
    },
}

/// The RTC interface the model's lane-change scenes are reported through.
const INTERFACE: &str = "lane_change_left";

/// The host's clock, which stands still.
fn now() -> Now {
    Now::new(0, Time::default())
}

/// The planner's engine.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Planner(Box<Engine>);

impl Hash for Planner {
    /// What decides the engine's next steps besides its core, which the model's state holds a
    /// copy of and hashes itself: whether a publication is due. (Every scene is routed through
    /// the one interface; the revision counter only labels publications.)
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.publication_due(now()).hash(state);
    }
}

impl Planner {
    /// An engine over a new core with `config`, no scene quota, told the clock's reading.
    pub(super) fn new(config: Config) -> Result<Self, String> {
        let options = engine::Options {
            scene_quota: 0,
            ..engine::Options::default()
        };
        let mut engine = Engine::new(config, options).map_err(|e| e.to_string())?;
        engine.handle_timeout(now());
        Ok(Self(Box::new(engine)))
    }

    /// The core.
    pub(super) fn state(&self) -> &State {
        self.0.state()
    }

    /// The planning module's sync reporting the owner's `input` through its RTC interface;
    /// whether the engine answered success. An input a module cannot report is not sent.
    pub(super) fn report(&mut self, input: &Input) -> Option<bool> {
        let request = Request::Sync(sync_of(input)?);
        Some(self.0.handle(request, now()).reply.success())
    }

    /// An operator's `set_commands` with `command` alone; whether it was answered success.
    pub(super) fn command(&mut self, command: Command) -> bool {
        let request = Request::Ad(wire::Request::SetCommands([command].into_iter().collect()));
        let reply = self.0.handle(request, now()).reply;
        matches!(reply, Reply::Ad(_)) && reply.success()
    }

    /// Whether a publication is due.
    pub(super) fn due(&self) -> bool {
        self.0.publication_due(now())
    }

    /// The publication, if one is due.
    pub(super) fn poll(&mut self) -> Option<Publication> {
        self.0.poll_publication(now())
    }

    /// What the streams would carry now, due or not.
    pub(super) fn publication(&self) -> Publication {
        self.0.publication(now().stamp)
    }
}

/// The lifecycle constant a module reports for `phase` (`tier4_rtc_msgs/State`).
const fn lifecycle(phase: Phase) -> u8 {
    match phase {
        Phase::Waiting => Lifecycle::WAITING_FOR_EXECUTION,
        Phase::Running => Lifecycle::RUNNING,
        Phase::Aborting => Lifecycle::ABORTING,
        Phase::Succeeded => Lifecycle::SUCCEEDED,
        Phase::Failed => Lifecycle::FAILED,
    }
}

/// The sync a planning module sends for an owner's input: the scene's status, safe when the
/// module decides to activate, in the input's phase (waiting for a registration), from 0 m to
/// 10 m. `None` for an input no module sends.
fn sync_of(input: &Input) -> Option<SyncRequest> {
    let (id, phase, report) = match input {
        Input::Register { id, report, .. } => (*id, Phase::Waiting, report),
        Input::Update {
            id, phase, report, ..
        } => (*id, *phase, report),
        _ => return None,
    };
    let status = CooperateStatus {
        uuid: Uuid::from(id),
        safe: report.decision == Decision::Activate,
        state: Lifecycle::new(lifecycle(phase)),
        start_distance: 0.0,
        finish_distance: 10.0,
        ..CooperateStatus::default()
    };
    Some(SyncRequest {
        interface: INTERFACE.to_owned(),
        statuses: vec![SyncStatus::from(&status)],
        sequences: Vec::new(),
        removed: Vec::new(),
    })
}

/// A module decision's `CooperationDecision` constant read back.
const fn module_decision(constant: u8) -> Option<Decision> {
    match constant {
        decision::DEACTIVATE => Some(Decision::Deactivate),
        decision::ACTIVATE => Some(Decision::Activate),
        _ => None,
    }
}

/// An operator decision's `CooperationDecision` constant read back.
const fn operator_decision(constant: u8) -> Option<OperatorDecision> {
    match constant {
        decision::DEACTIVATE => Some(OperatorDecision::Deactivate),
        decision::ACTIVATE => Some(OperatorDecision::Activate),
        decision::AUTONOMOUS => Some(OperatorDecision::Autonomous),
        decision::UNDECIDED => Some(OperatorDecision::Undecided),
        _ => None,
    }
}

/// Each scene a publication's steering factors tell of, in their order: its identifier and
/// the status its factor carries, read back with the AD API's constants (`None` where a
/// constant is not one the message defines, or the factor carries no one status). With
/// `undecided_as_unknown` (a planted fault), an `UNDECIDED` operator decision is read as the
/// engine would have written it as `UNKNOWN` (0).
pub(super) fn read_back(
    publication: &Publication,
    undecided_as_unknown: bool,
) -> Vec<(SceneId, Option<CooperationStatus>)> {
    publication
        .steering
        .factors
        .iter()
        .filter_map(|factor| {
            let [status] = factor.cooperation.as_slice() else {
                return None;
            };
            let id = SceneId::from_bytes(status.uuid.uuid);
            let mut cooperator = status.cooperator.decision;
            if undecided_as_unknown && cooperator == decision::UNDECIDED {
                cooperator = 0;
            }
            let read = module_decision(status.autonomous.decision)
                .zip(operator_decision(cooperator))
                .map(|(module, operator)| CooperationStatus {
                    id,
                    module_decision: module,
                    operator_decision: operator,
                    cancellable: status.cancellable,
                });
            Some((id, read))
        })
        .collect()
}

impl NetworkModel {
    /// What a publication of the engine tells an operator, through the planted fault if there
    /// is one.
    pub(super) fn written(&self, step: &NetStep, publication: &Publication) -> Vec<Seen> {
        let fault = self.planner
            == PlannerKind::Engine {
                written_fault: Some(EngineFault::UndecidedAsUnknown),
            };
        self.seen(step, read_back(publication, fault).into_iter())
    }

    /// An owner's input as its planning module reports it to the engine in `next`.
    pub(super) fn report_through(
        &self,
        from: &NetStep,
        next: &mut NetStep,
        input: &Input,
    ) -> Option<()> {
        let planner = next.planner.as_mut()?;
        let accepted = planner.report(input)?;
        let core = planner.state().clone();
        self.settle(from, next, core, !accepted);
        Some(())
    }

    /// A delivered command, answered by the engine in `next` as a `set_commands` request:
    /// whether it was applied, and whether applying it again at once would change the core.
    /// The rule it fired or was refused by (a label for the witnesses) is the core's transition
    /// of the state it was delivered in.
    pub(super) fn command_through(
        &self,
        from: &NetStep,
        next: &mut NetStep,
        command: Command,
    ) -> Option<(bool, bool)> {
        let planner = next.planner.as_mut()?;
        let applied = planner.command(command);
        let core = planner.state().clone();
        let mut again = planner.clone();
        let mut copy = from.core.clone();
        next.last = Some(
            match copy.apply(&Input::SetCommands {
                commands: vec![command],
            }) {
                Ok(transition) => transition.rule,
                Err(rejection) => rejection.rule(),
            },
        );
        self.settle(from, next, core, !applied);
        let second = applied && {
            again.command(command);
            *again.state() != next.core
        };
        Some((applied, second))
    }
}
