//! The messages, field for field and constant for constant, with the ROS shapes they contain.
//!
//! Every message is a plain container: any number fits a constant field, any string fits a
//! behaviour (a UUID is the one exception: it is 16 bytes, or it does not read). Meaning is
//! checked when a message is converted into the
//! core's types (`super::convert`), so that a bad value is reported with the field it sits in.
//!
//! Serde reads a message as rosbridge does: a missing field takes its default (zero, empty,
//! the identity orientation), and a field the message does not have is an error.

use serde::{Deserialize, Serialize};

use cooperation::OperatorDecision;

// -------------------------------------------------------------------------------------------
// ROS shapes
// -------------------------------------------------------------------------------------------

use crate::Time;

/// A message header (`std_msgs/Header`): when, and in which coordinate frame.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Header {
    /// When the data was produced.
    pub stamp: Time,
    /// The coordinate frame the message's poses are in.
    pub frame_id: String,
}

/// A position (`geometry_msgs/Point`), in metres.
#[derive(Clone, Copy, PartialEq, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Point {
    /// `x`.
    pub x: f64,
    /// `y`.
    pub y: f64,
    /// `z`.
    pub z: f64,
}

/// An orientation (`geometry_msgs/Quaternion`). As in ROS, the default is the identity
/// (`w = 1`).
#[derive(Clone, Copy, PartialEq, Debug, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Quaternion {
    /// `x`.
    pub x: f64,
    /// `y`.
    pub y: f64,
    /// `z`.
    pub z: f64,
    /// `w`.
    pub w: f64,
}

impl Default for Quaternion {
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// A pose (`geometry_msgs/Pose`): a position and an orientation.
#[derive(Clone, Copy, PartialEq, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Pose {
    /// Where.
    pub position: Point,
    /// Which way it faces.
    pub orientation: Quaternion,
}

pub use crate::Uuid;

// -------------------------------------------------------------------------------------------
// Cooperation
// -------------------------------------------------------------------------------------------

crate::constant::constant_message! {
    /// A decision (`autoware_adapi_v1_msgs/CooperationDecision`): one of the constants below.
    #[serde(default, deny_unknown_fields)]
    pub struct CooperationDecision {
        /// One of the constants.
        pub decision: u8
    }
    meaning OperatorDecision;
    /// Not set. Never a valid decision.
    const UNKNOWN = 0;
    /// Priority on safety.
    const DEACTIVATE = 1 => OperatorDecision::Deactivate;
    /// Priority on driving.
    const ACTIVATE = 2 => OperatorDecision::Activate;
    /// Follow the module decision (operator decisions only).
    const AUTONOMOUS = 3 => OperatorDecision::Autonomous;
    /// No operator decision: the policy applies (operator decisions only; the spec's "none").
    const UNDECIDED = 4 => OperatorDecision::Undecided;
}

/// A scene's cooperation status (`autoware_adapi_v1_msgs/CooperationStatus`).
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CooperationStatus {
    /// The scene's identifier.
    pub uuid: Uuid,
    /// The module decision: `DEACTIVATE` or `ACTIVATE`.
    pub autonomous: CooperationDecision,
    /// The operator decision: `DEACTIVATE`, `ACTIVATE`, `AUTONOMOUS` or `UNDECIDED`.
    pub cooperator: CooperationDecision,
    /// Whether a command for the scene would be accepted now.
    pub cancellable: bool,
}

/// An operator command (`autoware_adapi_v1_msgs/CooperationCommand`).
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CooperationCommand {
    /// The scene.
    pub uuid: Uuid,
    /// The operator decision: `DEACTIVATE`, `ACTIVATE`, `AUTONOMOUS` or `UNDECIDED`.
    pub cooperator: CooperationDecision,
}

/// A module's cooperation policy (`autoware_adapi_v1_msgs/CooperationPolicy`).
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CooperationPolicy {
    /// The module's behaviour: a [`PlanningBehavior`] string.
    pub behavior: String,
    /// The module's sequence: a [`PlanningSequence`] string, or empty.
    pub sequence: String,
    /// `OPTIONAL` or `REQUIRED`.
    pub policy: u8,
}

impl CooperationPolicy {
    /// The module's decision is followed without an operator decision.
    pub const OPTIONAL: u8 = 1;
    /// Driving on needs an operator decision.
    pub const REQUIRED: u8 = 2;
}

/// The behaviour strings (`autoware_adapi_v1_msgs/PlanningBehavior`). On the wire a behaviour
/// is a plain string field; this type only names the values.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct PlanningBehavior;

impl PlanningBehavior {
    /// Not set. Never a module's behaviour.
    pub const UNKNOWN: &'static str = "";
    /// Avoidance.
    pub const AVOIDANCE: &'static str = "avoidance";
    /// Crosswalk.
    pub const CROSSWALK: &'static str = "crosswalk";
    /// Goal planner.
    pub const GOAL_PLANNER: &'static str = "goal-planner";
    /// Intersection.
    pub const INTERSECTION: &'static str = "intersection";
    /// Lane change.
    pub const LANE_CHANGE: &'static str = "lane-change";
    /// Merge.
    pub const MERGE: &'static str = "merge";
    /// No drivable lane.
    pub const NO_DRIVABLE_LANE: &'static str = "no-drivable-lane";
    /// No stopping area.
    pub const NO_STOPPING_AREA: &'static str = "no-stopping-area";
    /// Rear check.
    pub const REAR_CHECK: &'static str = "rear-check";
    /// Route obstacle.
    pub const ROUTE_OBSTACLE: &'static str = "route-obstacle";
    /// Sidewalk.
    pub const SIDEWALK: &'static str = "sidewalk";
    /// Start planner.
    pub const START_PLANNER: &'static str = "start-planner";
    /// Stop sign.
    pub const STOP_SIGN: &'static str = "stop-sign";
    /// Surrounding obstacle.
    pub const SURROUNDING_OBSTACLE: &'static str = "surrounding-obstacle";
    /// Traffic signal.
    pub const TRAFFIC_SIGNAL: &'static str = "traffic-signal";
    /// A user-defined area; the constant's name says "detection", its value "attention".
    pub const USER_DEFINED_DETECTION_AREA: &'static str = "user-defined-attention-area";
    /// Virtual traffic light.
    pub const VIRTUAL_TRAFFIC_LIGHT: &'static str = "virtual-traffic-light";
    /// Run out.
    pub const RUN_OUT: &'static str = "run-out";
    /// Adaptive cruise.
    pub const ADAPTIVE_CRUISE: &'static str = "adaptive-cruise";
    /// Roundabout.
    pub const ROUNDABOUT: &'static str = "roundabout";
}

/// The sequence strings (`autoware_adapi_v1_msgs/PlanningSequence`). On the wire a sequence is
/// a plain string field; the empty string means the behaviour has no sequences.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct PlanningSequence;

impl PlanningSequence {
    /// Moving away from the current path.
    pub const CHANGE: &'static str = "change";
    /// Coming back to it.
    pub const RETURN: &'static str = "return";
}

// -------------------------------------------------------------------------------------------
// Factors
// -------------------------------------------------------------------------------------------

/// A place where the vehicle may stop or slow down (`autoware_adapi_v1_msgs/VelocityFactor`).
#[derive(Clone, PartialEq, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VelocityFactor {
    /// Where, in the array header's frame.
    pub pose: Pose,
    /// How far ahead, in metres.
    pub distance: f32,
    /// `UNKNOWN`, `APPROACHING` or `STOPPED`.
    pub status: u16,
    /// The module's behaviour: a [`PlanningBehavior`] string.
    pub behavior: String,
    /// The module's sequence: a [`PlanningSequence`] string, or empty.
    pub sequence: String,
    /// Free text.
    pub detail: String,
    /// The scene's cooperation status, if the module cooperates: at most one entry.
    pub cooperation: Vec<CooperationStatus>,
}

impl VelocityFactor {
    /// Status not known.
    pub const UNKNOWN: u16 = 0;
    /// Status: the vehicle is approaching the factor.
    pub const APPROACHING: u16 = 1;
    /// Status: the vehicle has stopped because of the factor.
    pub const STOPPED: u16 = 2;
}

/// Velocity factors with their header (`autoware_adapi_v1_msgs/VelocityFactorArray`).
#[derive(Clone, PartialEq, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VelocityFactorArray {
    /// When, and the frame of the poses.
    pub header: Header,
    /// The factors.
    pub factors: Vec<VelocityFactor>,
}

/// A section where the vehicle may steer (`autoware_adapi_v1_msgs/SteeringFactor`).
#[derive(Clone, PartialEq, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SteeringFactor {
    /// Start and end of the section, in the array header's frame.
    pub pose: [Pose; 2],
    /// Distances to the start and to the end, in metres.
    pub distance: [f32; 2],
    /// `UNKNOWN`, `LEFT`, `RIGHT` or `STRAIGHT`.
    pub direction: u16,
    /// `UNKNOWN`, `APPROACHING` or `TURNING`.
    pub status: u16,
    /// The module's behaviour: a [`PlanningBehavior`] string.
    pub behavior: String,
    /// The module's sequence: a [`PlanningSequence`] string, or empty.
    pub sequence: String,
    /// Free text.
    pub detail: String,
    /// The scene's cooperation status, if the module cooperates: at most one entry.
    pub cooperation: Vec<CooperationStatus>,
}

impl SteeringFactor {
    /// Direction or status not known.
    pub const UNKNOWN: u16 = 0;
    /// Direction: left.
    pub const LEFT: u16 = 1;
    /// Direction: right.
    pub const RIGHT: u16 = 2;
    /// Direction: straight on.
    pub const STRAIGHT: u16 = 3;
    /// Status: the vehicle is approaching the section.
    pub const APPROACHING: u16 = 1;
    /// Status: the vehicle is in the section. (Status 2 was once defined and is no more.)
    pub const TURNING: u16 = 3;
}

/// Steering factors with their header (`autoware_adapi_v1_msgs/SteeringFactorArray`).
#[derive(Clone, PartialEq, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SteeringFactorArray {
    /// When, and the frame of the poses.
    pub header: Header,
    /// The factors.
    pub factors: Vec<SteeringFactor>,
}

// -------------------------------------------------------------------------------------------
// Responses and services
// -------------------------------------------------------------------------------------------

pub use super::status::ResponseStatus;

/// The request of `set_commands` (`autoware_adapi_v1_msgs/srv/SetCooperationCommands`).
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SetCooperationCommandsRequest {
    /// The commands, applied all or none.
    pub commands: Vec<CooperationCommand>,
}

/// The response of `set_commands`.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SetCooperationCommandsResponse {
    /// The outcome.
    pub status: ResponseStatus,
}

/// The request of `set_policies` (`autoware_adapi_v1_msgs/srv/SetCooperationPolicies`).
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SetCooperationPoliciesRequest {
    /// The policies, set all or none.
    pub policies: Vec<CooperationPolicy>,
}

/// The response of `set_policies`.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SetCooperationPoliciesResponse {
    /// The outcome.
    pub status: ResponseStatus,
}

/// The request of `get_policies` (`autoware_adapi_v1_msgs/srv/GetCooperationPolicies`): no
/// fields, `{}` on the wire.
#[derive(
    Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct GetCooperationPoliciesRequest {}

/// The response of `get_policies`.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GetCooperationPoliciesResponse {
    /// The outcome.
    pub status: ResponseStatus,
    /// Every configured module's current policy.
    pub policies: Vec<CooperationPolicy>,
}
