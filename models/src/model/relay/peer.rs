//! A planning module's RTC interface as upstream's `rtc_interface` behaves, quirks included:
//! the peer the relay model and its scenario tests put beside the relay.
//!
//! Written from the upstream facts (`upstream-rtc` notes §3.4 to §3.6), not from this
//! project's adapter: a vector of statuses searched by identifier; a new status forced to
//! waiting, with command `DEACTIVATE` and the interface's auto mode; updates checked against
//! upstream's transition table and dropped whole when it forbids them; a command taken for a
//! registered waiting or running scene, which sets its command and turns its `auto_mode` off; the
//! auto-mode switch overwriting every status's `auto_mode`; `isActivated` as upstream computes
//! it.

use cooperation::{Phase, SceneId};
use cooperation_adapters::rtc::{
    self, AutoModeStatus, CooperateCommandsRequest, CooperateCommandsResponse, CooperateResponse,
    CooperateStatus, CooperateStatusArray,
};
use cooperation_adapters::{Time, Uuid};
use serde::{Deserialize, Serialize};

/// One status as the interface keeps it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub struct Status {
    /// The scene.
    pub id: SceneId,
    /// `safe`.
    pub safe: bool,
    /// `requested`.
    pub requested: bool,
    /// `command_status` is `ACTIVATE`.
    pub activate: bool,
    /// `state`.
    pub phase: Phase,
    /// `auto_mode`.
    pub auto_mode: bool,
}

/// An upstream RTC interface.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
pub struct Upstream {
    /// The module type its statuses carry.
    pub module: u8,
    /// `is_auto_mode_enabled_`: the auto mode of new statuses.
    pub auto_mode: bool,
    /// `registered_status_`, in registration order.
    pub statuses: Vec<Status>,
}

/// Upstream's transition table of `updateCooperateStatus` (four rules).
const fn allowed(from: Phase, to: Phase) -> bool {
    use Phase::{Aborting, Failed, Running, Waiting};
    matches!(
        (from, to),
        (Waiting, Waiting | Running | Failed)
            | (Running, Running | Aborting | Phase::Succeeded | Failed)
            | (Aborting, Aborting | Failed)
    ) || from as u8 == to as u8
}

/// `tier4_rtc_msgs/State`'s number of a phase.
const fn lifecycle(phase: Phase) -> u8 {
    match phase {
        Phase::Waiting => rtc::Lifecycle::WAITING_FOR_EXECUTION,
        Phase::Running => rtc::Lifecycle::RUNNING,
        Phase::Aborting => rtc::Lifecycle::ABORTING,
        Phase::Succeeded => rtc::Lifecycle::SUCCEEDED,
        Phase::Failed => rtc::Lifecycle::FAILED,
    }
}

impl Upstream {
    /// `RTCInterface(node, name, enable_rtc)`: auto mode is `!enable_rtc`.
    #[must_use]
    pub const fn new(module: u8, enable_rtc: bool) -> Self {
        Self {
            module,
            auto_mode: !enable_rtc,
            statuses: Vec::new(),
        }
    }

    fn find(&mut self, id: SceneId) -> Option<&mut Status> {
        self.statuses.iter_mut().find(|status| status.id == id)
    }

    /// `updateCooperateStatus(uuid, safe, state, …, requested)`.
    pub fn update(&mut self, id: SceneId, safe: bool, phase: Phase, requested: bool) {
        let auto_mode = self.auto_mode;
        match self.find(id) {
            None => self.statuses.push(Status {
                id,
                safe,
                requested,
                activate: false,
                phase: Phase::Waiting,
                auto_mode,
            }),
            Some(status) if allowed(status.phase, phase) => {
                status.safe = safe;
                status.requested = requested;
                status.phase = phase;
            }
            Some(_) => {}
        }
    }

    /// `removeCooperateStatus(uuid)`.
    pub fn remove(&mut self, id: SceneId) {
        if let Some(at) = self.statuses.iter().position(|status| status.id == id) {
            self.statuses.remove(at);
        }
    }

    /// `clearCooperateStatus()`.
    pub fn clear(&mut self) {
        self.statuses.clear();
    }

    /// The `cooperate_commands` service (not locked): one response per command, success when
    /// the scene is registered waiting or running; then each such command sets its scene's
    /// command and turns its auto mode off.
    pub fn cooperate_commands(
        &mut self,
        request: &CooperateCommandsRequest,
    ) -> CooperateCommandsResponse {
        let mut responses = Vec::with_capacity(request.commands.len());
        for command in &request.commands {
            let id = SceneId::from(command.uuid);
            let success = self
                .find(id)
                .is_some_and(|status| matches!(status.phase, Phase::Waiting | Phase::Running));
            responses.push(CooperateResponse {
                uuid: command.uuid,
                module: command.module,
                success,
            });
        }
        for command in &request.commands {
            let id = SceneId::from(command.uuid);
            if let Some(status) = self.find(id) {
                if matches!(status.phase, Phase::Waiting | Phase::Running) {
                    status.activate = command.command.r#type == rtc::Command::ACTIVATE;
                    status.auto_mode = false;
                }
            }
        }
        CooperateCommandsResponse { responses }
    }

    /// The `enable_auto_mode` service: the default for new statuses and every status's
    /// `auto_mode`; always a success.
    pub fn enable_auto_mode(&mut self, enable: bool) -> bool {
        self.auto_mode = enable;
        for status in &mut self.statuses {
            status.auto_mode = enable;
        }
        true
    }

    /// `isActivated(uuid)`.
    #[must_use]
    pub fn is_activated(&self, id: SceneId) -> bool {
        let Some(status) = self.statuses.iter().find(|status| status.id == id) else {
            return false;
        };
        if matches!(status.phase, Phase::Succeeded | Phase::Failed) {
            return false;
        }
        if status.auto_mode && !status.requested {
            return status.safe;
        }
        status.activate
    }

    /// What `publishCooperateStatus(stamp)` publishes.
    #[must_use]
    pub fn status_array(&self, stamp: Time) -> CooperateStatusArray {
        CooperateStatusArray {
            stamp,
            statuses: self
                .statuses
                .iter()
                .map(|status| CooperateStatus {
                    stamp,
                    uuid: Uuid::from(status.id),
                    module: rtc::Module::new(self.module),
                    safe: status.safe,
                    requested: status.requested,
                    command_status: rtc::Command::new(if status.activate {
                        rtc::Command::ACTIVATE
                    } else {
                        rtc::Command::DEACTIVATE
                    }),
                    state: rtc::Lifecycle::new(lifecycle(status.phase)),
                    auto_mode: status.auto_mode,
                    start_distance: 10.0,
                    finish_distance: 60.0,
                })
                .collect(),
        }
    }

    /// What the 10 Hz auto-mode timer publishes.
    #[must_use]
    pub const fn auto_mode_status(&self) -> AutoModeStatus {
        AutoModeStatus {
            module: rtc::Module::new(self.module),
            is_auto_mode: self.auto_mode,
        }
    }
}
