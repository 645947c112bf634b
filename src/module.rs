//! Modules: the planning behaviours a scene belongs to, and their sequences.

use core::cmp::Ordering;
use core::fmt;
use core::str::FromStr;

mod name;
#[cfg(feature = "serde")]
mod serde_form;

pub use name::{Extension, NameProblem};

/// A planning behaviour: one of the AD API's `PlanningBehavior` string constants, or a user
/// extension.
///
/// The AD API's `UNKNOWN` (the empty string) is not a behaviour: parsing it fails. Any other
/// string that is not a built-in name is a user extension if it is a valid
/// [`Extension`] name (1 to 24 bytes of `a-z`, `0-9` and `-`, starting with a letter):
///
/// ```
/// use cooperation::{Behavior, NameProblem};
///
/// assert_eq!("lane-change".parse(), Ok(Behavior::LaneChange));
/// let custom: Behavior = "valet-parking".parse().unwrap();
/// assert!(matches!(custom, Behavior::Extension(_)));
/// assert_eq!(custom.as_str(), "valet-parking");
/// assert_eq!(Behavior::named("lane_change"), Err(NameProblem::Character { at: 4 }));
/// ```
///
/// Behaviours are ordered by their strings, byte by byte, built-in and extension names alike
/// (`approach-assist` before `avoidance`, `lane-change` before `lane-change-assist`): the order
/// `get_policies` lists modules in (`[COOP-POL-GET.2]`). With the `serde` feature a behaviour is
/// written as its string.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
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
    /// A user extension: any other valid name.
    Extension(Extension),
}

impl Behavior {
    /// Every built-in behaviour, in the order of their strings.
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

    /// The behaviour `name` stands for: a built-in one, or else an extension.
    ///
    /// # Errors
    ///
    /// Why `name` is neither a built-in name nor a valid [`Extension`] name.
    pub const fn named(name: &str) -> Result<Self, NameProblem> {
        let mut rest: &[Self] = &Self::ALL;
        while let [behavior, tail @ ..] = rest {
            if let Some(builtin) = behavior.builtin_str() {
                if name::same(builtin, name) {
                    return Ok(*behavior);
                }
            }
            rest = tail;
        }
        match Extension::new(name) {
            Ok(extension) => Ok(Self::Extension(extension)),
            Err(problem) => Err(problem),
        }
    }

    /// The AD API string.
    #[must_use]
    pub fn as_str(&self) -> &str {
        match self {
            Self::Extension(extension) => extension.as_str(),
            builtin => builtin.builtin_str().unwrap_or_default(),
        }
    }

    /// The string's bytes, which module order compares.
    fn name_bytes(&self) -> &[u8] {
        match self {
            Self::Extension(extension) => extension.as_bytes(),
            builtin => builtin.builtin_str().unwrap_or_default().as_bytes(),
        }
    }

    /// A built-in behaviour's place in [`Behavior::ALL`]; `None` for an extension.
    #[inline]
    pub(crate) const fn rank(self) -> Option<usize> {
        Some(match self {
            Self::Extension(_) => return None,
            Self::AdaptiveCruise => 0,
            Self::Avoidance => 1,
            Self::Crosswalk => 2,
            Self::GoalPlanner => 3,
            Self::Intersection => 4,
            Self::LaneChange => 5,
            Self::Merge => 6,
            Self::NoDrivableLane => 7,
            Self::NoStoppingArea => 8,
            Self::RearCheck => 9,
            Self::Roundabout => 10,
            Self::RouteObstacle => 11,
            Self::RunOut => 12,
            Self::Sidewalk => 13,
            Self::StartPlanner => 14,
            Self::StopSign => 15,
            Self::SurroundingObstacle => 16,
            Self::TrafficSignal => 17,
            Self::UserDefinedAttentionArea => 18,
            Self::VirtualTrafficLight => 19,
        })
    }

    /// The AD API string of a built-in behaviour; `None` for an extension.
    const fn builtin_str(self) -> Option<&'static str> {
        Some(match self {
            Self::Extension(_) => return None,
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
        })
    }
}

/// A string that names no [`Behavior`] or no [`Sequence`]: neither a built-in name nor a valid
/// [`Extension`] name.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct InvalidName {
    /// What was being parsed: `"behavior"` or `"sequence"`.
    pub field: &'static str,
    /// The string that was given.
    pub given: String,
    /// What is wrong with it.
    pub problem: NameProblem,
}

impl fmt::Display for InvalidName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} is not a {}: {}",
            self.given, self.field, self.problem
        )
    }
}

impl std::error::Error for InvalidName {}

impl FromStr for Behavior {
    type Err = InvalidName;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::named(text).map_err(|problem| InvalidName {
            field: "behavior",
            given: text.to_owned(),
            problem,
        })
    }
}

impl fmt::Display for Behavior {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A planning sequence: which part of a behaviour a module plans (AD API `PlanningSequence`),
/// or a user extension (a valid [`Extension`] name that is not a built-in one).
///
/// Sequences are ordered by their strings, byte by byte, built-in and extension names alike:
/// the empty sequence first, then `approach` (an extension), `change`, `return`. With the
/// `serde` feature a sequence is written as its string (`""` for the empty one).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub enum Sequence {
    /// The empty string: the behaviour is not split into sequences.
    #[default]
    Empty,
    /// `"change"`: moving away from the current path (for example, avoidance's shift out).
    Change,
    /// `"return"`: coming back to it.
    Return,
    /// A user extension: any other valid name.
    Extension(Extension),
}

impl Sequence {
    /// Every built-in sequence.
    pub const ALL: [Self; 3] = [Self::Empty, Self::Change, Self::Return];

    /// The sequence `name` stands for: a built-in one (`""` is [`Sequence::Empty`]), or else an
    /// extension.
    ///
    /// # Errors
    ///
    /// Why `name` is neither a built-in name nor a valid [`Extension`] name.
    pub const fn named(name: &str) -> Result<Self, NameProblem> {
        let mut rest: &[Self] = &Self::ALL;
        while let [sequence, tail @ ..] = rest {
            if let Some(builtin) = sequence.builtin_str() {
                if name::same(builtin, name) {
                    return Ok(*sequence);
                }
            }
            rest = tail;
        }
        match Extension::new(name) {
            Ok(extension) => Ok(Self::Extension(extension)),
            Err(problem) => Err(problem),
        }
    }

    /// The AD API string.
    #[must_use]
    pub fn as_str(&self) -> &str {
        match self {
            Self::Extension(extension) => extension.as_str(),
            builtin => builtin.builtin_str().unwrap_or_default(),
        }
    }

    /// The string's bytes, which module order compares.
    fn name_bytes(&self) -> &[u8] {
        match self {
            Self::Extension(extension) => extension.as_bytes(),
            builtin => builtin.builtin_str().unwrap_or_default().as_bytes(),
        }
    }

    /// A built-in sequence's place in [`Sequence::ALL`]; `None` for an extension.
    #[inline]
    pub(crate) const fn rank(self) -> Option<usize> {
        match self {
            Self::Empty => Some(0),
            Self::Change => Some(1),
            Self::Return => Some(2),
            Self::Extension(_) => None,
        }
    }

    /// The AD API string of a built-in sequence; `None` for an extension.
    const fn builtin_str(self) -> Option<&'static str> {
        match self {
            Self::Empty => Some(""),
            Self::Change => Some("change"),
            Self::Return => Some("return"),
            Self::Extension(_) => None,
        }
    }
}

/// The order of two names, each a built-in one (by its place in its `ALL`, which lists the
/// built-in names in string order) or an extension: byte order of the strings, without
/// comparing strings when both are built in. An extension value can hold a built-in name of
/// the other kind (a sequence named `avoidance` made a behaviour extension); of two such
/// unequal values with one string, the built-in one comes first, so the order agrees with
/// `Eq`.
fn name_order(a: (Option<usize>, &[u8]), b: (Option<usize>, &[u8])) -> Ordering {
    match (a, b) {
        ((Some(a), _), (Some(b), _)) => a.cmp(&b),
        ((a_rank, a), (b_rank, b)) => a
            .cmp(b)
            .then_with(|| a_rank.is_none().cmp(&b_rank.is_none())),
    }
}

impl Ord for Behavior {
    /// Byte order of the behaviours' strings (`[COOP-POL-GET.2]`).
    fn cmp(&self, other: &Self) -> Ordering {
        name_order(
            (self.rank(), self.name_bytes()),
            (other.rank(), other.name_bytes()),
        )
    }
}

impl PartialOrd for Behavior {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Sequence {
    /// Byte order of the sequences' strings (`[COOP-POL-GET.2]`).
    fn cmp(&self, other: &Self) -> Ordering {
        name_order(
            (self.rank(), self.name_bytes()),
            (other.rank(), other.name_bytes()),
        )
    }
}

impl PartialOrd for Sequence {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl FromStr for Sequence {
    type Err = InvalidName;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::named(text).map_err(|problem| InvalidName {
            field: "sequence",
            given: text.to_owned(),
            problem,
        })
    }
}

/// A module, identified the AD API way: a behaviour plus a sequence.
///
/// Cooperation policies are held per module (spec §3). Modules are ordered by behaviour, then
/// sequence, each by its string (`[COOP-POL-GET.2]`).
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
    /// How many built-in modules there are: every built-in behaviour with every built-in
    /// sequence.
    pub(crate) const COUNT: usize = Behavior::ALL.len() * Sequence::ALL.len();

    /// A built-in module's place in module order, below [`COUNT`](Self::COUNT): a dense index
    /// for per-module tables. `None` for a module with an extension behaviour or sequence.
    #[inline]
    pub(crate) const fn index(self) -> Option<usize> {
        match (self.behavior.rank(), self.sequence.rank()) {
            (Some(behavior), Some(sequence)) => Some(behavior * Sequence::ALL.len() + sequence),
            _ => None,
        }
    }

    /// The built-in module at `index` of module order.
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
mod tests;
