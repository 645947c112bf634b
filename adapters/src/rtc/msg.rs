//! The `tier4_rtc_msgs` messages and services, field for field, and their parsing into the
//! core's types.
//!
//! With the `serde` feature every type (de)serializes in the JSON shape rosbridge uses: a UUID is
//! `{"uuid": [16 numbers]}` (a base64 string is accepted too), a time is `{"sec", "nanosec"}`,
//! and a message that carries a constant is `{"type": n}`. Fields hold the raw numbers, so any
//! message deserializes; parsing into the core's types is where an undefined constant is
//! refused, with the field named (`[COOP-DEV-CONSTANTS.1]`).

use cooperation::{Decision, Phase, SceneId};

use super::{FieldError, ModuleType};

pub use crate::Uuid;

/// `builtin_interfaces/Time`, shared with the AD API messages.
use crate::Time;

crate::constant::constant_message! {
    /// `tier4_rtc_msgs/Command`: an operator's command, or a scene's command status.
    #[serde(deny_unknown_fields)]
    pub struct Command {
        /// [`DEACTIVATE`](Self::DEACTIVATE) or [`ACTIVATE`](Self::ACTIVATE).
        #[serde(rename = "type")]
        pub r#type: u8
    }
    meaning Decision;
    /// Plan with priority on safety.
    const DEACTIVATE = 0 => Decision::Deactivate;
    /// Plan with priority on driving.
    const ACTIVATE = 1 => Decision::Activate;
}

impl Command {
    /// The decision it carries.
    ///
    /// # Errors
    /// A [`FieldError`] on `type` if it is neither constant.
    pub fn decision(&self) -> Result<Decision, FieldError> {
        self.meaning()
            .ok_or_else(|| FieldError::new("type", self.r#type, "DEACTIVATE (0) or ACTIVATE (1)"))
    }
}

crate::constant::constant_message! {
    /// `tier4_rtc_msgs/State`: where a scene is in its lifecycle. Named `Lifecycle` here so
    /// that the one `State` a reader meets is the core's.
    #[serde(deny_unknown_fields)]
    pub struct Lifecycle {
        /// One of the five constants.
        #[serde(rename = "type")]
        pub r#type: u8
    }
    meaning Phase;
    /// Registered, not yet executing.
    const WAITING_FOR_EXECUTION = 0 => Phase::Waiting;
    /// Executing.
    const RUNNING = 1 => Phase::Running;
    /// Being abandoned.
    const ABORTING = 2 => Phase::Aborting;
    /// Completed.
    const SUCCEEDED = 3 => Phase::Succeeded;
    /// Cancelled.
    const FAILED = 4 => Phase::Failed;
}

impl Lifecycle {
    /// The phase it names.
    ///
    /// # Errors
    /// A [`FieldError`] on `type` if it is none of the five constants.
    pub fn phase(&self) -> Result<Phase, FieldError> {
        self.meaning().ok_or_else(|| {
            FieldError::new(
                "type",
                self.r#type,
                "WAITING_FOR_EXECUTION (0), RUNNING (1), ABORTING (2), SUCCEEDED (3) or FAILED (4)",
            )
        })
    }
}

crate::constant::constant_message! {
    /// `tier4_rtc_msgs/Module`: which kind of module a status or command is about, in the
    /// current numbering (see [`ModuleType`] for the numbering before April 2023). The one
    /// table of the current numbering: [`ModuleType::value`] and [`ModuleType::from_value`]
    /// read it.
    #[serde(deny_unknown_fields)]
    pub struct Module {
        /// One of the constants.
        #[serde(rename = "type")]
        pub r#type: u8
    }
    meaning ModuleType;
    /// No module.
    const NONE = 0 => ModuleType::None;
    /// Lane change to the left.
    const LANE_CHANGE_LEFT = 1 => ModuleType::LaneChangeLeft;
    /// Lane change to the right.
    const LANE_CHANGE_RIGHT = 2 => ModuleType::LaneChangeRight;
    /// Static obstacle avoidance to the left.
    const AVOIDANCE_LEFT = 3 => ModuleType::AvoidanceLeft;
    /// Static obstacle avoidance to the right.
    const AVOIDANCE_RIGHT = 4 => ModuleType::AvoidanceRight;
    /// Goal planner (formerly pull over).
    const GOAL_PLANNER = 5 => ModuleType::GoalPlanner;
    /// Start planner (formerly pull out).
    const START_PLANNER = 6 => ModuleType::StartPlanner;
    /// Traffic light, and virtual traffic light.
    const TRAFFIC_LIGHT = 7 => ModuleType::TrafficLight;
    /// Intersection.
    const INTERSECTION = 8 => ModuleType::Intersection;
    /// Intersection occlusion (inserted here in April 2023).
    const INTERSECTION_OCCLUSION = 9 => ModuleType::IntersectionOcclusion;
    /// Crosswalk.
    const CROSSWALK = 10 => ModuleType::Crosswalk;
    /// Blind spot.
    const BLIND_SPOT = 11 => ModuleType::BlindSpot;
    /// Detection area.
    const DETECTION_AREA = 12 => ModuleType::DetectionArea;
    /// No stopping area.
    const NO_STOPPING_AREA = 13 => ModuleType::NoStoppingArea;
    /// Occlusion spot.
    const OCCLUSION_SPOT = 14 => ModuleType::OcclusionSpot;
    /// Lane change to the left requested from outside.
    const EXT_REQUEST_LANE_CHANGE_LEFT = 15 => ModuleType::ExtRequestLaneChangeLeft;
    /// Lane change to the right requested from outside.
    const EXT_REQUEST_LANE_CHANGE_RIGHT = 16 => ModuleType::ExtRequestLaneChangeRight;
    /// Avoidance by a lane change to the left.
    const AVOIDANCE_BY_LC_LEFT = 17 => ModuleType::AvoidanceByLcLeft;
    /// Avoidance by a lane change to the right.
    const AVOIDANCE_BY_LC_RIGHT = 18 => ModuleType::AvoidanceByLcRight;
    /// Roundabout: unverified, see [`ModuleType::Roundabout`].
    const ROUNDABOUT = 19 => ModuleType::Roundabout;
}

impl Module {
    /// The module type it names, in the current numbering.
    ///
    /// # Errors
    /// A [`FieldError`] on `type` if no module type has this value.
    pub fn module_type(&self) -> Result<ModuleType, FieldError> {
        self.meaning()
            .ok_or_else(|| FieldError::new("type", self.r#type, "a Module constant (0 to 19)"))
    }
}

/// `tier4_rtc_msgs/CooperateStatus`: one scene as an RTC interface publishes it.
#[derive(Clone, Copy, PartialEq, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CooperateStatus {
    /// When the scene's owner last reported it.
    pub stamp: Time,
    /// The scene.
    pub uuid: Uuid,
    /// The module type of the interface that publishes it.
    pub module: Module,
    /// The module's own judgment: the module decision is activate.
    pub safe: bool,
    /// The owner asks the operator explicitly. Absent in older messages: `false`.
    #[serde(default)]
    pub requested: bool,
    /// The operator's command, `DEACTIVATE` until one arrives.
    pub command_status: Command,
    /// The lifecycle state.
    pub state: Lifecycle,
    /// Whether the scene proceeds without an operator's approval.
    pub auto_mode: bool,
    /// Distance to the start of the section the scene changes, in metres.
    pub start_distance: f32,
    /// Distance to its end, in metres.
    pub finish_distance: f32,
}

/// A [`CooperateStatus`] with every constant parsed.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct ParsedStatus {
    /// When the owner last reported the scene.
    pub stamp: Time,
    /// The scene.
    pub id: SceneId,
    /// The module type.
    pub module: ModuleType,
    /// The module decision (`safe`).
    pub module_decision: Decision,
    /// `requested`.
    pub requested: bool,
    /// The command status.
    pub command: Decision,
    /// The phase (`state`).
    pub phase: Phase,
    /// `auto_mode`.
    pub auto_mode: bool,
    /// `start_distance`.
    pub start_distance: f32,
    /// `finish_distance`.
    pub finish_distance: f32,
}

impl CooperateStatus {
    /// Parses every constant.
    ///
    /// # Errors
    /// A [`FieldError`] naming the first field with an undefined constant: `module.type`,
    /// `command_status.type` or `state.type`.
    pub fn parse(&self) -> Result<ParsedStatus, FieldError> {
        Ok(ParsedStatus {
            stamp: self.stamp,
            id: self.uuid.into(),
            module: self.module.module_type().map_err(|e| e.within("module"))?,
            module_decision: if self.safe {
                Decision::Activate
            } else {
                Decision::Deactivate
            },
            requested: self.requested,
            command: self
                .command_status
                .decision()
                .map_err(|e| e.within("command_status"))?,
            phase: self.state.phase().map_err(|e| e.within("state"))?,
            auto_mode: self.auto_mode,
            start_distance: self.start_distance,
            finish_distance: self.finish_distance,
        })
    }
}

/// `tier4_rtc_msgs/CooperateStatusArray`.
#[derive(Clone, PartialEq, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CooperateStatusArray {
    /// When the array was published.
    pub stamp: Time,
    /// The statuses.
    pub statuses: Vec<CooperateStatus>,
}

impl CooperateStatusArray {
    /// Parses every status.
    ///
    /// # Errors
    /// The first [`FieldError`], its field prefixed by `statuses[i]`.
    pub fn parse(&self) -> Result<Vec<ParsedStatus>, FieldError> {
        self.statuses
            .iter()
            .enumerate()
            .map(|(index, status)| {
                status
                    .parse()
                    .map_err(|e| e.at_index(index).within("statuses"))
            })
            .collect()
    }
}

/// `tier4_rtc_msgs/CooperateCommand`: an operator's command for one scene.
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Debug,
    Default,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct CooperateCommand {
    /// The scene.
    pub uuid: Uuid,
    /// The module type the sender believes the scene has. Checked to be a defined constant;
    /// scenes are matched by `uuid` alone.
    pub module: Module,
    /// The command.
    pub command: Command,
}

impl CooperateCommand {
    /// The core command: this scene, the operator decision activate or deactivate.
    ///
    /// # Errors
    /// A [`FieldError`] on `module.type` or `command.type` if it is not a defined constant.
    pub fn parse(&self) -> Result<cooperation::Command, FieldError> {
        self.module.module_type().map_err(|e| e.within("module"))?;
        let decision = self.command.decision().map_err(|e| e.within("command"))?;
        Ok(cooperation::Command {
            id: self.uuid.into(),
            decision: match decision {
                Decision::Deactivate => cooperation::OperatorDecision::Deactivate,
                Decision::Activate => cooperation::OperatorDecision::Activate,
            },
        })
    }
}

/// `tier4_rtc_msgs/CooperateResponse`: the answer for one command.
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Debug,
    Default,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct CooperateResponse {
    /// The command's scene.
    pub uuid: Uuid,
    /// The command's module, as sent.
    pub module: Module,
    /// Whether the command was applied.
    pub success: bool,
}

/// `tier4_rtc_msgs/AutoModeStatus`: whether an interface's scenes proceed without approval.
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Debug,
    Default,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct AutoModeStatus {
    /// The interface's module type.
    pub module: Module,
    /// Whether auto mode is on.
    pub is_auto_mode: bool,
}

/// `tier4_rtc_msgs/AutoModeStatusArray`.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AutoModeStatusArray {
    /// When the array was published.
    pub stamp: Time,
    /// One status per interface.
    pub statuses: Vec<AutoModeStatus>,
}

/// The request of `tier4_rtc_msgs/srv/CooperateCommands`.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CooperateCommandsRequest {
    /// When it was sent (not read, as upstream).
    pub stamp: Time,
    /// The commands, in order.
    pub commands: Vec<CooperateCommand>,
}

impl CooperateCommandsRequest {
    /// The core commands, in order.
    ///
    /// # Errors
    /// The first [`FieldError`], its field prefixed by `commands[i]`.
    pub fn parse(&self) -> Result<Vec<cooperation::Command>, FieldError> {
        self.commands
            .iter()
            .enumerate()
            .map(|(index, command)| {
                command
                    .parse()
                    .map_err(|e| e.at_index(index).within("commands"))
            })
            .collect()
    }
}

/// The response of `tier4_rtc_msgs/srv/CooperateCommands`.
#[derive(Clone, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CooperateCommandsResponse {
    /// One response per command, in request order.
    pub responses: Vec<CooperateResponse>,
}

impl CooperateCommandsResponse {
    /// The response to `request` when its batch applied (`success`) or did not: every entry
    /// says the same (`[COOP-DEV-BATCH.1]`), naming its command's scene and module as sent.
    #[must_use]
    pub fn answering(request: &CooperateCommandsRequest, success: bool) -> Self {
        Self {
            responses: request
                .commands
                .iter()
                .map(|command| CooperateResponse {
                    uuid: command.uuid,
                    module: command.module,
                    success,
                })
                .collect(),
        }
    }
}

/// The request of `tier4_rtc_msgs/srv/AutoMode`.
#[derive(
    Clone, Copy, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct AutoModeRequest {
    /// Turn auto mode on or off.
    pub enable: bool,
}

/// The response of `tier4_rtc_msgs/srv/AutoMode`.
#[derive(
    Clone, Copy, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct AutoModeResponse {
    /// Whether it was done.
    pub success: bool,
}

/// The request of `tier4_rtc_msgs/srv/AutoModeWithModule`.
#[derive(
    Clone, Copy, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct AutoModeWithModuleRequest {
    /// The module type whose interfaces to switch.
    pub module: Module,
    /// Turn auto mode on or off.
    pub enable: bool,
}

/// The response of `tier4_rtc_msgs/srv/AutoModeWithModule`.
#[derive(
    Clone, Copy, PartialEq, Eq, Hash, Debug, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct AutoModeWithModuleResponse {
    /// Whether it was done.
    pub success: bool,
}
