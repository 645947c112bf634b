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

/// The highest DDS domain a ROS 2 node may join: in DDS's mapping of domains to ports, a higher
/// one needs ports past 65535.
pub const MAX_DOMAIN: u16 = 232;

/// The domain `text` names (a `ROS_DOMAIN_ID`), or why it names none.
///
/// ```
/// assert_eq!(cooperation_dds::domain("42"), Ok(42));
/// assert_eq!(cooperation_dds::domain("232"), Ok(232));
/// assert_eq!(
///     cooperation_dds::domain("233"),
///     Err(r#""233" is not a DDS domain: give one from 0 to 232"#.to_owned())
/// );
/// assert!(cooperation_dds::domain("-1").is_err());
/// assert!(cooperation_dds::domain("seven").is_err());
/// ```
///
/// # Errors
/// A text that is not a number from 0 to [`MAX_DOMAIN`], saying so.
pub fn domain(text: &str) -> Result<u16, String> {
    text.trim()
        .parse::<u16>()
        .ok()
        .filter(|domain| *domain <= MAX_DOMAIN)
        .ok_or_else(|| format!("{text:?} is not a DDS domain: give one from 0 to {MAX_DOMAIN}"))
}
