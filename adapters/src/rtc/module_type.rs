//! `tier4_rtc_msgs/Module`'s values: the current numbering, and the one before April 2023.

use core::fmt;

/// A module type as `tier4_rtc_msgs/Module.type` names it.
///
/// [`value`](Self::value) is the current numbering. In April 2023 `INTERSECTION_OCCLUSION`,
/// first appended as 18, was inserted at 9, moving `CROSSWALK` … `AVOIDANCE_BY_LC_RIGHT` up by
/// one; [`legacy_value`](Self::legacy_value) and [`from_legacy_value`](Self::from_legacy_value)
/// convert the numbering before that. `ROUNDABOUT` is newer still and its value, 19, is
/// unverified ([`is_verified`](Self::is_verified)).
#[derive(
    Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, serde::Serialize, serde::Deserialize,
)]
pub enum ModuleType {
    /// `NONE` (0): no module; what upstream reports for an interface name it does not know.
    None,
    /// `LANE_CHANGE_LEFT` (1).
    LaneChangeLeft,
    /// `LANE_CHANGE_RIGHT` (2).
    LaneChangeRight,
    /// `AVOIDANCE_LEFT` (3): static obstacle avoidance to the left.
    AvoidanceLeft,
    /// `AVOIDANCE_RIGHT` (4).
    AvoidanceRight,
    /// `GOAL_PLANNER` (5), formerly `PULL_OVER`.
    GoalPlanner,
    /// `START_PLANNER` (6), formerly `PULL_OUT`.
    StartPlanner,
    /// `TRAFFIC_LIGHT` (7): the traffic light and the virtual traffic light both report it.
    TrafficLight,
    /// `INTERSECTION` (8).
    Intersection,
    /// `INTERSECTION_OCCLUSION` (9 since April 2023; 18 before).
    IntersectionOcclusion,
    /// `CROSSWALK` (10; 9 before April 2023).
    Crosswalk,
    /// `BLIND_SPOT` (11; 10 before).
    BlindSpot,
    /// `DETECTION_AREA` (12; 11 before).
    DetectionArea,
    /// `NO_STOPPING_AREA` (13; 12 before).
    NoStoppingArea,
    /// `OCCLUSION_SPOT` (14; 13 before).
    OcclusionSpot,
    /// `EXT_REQUEST_LANE_CHANGE_LEFT` (15; 14 before).
    ExtRequestLaneChangeLeft,
    /// `EXT_REQUEST_LANE_CHANGE_RIGHT` (16; 15 before).
    ExtRequestLaneChangeRight,
    /// `AVOIDANCE_BY_LC_LEFT` (17; 16 before).
    AvoidanceByLcLeft,
    /// `AVOIDANCE_BY_LC_RIGHT` (18; 17 before).
    AvoidanceByLcRight,
    /// `ROUNDABOUT` (19, unverified): the next free value when it was added in 2025.
    Roundabout,
}

impl ModuleType {
    /// Every module type, in the order of their current values.
    pub const ALL: [Self; 20] = [
        Self::None,
        Self::LaneChangeLeft,
        Self::LaneChangeRight,
        Self::AvoidanceLeft,
        Self::AvoidanceRight,
        Self::GoalPlanner,
        Self::StartPlanner,
        Self::TrafficLight,
        Self::Intersection,
        Self::IntersectionOcclusion,
        Self::Crosswalk,
        Self::BlindSpot,
        Self::DetectionArea,
        Self::NoStoppingArea,
        Self::OcclusionSpot,
        Self::ExtRequestLaneChangeLeft,
        Self::ExtRequestLaneChangeRight,
        Self::AvoidanceByLcLeft,
        Self::AvoidanceByLcRight,
        Self::Roundabout,
    ];

    /// The current value of `Module.type`.
    #[must_use]
    pub const fn value(self) -> u8 {
        super::Module::of(self).r#type
    }

    /// The module type with this current value, if any.
    #[must_use]
    pub const fn from_value(value: u8) -> Option<Self> {
        super::Module::new(value).meaning()
    }

    /// The value in the numbering before April 2023, when `INTERSECTION_OCCLUSION` had been
    /// appended as 18 and not yet moved to 9. `None` for `ROUNDABOUT`, which did not exist.
    #[must_use]
    pub const fn legacy_value(self) -> Option<u8> {
        match self {
            Self::IntersectionOcclusion => Some(18),
            Self::Roundabout => None,
            other => {
                let value = other.value();
                Some(if value > 9 { value - 1 } else { value })
            }
        }
    }

    /// The module type with this value in the numbering before April 2023, if any.
    #[must_use]
    pub const fn from_legacy_value(value: u8) -> Option<Self> {
        match value {
            0..=8 => Self::from_value(value),
            9..=17 => Self::from_value(value + 1),
            18 => Some(Self::IntersectionOcclusion),
            _ => None,
        }
    }

    /// Whether the value is confirmed from the message definition (all but `ROUNDABOUT`).
    #[must_use]
    pub const fn is_verified(self) -> bool {
        !matches!(self, Self::Roundabout)
    }

    /// The message's constant name, for example `LANE_CHANGE_LEFT`.
    #[must_use]
    pub const fn constant(self) -> &'static str {
        match self {
            Self::None => "NONE",
            Self::LaneChangeLeft => "LANE_CHANGE_LEFT",
            Self::LaneChangeRight => "LANE_CHANGE_RIGHT",
            Self::AvoidanceLeft => "AVOIDANCE_LEFT",
            Self::AvoidanceRight => "AVOIDANCE_RIGHT",
            Self::GoalPlanner => "GOAL_PLANNER",
            Self::StartPlanner => "START_PLANNER",
            Self::TrafficLight => "TRAFFIC_LIGHT",
            Self::Intersection => "INTERSECTION",
            Self::IntersectionOcclusion => "INTERSECTION_OCCLUSION",
            Self::Crosswalk => "CROSSWALK",
            Self::BlindSpot => "BLIND_SPOT",
            Self::DetectionArea => "DETECTION_AREA",
            Self::NoStoppingArea => "NO_STOPPING_AREA",
            Self::OcclusionSpot => "OCCLUSION_SPOT",
            Self::ExtRequestLaneChangeLeft => "EXT_REQUEST_LANE_CHANGE_LEFT",
            Self::ExtRequestLaneChangeRight => "EXT_REQUEST_LANE_CHANGE_RIGHT",
            Self::AvoidanceByLcLeft => "AVOIDANCE_BY_LC_LEFT",
            Self::AvoidanceByLcRight => "AVOIDANCE_BY_LC_RIGHT",
            Self::Roundabout => "ROUNDABOUT",
        }
    }
}

impl fmt::Display for ModuleType {
    /// The constant name and the current value, for example `LANE_CHANGE_LEFT (1)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.constant(), self.value())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn current_values_are_the_positions_and_round_trip() {
        for (at, module) in ModuleType::ALL.into_iter().enumerate() {
            assert_eq!(usize::from(module.value()), at);
            assert_eq!(ModuleType::from_value(module.value()), Some(module));
        }
        assert_eq!(ModuleType::from_value(20), None);
        assert_eq!(ModuleType::from_value(255), None);
    }

    #[test]
    fn the_2023_insertion_moves_crosswalk_to_avoidance_by_lc_up_by_one() {
        let legacy: Vec<(u8, &str)> = (0..=18)
            .map(|value| {
                let module = ModuleType::from_legacy_value(value).expect("defined");
                assert_eq!(module.legacy_value(), Some(value));
                (value, module.constant())
            })
            .collect();
        assert_eq!(legacy[9], (9, "CROSSWALK"));
        assert_eq!(legacy[17], (17, "AVOIDANCE_BY_LC_RIGHT"));
        assert_eq!(legacy[18], (18, "INTERSECTION_OCCLUSION"));
        assert_eq!(ModuleType::from_legacy_value(19), None);
        assert_eq!(ModuleType::Roundabout.legacy_value(), None);
        assert!(!ModuleType::Roundabout.is_verified());
        assert!(ModuleType::ALL.iter().filter(|m| !m.is_verified()).count() == 1);
    }
}
