//! The AD API on the wire: the `autoware_adapi_v1_msgs` cooperation messages and services, as
//! rosbridge carries them in JSON, over the core.
//!
//! - **Messages** ([`CooperationCommand`], [`CooperationPolicy`], [`VelocityFactorArray`], …)
//!   are field for field the message definitions, with their constants as associated
//!   constants (`CooperationDecision::ACTIVATE`). They hold whatever arrives: any number in a
//!   constant field, any string in a behaviour, a UUID of any length.
//! - **Conversions** into the core's types parse: `Command::try_from(&command)` is a core
//!   command or a [`Malformed`] naming the field, e.g.
//!   `commands[2].cooperator.decision: 7 is not a CooperationDecision constant`. Conversions
//!   out of the core always succeed.
//! - **Services**: [`set_commands`], [`set_policies`] and [`get_policies`] take the request
//!   message and give the response message with whether the state changed ([`Answer`]),
//!   following the AD API's [`ResponseStatus`] conventions (`[COOP-API-STATUS.1]`);
//!   [`velocity_factors`] and [`steering_factors`] are the two streams. From JSON,
//!   [`Service::read`] reads a [`Request`] of at most [`MAX_REQUEST_BYTES`] (no state needed,
//!   so before any lock), [`Request::answer`] answers it, and the caller writes the typed
//!   [`Response`] once, inside whatever frame carries it ([`to_json`] alone).
//!
//! Nothing here decides anything: what a batch may contain, which scenes exist, which modules
//! have policies are the core's rules, applied by [`State::apply`](cooperation::State::apply);
//! a rejection comes back as a `PARAMETER_ERROR` with the core's explanation. A malformed
//! request never reaches the core, so it changes nothing either.
//!
//! `docs/wire.md` shows the JSON shapes, the accepted UUID forms, the errors and the limits.
//!
//! # Names
//!
//! The messages keep their ROS names, so some share a name with a core type and are its wire
//! form: [`wire::Pose`](Pose) is `geometry_msgs/Pose` (points and a quaternion), the core's
//! [`Pose`](cooperation::Pose) holds the same numbers as arrays;
//! [`wire::CooperationStatus`](CooperationStatus) is the message the core's
//! [`CooperationStatus`](cooperation::CooperationStatus) converts to; [`wire::Uuid`](Uuid) (the
//! same type as [`rtc::Uuid`](crate::rtc::Uuid)) is the ROS shape. This is on purpose: each name reads as the message definition it stands for.
//! Name them through the module (`wire::Pose`, as the example does) rather than importing
//! `wire::*` beside `cooperation::*`.
//!
//! # Example
//!
//! An operator interface talking rosbridge JSON to a planner that holds the state:
//!
//! ```
//! use cooperation::*;
//! use cooperation_adapters::{wire::{self, Service}, Time};
//!
//! let lane_change = Module::new(Behavior::LaneChange);
//! let mut state = State::new(Config::new([(lane_change, Policy::Required)]))?;
//! let id = SceneId::from_u128(0x0001_0203_0405_0607_0809_0a0b_0c0d_0e0f);
//! let geometry = Geometry::steering(Direction::Left, 20.0, 60.0);
//! state.apply(&Input::Register { id, module: lane_change, report: Report::new(Decision::Activate, geometry) })?;
//!
//! // The operator activates the scene, naming it by its UUID (here in rosbridge's base64 form).
//! let request = br#"{"commands": [
//!     {"uuid": {"uuid": "AAECAwQFBgcICQoLDA0ODw=="}, "cooperator": {"decision": 2}}
//! ]}"#;
//! let answer = Service::SetCommands.read(request)?.answer(&mut state);
//! assert_eq!(wire::to_json(&answer.response), br#"{"status":{"success":true,"code":0,"message":""}}"#);
//! assert!(answer.changed);
//! assert_eq!(state.merged_decision(id), Some(Decision::Activate));
//!
//! // A decision number the message does not define: refused, naming the field; nothing changes.
//! let before = state.clone();
//! let request = wire::SetCooperationCommandsRequest {
//!     commands: vec![wire::CooperationCommand {
//!         uuid: id.into(),
//!         cooperator: wire::CooperationDecision { decision: 7 },
//!     }],
//! };
//! let answer = wire::set_commands(&mut state, &request);
//! assert!(!answer.response.status.success && !answer.changed);
//! assert_eq!(answer.response.status.code, wire::ResponseStatus::PARAMETER_ERROR);
//! assert_eq!(
//!     answer.response.status.message,
//!     "commands[0].cooperator.decision: 7 is not a CooperationDecision constant"
//! );
//! assert_eq!(state, before);
//!
//! // The steering factors stream, with the scene's cooperation status.
//! let factors = wire::steering_factors(&state, Time { sec: 12, nanosec: 0 });
//! assert_eq!(factors.header.frame_id, "map");
//! let cooperation = &factors.factors[0].cooperation[0];
//! assert_eq!(cooperation.cooperator.decision, wire::CooperationDecision::ACTIVATE);
//! assert_eq!(SceneId::from(cooperation.uuid), id);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod convert;
mod error;
mod msg;
mod service;
mod status;

use crate::FieldPath;
pub use error::Malformed;
pub use msg::{
    CooperationCommand, CooperationDecision, CooperationPolicy, CooperationStatus,
    GetCooperationPoliciesRequest, GetCooperationPoliciesResponse, Header, PlanningBehavior,
    PlanningSequence, Point, Pose, Quaternion, ResponseStatus, SetCooperationCommandsRequest,
    SetCooperationCommandsResponse, SetCooperationPoliciesRequest, SetCooperationPoliciesResponse,
    SteeringFactor, SteeringFactorArray, Uuid, VelocityFactor, VelocityFactorArray,
};
pub use service::{
    check_request_len, from_json, get_policies, set_commands, set_policies, steering_factors,
    steering_factors_with, to_json, velocity_factors, velocity_factors_with, Answer, Request,
    Response, Service, FRAME_ID, MAX_REQUEST_BYTES, STEERING_FACTORS, STEERING_FACTORS_TYPE,
    VELOCITY_FACTORS, VELOCITY_FACTORS_TYPE,
};
