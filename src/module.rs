//! Modules: the planning behaviours a scene belongs to, and their sequences.

use core::fmt;
use core::str::FromStr;

/// A planning behaviour, as the AD API's `PlanningBehavior` string constants name it.
///
/// The AD API's `UNKNOWN` (the empty string) is not a behaviour: parsing it fails.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Behavior {
    /// `"adaptive-cruise"`.
    AdaptiveCruise,
    /// `"avoidance"`.
    Avoidance,
    /// `"crosswalk"`.
    Crosswalk,
    /// `"goal-planner"`.
    GoalPlanner,
    /// `"intersection"`.
    Intersection,
    /// `"lane-change"`.
    LaneChange,
    /// `"merge"`.
    Merge,
    /// `"no-drivable-lane"`.
    NoDrivableLane,
    /// `"no-stopping-area"`.
    NoStoppingArea,
    /// `"rear-check"`.
    RearCheck,
    /// `"roundabout"`.
    Roundabout,
    /// `"route-obstacle"`.
    RouteObstacle,
    /// `"run-out"`.
    RunOut,
    /// `"sidewalk"`.
    Sidewalk,
    /// `"start-planner"`.
    StartPlanner,
    /// `"stop-sign"`.
    StopSign,
    /// `"surrounding-obstacle"`.
    SurroundingObstacle,
    /// `"traffic-signal"`.
    TrafficSignal,
    /// `"user-defined-attention-area"` (the AD API constant is `USER_DEFINED_DETECTION_AREA`).
    UserDefinedAttentionArea,
    /// `"virtual-traffic-light"`.
    VirtualTrafficLight,
}

impl Behavior {
    /// Every behaviour, in the order of their strings.
    pub const ALL: [Self; 20] = [
        Self::AdaptiveCruise,
        Self::Avoidance,
        Self::Crosswalk,
        Self::GoalPlanner,
        Self::Intersection,
        Self::LaneChange,
        Self::Merge,
        Self::NoDrivableLane,
        Self::NoStoppingArea,
        Self::RearCheck,
        Self::Roundabout,
        Self::RouteObstacle,
        Self::RunOut,
        Self::Sidewalk,
        Self::StartPlanner,
        Self::StopSign,
        Self::SurroundingObstacle,
        Self::TrafficSignal,
        Self::UserDefinedAttentionArea,
        Self::VirtualTrafficLight,
    ];

    /// The AD API string.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::AdaptiveCruise => "adaptive-cruise",
            Self::Avoidance => "avoidance",
            Self::Crosswalk => "crosswalk",
            Self::GoalPlanner => "goal-planner",
            Self::Intersection => "intersection",
            Self::LaneChange => "lane-change",
            Self::Merge => "merge",
            Self::NoDrivableLane => "no-drivable-lane",
            Self::NoStoppingArea => "no-stopping-area",
            Self::RearCheck => "rear-check",
            Self::Roundabout => "roundabout",
            Self::RouteObstacle => "route-obstacle",
            Self::RunOut => "run-out",
            Self::Sidewalk => "sidewalk",
            Self::StartPlanner => "start-planner",
            Self::StopSign => "stop-sign",
            Self::SurroundingObstacle => "surrounding-obstacle",
            Self::TrafficSignal => "traffic-signal",
            Self::UserDefinedAttentionArea => "user-defined-attention-area",
            Self::VirtualTrafficLight => "virtual-traffic-light",
        }
    }
}

/// A string that names no [`Behavior`] or no [`Sequence`].
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct UnknownName {
    /// What was being parsed: `"behavior"` or `"sequence"`.
    pub field: &'static str,
    /// The string that was given.
    pub given: String,
}

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown {} {:?}", self.field, self.given)
    }
}

impl std::error::Error for UnknownName {}

impl FromStr for Behavior {
    type Err = UnknownName;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|behavior| behavior.as_str() == text)
            .ok_or_else(|| UnknownName {
                field: "behavior",
                given: text.to_owned(),
            })
    }
}

impl fmt::Display for Behavior {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A planning sequence: which part of a behaviour a module plans (AD API `PlanningSequence`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Sequence {
    /// The empty string: the behaviour is not split into sequences.
    #[default]
    Empty,
    /// `"change"`: moving away from the current path (for example, avoidance's shift out).
    Change,
    /// `"return"`: coming back to it.
    Return,
}

impl Sequence {
    /// Every sequence.
    pub const ALL: [Self; 3] = [Self::Empty, Self::Change, Self::Return];

    /// The AD API string.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Empty => "",
            Self::Change => "change",
            Self::Return => "return",
        }
    }
}

impl FromStr for Sequence {
    type Err = UnknownName;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|sequence| sequence.as_str() == text)
            .ok_or_else(|| UnknownName {
                field: "sequence",
                given: text.to_owned(),
            })
    }
}

/// A module, identified the AD API way: a behaviour plus a sequence.
///
/// Cooperation policies are held per module (spec §3).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Module {
    /// The behaviour.
    pub behavior: Behavior,
    /// The sequence.
    pub sequence: Sequence,
}

impl Module {
    /// A module with the empty sequence.
    #[must_use]
    pub const fn new(behavior: Behavior) -> Self {
        Self {
            behavior,
            sequence: Sequence::Empty,
        }
    }

    /// A module with a sequence.
    #[must_use]
    pub const fn with_sequence(behavior: Behavior, sequence: Sequence) -> Self {
        Self { behavior, sequence }
    }
}

impl Module {
    /// How many modules there are: every behaviour with every sequence.
    pub(crate) const COUNT: usize = Behavior::ALL.len() * Sequence::ALL.len();

    /// The module's place in module order, below [`COUNT`](Self::COUNT): a dense index for
    /// per-module tables.
    pub(crate) const fn index(self) -> usize {
        self.behavior as usize * Sequence::ALL.len() + self.sequence as usize
    }

    /// The module at `index` of module order.
    pub(crate) fn at_index(index: usize) -> Option<Self> {
        let behavior = *Behavior::ALL.get(index / Sequence::ALL.len())?;
        let sequence = *Sequence::ALL.get(index % Sequence::ALL.len())?;
        Some(Self { behavior, sequence })
    }
}

impl fmt::Display for Module {
    /// `lane-change`, or `avoidance/change` when the sequence is not empty.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.sequence {
            Sequence::Empty => f.write_str(self.behavior.as_str()),
            sequence => write!(f, "{}/{}", self.behavior, sequence.as_str()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn behavior_strings_round_trip_and_are_sorted() {
        for behavior in Behavior::ALL {
            assert_eq!(behavior.as_str().parse::<Behavior>(), Ok(behavior));
        }
        let names: Vec<_> = Behavior::ALL.iter().map(|b| b.as_str()).collect();
        let mut sorted = names.clone();
        sorted.sort_unstable();
        assert_eq!(names, sorted);
        assert!("".parse::<Behavior>().is_err());
        assert!("emergency-operation".parse::<Behavior>().is_err());
    }

    #[test]
    fn sequences_round_trip() {
        for sequence in Sequence::ALL {
            assert_eq!(sequence.as_str().parse::<Sequence>(), Ok(sequence));
        }
        assert_eq!(
            "back".parse::<Sequence>(),
            Err(UnknownName {
                field: "sequence",
                given: "back".into()
            })
        );
    }

    #[test]
    fn module_index_is_dense_and_in_module_order() {
        let modules: Vec<Module> = (0..Module::COUNT).filter_map(Module::at_index).collect();
        assert_eq!(modules.len(), Module::COUNT);
        assert_eq!(Module::at_index(Module::COUNT), None);
        for (index, module) in modules.iter().enumerate() {
            assert_eq!(module.index(), index);
        }
        assert!(modules.windows(2).all(|pair| pair[0] < pair[1]));
    }

    #[test]
    fn module_display() {
        assert_eq!(Module::new(Behavior::LaneChange).to_string(), "lane-change");
        assert_eq!(
            Module::with_sequence(Behavior::Avoidance, Sequence::Return).to_string(),
            "avoidance/return"
        );
    }
}
