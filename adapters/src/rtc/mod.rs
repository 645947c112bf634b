//! Compatibility with TIER IV's RTC (`tier4_rtc_msgs` and `rtc_interface`): the messages, and
//! the `RTCInterface` calls answered from the core.
//!
//! Autoware's planning modules talk to cooperation through `rtc_interface`: one interface per
//! module name (`lane_change_left`, `intersection`, …), a status per scene with a `safe` flag, a
//! lifecycle state and distances, operator commands `ACTIVATE`/`DEACTIVATE`, and an auto-mode
//! switch. This module keeps those calls and messages and maps them onto the core:
//!
//! | RTC | Core |
//! |---|---|
//! | interface name | a [`Binding`]: a behaviour, the sequences its scenes may have (each a core [`Module`](cooperation::Module)), and the factor [`Kind`] |
//! | `updateCooperateStatus` for a new UUID | `Register` in the interface's module, or in the one its sequence names ([`StatusReport::sequence`]), then `Update` if the state is not waiting, all or none |
//! | `updateCooperateStatus` | `Update`: `safe` ↦ module decision, `state` ↦ phase, distances ↦ geometry, `requested` |
//! | `removeCooperateStatus`, `clearCooperateStatus` | `Remove` |
//! | `removeExpiredCooperateStatus` | `Tick` ([`Rtc::tick`]) |
//! | `CooperateCommands` | `SetCommands` |
//! | `AutoMode`, `AutoModeWithModule` | `SetPolicies`: enable ↦ optional, disable ↦ required |
//! | `isActivated` | the merged decision |
//! | `isForceActivated`, `isForceDeactivated` | the force flags |
//! | `CooperateStatus.auto_mode` | operator decision autonomous, or none under an optional policy |
//!
//! The adapter keeps no decision of its own: every answer is a core query, every change a core
//! input, and every refusal a typed [`RtcError`]. Where upstream's answer is a quirk, the answer
//! here is the one the specification's deviations (`spec/cooperation.md` §9) give;
//! `docs/rtc.md` explains the migration call for call.
//!
//! # Names
//!
//! The messages keep their ROS names, so two share a name with a core type and mean something
//! else: [`rtc::Module`](Module) is an RTC module-type number, not a core
//! [`Module`](cooperation::Module); [`rtc::Command`](Command) is a command-type number, not a
//! core [`Command`](cooperation::Command). Each name reads as the message definition it stands
//! for; name them through the module (`rtc::Module`, as the example does) rather than importing
//! `rtc::*` beside `cooperation::*`. The one exception is `tier4_rtc_msgs/State`, the lifecycle
//! constant, which is [`Lifecycle`] here: a reader meets one `State`, the core's.
//!
//! # Example
//!
//! ```
//! use cooperation::{Config, OperatorDecision, Phase, SceneId, State};
//! use cooperation_adapters::rtc::{self, CooperateCommand, CooperateCommandsRequest, Rtc, StatusReport};
//! use cooperation_adapters::Time;
//!
//! let mut rtc = Rtc::standard();
//! // Upstream's `enable_rtc = false`: auto mode on, so every bound module's policy is optional.
//! let mut state = State::new(Config::new(rtc.policies(false)))?;
//! let id = SceneId::from_u128(0x42);
//!
//! {
//!     // The lane change module reports its scene every cycle; it is not safe yet.
//!     let mut lane_change = rtc.interface(&mut state, "lane_change_left")?;
//!     lane_change.update_cooperate_status(&StatusReport::new(id, false, Phase::Waiting, 20.0, 60.0))?;
//!     assert!(lane_change.view().is_registered(id));
//!     assert!(!lane_change.view().is_activated(id)); // auto mode: follows `safe`
//!
//!     // The operator approves through the interface's CooperateCommands service.
//!     let request = CooperateCommandsRequest {
//!         stamp: Time::default(),
//!         commands: vec![CooperateCommand {
//!             uuid: id.into(),
//!             module: rtc::Module::new(rtc::Module::LANE_CHANGE_LEFT),
//!             command: rtc::Command::new(rtc::Command::ACTIVATE),
//!         }],
//!     };
//!     let reply = lane_change.cooperate_commands(&request);
//!     assert!(reply.response.responses[0].success);
//!     assert!(lane_change.view().is_activated(id) && lane_change.view().is_force_activated(id));
//!
//!     // What upstream publishes on /planning/cooperate_status/lane_change_left.
//!     let array = lane_change.view().cooperate_status_array(Time::new(100, 0));
//!     assert_eq!(array.statuses[0].command_status.r#type, rtc::Command::ACTIVATE);
//!     assert!(!array.statuses[0].auto_mode);
//!
//!     // A status message with an undefined state is refused where it is read, naming the field.
//!     let mut status = array.statuses[0];
//!     status.state = rtc::Lifecycle::new(7);
//!     assert_eq!(status.report().unwrap_err().to_string(), "state.type is 7, which is not WAITING_FOR_EXECUTION (0), RUNNING (1), ABORTING (2), SUCCEEDED (3) or FAILED (4)");
//! }
//!
//! // The AD API sees the same scene as a steering factor.
//! let mut factors = Vec::new();
//! state.steering_factors_into(&mut factors);
//! assert_eq!(factors[0].cooperation.map(|c| c.operator_decision), Some(OperatorDecision::Activate));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod adapter;
mod binding;
mod error;
mod module_type;
mod msg;
mod report;

pub use adapter::{
    policy_for_auto_mode, Answers, Interface, InterfaceId, Reply, Rtc, View, SCENE_QUOTA,
};
pub use binding::{Binding, Kind};
pub use error::{FieldError, RtcError};
pub use module_type::ModuleType;
pub use msg::{
    AutoModeRequest, AutoModeResponse, AutoModeStatus, AutoModeStatusArray,
    AutoModeWithModuleRequest, AutoModeWithModuleResponse, Command, CooperateCommand,
    CooperateCommandsRequest, CooperateCommandsResponse, CooperateResponse, CooperateStatus,
    CooperateStatusArray, Lifecycle, Module, ParsedStatus, Uuid,
};
pub use report::{StatusReport, Transitions};
