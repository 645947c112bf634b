//! The planning modules' service, `/cooperation/rtc/sync`: one round trip per planning cycle,
//! served by both nodes (rosbridge JSON and ROS 2 over DDS).
//!
//! A module sends every scene it reports this cycle as a `tier4_rtc_msgs/CooperateStatus` and
//! the identifiers it removes; the node applies each through the module's RTC interface
//! ([`crate::rtc::Interface`]) and answers with the interface's statuses and each live
//! scene's merged decision. `docs/server.md` shows the shapes; [`SyncCooperateStatusRequest`] is the request's DDS form.

use std::collections::{BTreeMap, BTreeSet};

use crate::rtc::{CooperateStatus, CooperateStatusArray, Lifecycle, RtcError, Uuid};
use crate::{Host, Time};
use cooperation::{SceneId, Sequence};
use serde::de::IgnoredAny;
use serde::{Deserialize, Serialize};

/// The service's name.
pub const NAME: &str = "/cooperation/rtc/sync";
/// The service's type.
pub const TYPE: &str = "cooperation_server/srv/SyncCooperateStatus";

/// The request.
#[derive(Clone, PartialEq, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyncRequest {
    /// The RTC interface the module reports through, e.g. `lane_change_left`.
    pub interface: String,
    /// This cycle's statuses, applied in order, each as `updateCooperateStatus`.
    #[serde(default)]
    pub statuses: Vec<SyncStatus>,
    /// The sequence of each new scene of an interface that binds several (the avoidances):
    /// each for a scene a status of this request reports, each scene's at most once, and
    /// counted with the statuses and removals against `max_batch`.
    #[serde(default)]
    pub sequences: Vec<StatedSequence>,
    /// Scenes the module removes, after the statuses, each as `removeCooperateStatus`.
    #[serde(default)]
    pub removed: Vec<Uuid>,
}

/// One status a module reports: the fields of `tier4_rtc_msgs/CooperateStatus` the module owns.
/// The fields the node fills (`stamp`, `module`, `command_status`, `auto_mode`) may be sent, as
/// the message has them, and are not read.
#[derive(Clone, PartialEq, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyncStatus {
    /// The scene.
    pub uuid: Uuid,
    /// The module's own judgment: the module decision is activate.
    pub safe: bool,
    /// The module asks for an operator decision.
    #[serde(default)]
    pub requested: bool,
    /// The lifecycle state (`tier4_rtc_msgs/State`).
    pub state: Lifecycle,
    /// Distance to the start of the section the scene changes, in metres.
    pub start_distance: f32,
    /// Distance to its end, in metres.
    pub finish_distance: f32,
    #[serde(default)]
    stamp: Option<IgnoredAny>,
    #[serde(default)]
    module: Option<IgnoredAny>,
    #[serde(default)]
    command_status: Option<IgnoredAny>,
    #[serde(default)]
    auto_mode: Option<IgnoredAny>,
}

impl SyncStatus {
    /// The status as the RTC interface reads it.
    #[must_use]
    pub fn status(&self) -> CooperateStatus {
        CooperateStatus {
            uuid: self.uuid,
            safe: self.safe,
            requested: self.requested,
            state: self.state,
            start_distance: self.start_distance,
            finish_distance: self.finish_distance,
            ..CooperateStatus::default()
        }
    }
}

/// A scene's sequence.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StatedSequence {
    /// The scene.
    pub uuid: Uuid,
    /// Its sequence, as the AD API writes it (`change`, `return`).
    pub sequence: Sequence,
}

/// The request in its DDS form (`cooperation_server/srv/SyncCooperateStatus` over ROS 2): each
/// status a whole `tier4_rtc_msgs/CooperateStatus`, since CDR has no optional field; the fields
/// the node fills are not read, as in the JSON form.
#[derive(Clone, PartialEq, Debug, Default, Serialize, Deserialize)]
pub struct SyncCooperateStatusRequest {
    /// As [`SyncRequest::interface`].
    pub interface: String,
    /// As [`SyncRequest::statuses`].
    pub statuses: Vec<CooperateStatus>,
    /// As [`SyncRequest::sequences`].
    pub sequences: Vec<StatedSequence>,
    /// As [`SyncRequest::removed`].
    pub removed: Vec<Uuid>,
}

impl From<SyncCooperateStatusRequest> for SyncRequest {
    fn from(request: SyncCooperateStatusRequest) -> Self {
        Self {
            interface: request.interface,
            statuses: request.statuses.iter().map(SyncStatus::from).collect(),
            sequences: request.sequences,
            removed: request.removed,
        }
    }
}

impl From<&CooperateStatus> for SyncStatus {
    /// The fields a module owns; the ones the node fills are dropped.
    fn from(status: &CooperateStatus) -> Self {
        Self {
            uuid: status.uuid,
            safe: status.safe,
            requested: status.requested,
            state: status.state,
            start_distance: status.start_distance,
            finish_distance: status.finish_distance,
            stamp: None,
            module: None,
            command_status: None,
            auto_mode: None,
        }
    }
}

/// The response.
#[derive(Clone, PartialEq, Debug, Default, Serialize, Deserialize)]
pub struct SyncResponse {
    /// Every status and removal applied.
    pub success: bool,
    /// Why the request as a whole was refused (an unknown interface, a malformed request);
    /// empty otherwise.
    pub message: String,
    /// One result per status, then one per removal, in the request's order.
    pub results: Vec<SyncResult>,
    /// The interface's statuses after the sync, as upstream publishes them on
    /// `/planning/cooperate_status/<interface>`.
    pub statuses: CooperateStatusArray,
    /// Each of the interface's live scenes' merged decision and force flags.
    pub activations: Vec<Activation>,
}

/// What became of one status or removal.
#[derive(Clone, PartialEq, Eq, Debug, Serialize, Deserialize)]
pub struct SyncResult {
    /// The scene.
    pub uuid: Uuid,
    /// It applied.
    pub success: bool,
    /// Why not, when it did not.
    pub message: String,
}

/// A live scene's merged decision: what upstream's `isActivated` and the force queries answer.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Serialize, Deserialize)]
pub struct Activation {
    /// The scene.
    pub uuid: Uuid,
    /// The merged decision is activate.
    pub activated: bool,
    /// An operator activated it.
    pub force_activated: bool,
    /// An operator deactivated it.
    pub force_deactivated: bool,
}

/// The request from its JSON form (rosbridge's `args`), or a message naming the field that
/// does not decode. A request over [`MAX_REQUEST_BYTES`](crate::wire::MAX_REQUEST_BYTES) is
/// refused unread.
///
/// # Errors
/// The message.
pub fn read_json(args: &[u8]) -> Result<SyncRequest, String> {
    crate::wire::check_request_len(args.len()).map_err(|malformed| malformed.to_string())?;
    let mut reader = serde_json::Deserializer::from_slice(args);
    let request: SyncRequest = serde_path_to_error::deserialize(&mut reader).map_err(|error| {
        let path = error.path().to_string();
        let inner = error.into_inner();
        if path == "." {
            inner.to_string()
        } else {
            format!("{path}: {inner}")
        }
    })?;
    reader.end().map_err(|error| error.to_string())?;
    Ok(request)
}

/// A sync's answer ([`answer`]).
#[derive(Clone, PartialEq, Debug)]
pub struct Synced {
    /// The response.
    pub response: SyncResponse,
    /// Whether the sync changed the core (a report also renews its scene's time to live).
    pub changed: bool,
    /// What it refused that its host should log, a line each: the whole sync when it carries
    /// more than `max_batch` entries, a scene over its interface's quota. Logging is the host's
    /// (`cooperation-dds` logs a peer's refusals at most once a period, [`crate::refusals`]).
    pub refused: Vec<String>,
}

/// A request's answer from the core. The engine ([`crate::engine`]) decides what is published.
pub fn answer(host: &mut Host, request: &SyncRequest, stamp: Time) -> Synced {
    let refusal = |message: String| Synced {
        response: refused(message),
        changed: false,
        refused: Vec::new(),
    };
    // One sync holds the node's lock while it applies: it carries no more entries than a
    // command batch may.
    let most = host.state().limits().max_batch;
    let entries = request.statuses.len() + request.sequences.len() + request.removed.len();
    if entries > most {
        let message = format!(
            "{entries} statuses, sequences and removals, more than the {most} a sync may carry \
             (the settings' max_batch)"
        );
        return Synced {
            refused: vec![format!("a sync refused: {message}")],
            ..refusal(message)
        };
    }
    let mut interface = match host.interface(&request.interface) {
        Ok(interface) => interface,
        Err(error) => return refusal(error.to_string()),
    };
    let sequences = match stated_sequences(request) {
        Ok(sequences) => sequences,
        Err(message) => return refusal(message),
    };
    let mut changed = false;
    let mut logged = Vec::new();
    let mut results = Vec::with_capacity(request.statuses.len() + request.removed.len());
    for status in &request.statuses {
        let stated = sequences.get(&status.uuid).copied();
        let outcome = status
            .status()
            .report()
            .map_err(RtcError::from)
            .map(|report| match stated {
                Some(sequence) => report.in_sequence(sequence),
                None => report,
            })
            .and_then(|report| interface.update_cooperate_status(&report))
            .map(drop);
        if let Err(error @ RtcError::SceneQuota { .. }) = &outcome {
            logged.push(format!("a scene refused: {error}"));
        }
        changed |= outcome.is_ok();
        results.push(result(status.uuid, outcome));
    }
    for &uuid in &request.removed {
        let outcome = interface
            .remove_cooperate_status(SceneId::from(uuid))
            .map(drop);
        changed |= outcome.is_ok();
        results.push(result(uuid, outcome));
    }
    let view = interface.view();
    let statuses = view.cooperate_status_array(stamp);
    let activations = statuses
        .statuses
        .iter()
        .map(|status| {
            let id = SceneId::from(status.uuid);
            Activation {
                uuid: status.uuid,
                activated: view.is_activated(id),
                force_activated: view.is_force_activated(id),
                force_deactivated: view.is_force_deactivated(id),
            }
        })
        .collect();
    let response = SyncResponse {
        success: results.iter().all(|result| result.success),
        message: String::new(),
        results,
        statuses,
        activations,
    };
    Synced {
        response,
        changed,
        refused: logged,
    }
}

/// Each stated sequence by its scene: each scene's at most once, and only for a scene a status
/// of the same request reports (a sequence is read only with its status).
fn stated_sequences(request: &SyncRequest) -> Result<BTreeMap<Uuid, Sequence>, String> {
    let reported: BTreeSet<Uuid> = request.statuses.iter().map(|status| status.uuid).collect();
    let mut sequences = BTreeMap::new();
    let mut first = BTreeMap::new();
    for (at, stated) in request.sequences.iter().enumerate() {
        let id = SceneId::from(stated.uuid);
        if let Some(earlier) = first.insert(stated.uuid, at) {
            return Err(format!(
                "sequences[{at}] states the sequence of scene {id} again (sequences[{earlier}] \
                 did): a scene's sequence is stated once"
            ));
        }
        if !reported.contains(&stated.uuid) {
            return Err(format!(
                "sequences[{at}] states the sequence of scene {id}, which no status of this \
                 sync reports"
            ));
        }
        sequences.insert(stated.uuid, stated.sequence);
    }
    Ok(sequences)
}

fn result<E: ToString>(uuid: Uuid, outcome: Result<(), E>) -> SyncResult {
    match outcome {
        Ok(()) => SyncResult {
            uuid,
            success: true,
            message: String::new(),
        },
        Err(error) => SyncResult {
            uuid,
            success: false,
            message: error.to_string(),
        },
    }
}

/// A response refusing the request as a whole.
#[must_use]
pub fn refused(message: String) -> SyncResponse {
    SyncResponse {
        success: false,
        message,
        ..SyncResponse::default()
    }
}
