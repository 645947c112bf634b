//! `cooperation-dds`: the cooperation AD API as a ROS 2 node over DDS.
//!
//! The node serves `/api/planning/cooperation/{set_commands,set_policies,get_policies}` and the
//! planning modules' `/cooperation/rtc/sync`, and publishes `/api/planning/velocity_factors` and
//! `steering_factors`, in the DDS names, types, QoS and request header `rmw_cyclonedds_cpp` uses,
//! so that ROS 2 nodes on Cyclone DDS reach it as any other node. It is RTPS in pure Rust
//! (`rustdds`): no ROS 2 installation is needed. Every answer comes from `cooperation_adapters`
//! (`dds`, `wire`, `sync`, `rtc`); this crate only moves bytes. `docs/ros2.md` describes it,
//! and `tools/ros2-interop` tests it against Cyclone DDS. Its stack mode ([`Stack`]) serves the
//! AD API over the planning modules' own RTC endpoints instead, through
//! `cooperation_adapters::relay` (`docs/autoware.md`, tested by `tools/stack-test`).

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

mod entities;
pub mod graph;
mod module;
pub mod node;
pub mod raw;
pub mod stack;

pub use node::{Node, Options};
pub use stack::{Door, DoorCall, Stack};
