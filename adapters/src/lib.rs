//! The cooperation core's ROS face: everything between [`cooperation::State`] and a ROS system,
//! and nothing that decides.
//!
//! The core (`cooperation`) is the state machine: inputs, rules, queries, typed rejections.
//! This crate, the ring around it, speaks ROS:
//!
//! - [`wire`]: the AD API's `autoware_adapi_v1_msgs` cooperation messages, services and
//!   streams, with its `ResponseStatus` codes, in the JSON shapes rosbridge uses. A service call
//!   is read ([`wire::Service::read`]), answered ([`wire::Request::answer`]) with a typed
//!   response and whether the state changed, and written once by whoever sends it.
//! - [`rtc`]: TIER IV's `tier4_rtc_msgs` messages and `rtc_interface` calls, answered from the
//!   core; `docs/rtc.md` is the migration guide.
//! - [`settings`]: the default policies and limits, from a ROS 2 parameter file.
//! - [`cdr`]: the same messages in CDR, as ROS 2 sends them over DDS; [`dds`]: the services
//!   as DDS carries them, from request bytes to reply bytes (`cooperation-dds`).
//! - [`sync`]: the planning modules' service of both nodes; [`clock`]: the nodes' one clock.
//! - [`engine`]: the service engine every host drives: each door's request answered time
//!   first, what the streams publish decided once, the core built once with the same defaults.
//! - [`refusals`]: the log of what a node refuses from its peers, one line and one summary a
//!   period.
//! - [`Host`] and [`Shared`]: the core with the RTC interfaces' routing and the time it was last
//!   told, as one value, and the engine over it behind one lock, for a process serving the core
//!   to several callers (`cooperation-server`, `cooperation-dds`, a C++ planner).
//!
//! Every change still goes through [`cooperation::State::apply`] (or
//! [`apply_all`](cooperation::State::apply_all), inputs applied all or none), the function the
//! model checker explores; no rule of the specification is restated here. Where a message can
//! say something the core has no word for (an undefined constant, a UUID of the wrong length),
//! the conversion refuses it with an error naming the field.
//!
//! # Example
//!
//! An operator's `set_commands` call as rosbridge carries it, read, answered and written:
//!
//! ```
//! use cooperation::*;
//! use cooperation_adapters::wire::{self, Service};
//!
//! let lane_change = Module::new(Behavior::LaneChange);
//! let mut state = State::new(Config::new([(lane_change, Policy::Required)]))?;
//! let id = SceneId::from_u128(0x0001_0203_0405_0607_0809_0a0b_0c0d_0e0f);
//! let report = Report::new(Decision::Activate, Geometry::steering(Direction::Left, 20.0, 60.0));
//! state.apply(&Input::Register { id, module: lane_change, report })?;
//!
//! let request = Service::SetCommands.read(
//!     br#"{"commands": [{"uuid": {"uuid": "AAECAwQFBgcICQoLDA0ODw=="}, "cooperator": {"decision": 2}}]}"#,
//! )?;
//! let answer = request.answer(&mut state);
//! assert!(answer.changed);
//! assert_eq!(wire::to_json(&answer.response), br#"{"status":{"success":true,"code":0,"message":""}}"#);
//! assert_eq!(state.merged_decision(id), Some(Decision::Activate));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

mod base64;
pub mod cdr;
pub mod clock;
mod constant;
pub mod dds;
pub mod engine;
mod host;
mod path;
pub mod refusals;
pub mod relay;
pub mod rtc;
#[doc = include_str!("../docs/settings.md")]
pub mod settings;
pub mod sync;
mod time;
mod uuid;
pub mod wire;

pub use host::{Host, Shared};
pub use path::{FieldPath, PathSegment};
pub use time::Time;
pub use uuid::Uuid;

pub mod guide {
    //! Guides for this crate's users, with examples that compile and run as doctests.

    #[doc = include_str!("../docs/relay.md")]
    pub mod relay {}

    #[doc = include_str!("../docs/rtc.md")]
    pub mod rtc {}

    #[doc = include_str!("../docs/wire.md")]
    pub mod wire {}
}
