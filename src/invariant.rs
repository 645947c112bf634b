//! The state invariants of spec §8, as data.

use core::fmt;

use crate::SceneId;

/// An invariant of the specification's §8. [`State::check_invariants`](crate::State) checks
/// them all.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub enum Invariant {
    /// No identifier is both live and retired.
    Disjoint,
    /// The retirement order lists exactly the retired identifiers, each once.
    RetiredOrder,
    /// No more identifiers are retired than the retired capacity.
    RetiredBound,
    /// No more scenes are live than the scene limit.
    LiveBound,
    /// No live scene is in a terminal phase.
    LivePhase,
    /// No live scene is older than the time-to-live.
    Age,
    /// Every live scene's module has a policy.
    Module,
}

impl Invariant {
    /// Every invariant, in spec order.
    pub const ALL: [Self; 7] = [
        Self::Disjoint,
        Self::RetiredOrder,
        Self::RetiredBound,
        Self::LiveBound,
        Self::LivePhase,
        Self::Age,
        Self::Module,
    ];

    /// The invariant's tag in the specification.
    #[must_use]
    pub const fn tag(self) -> &'static str {
        match self {
            Self::Disjoint => "COOP-INV-DISJOINT.1",
            Self::RetiredOrder => "COOP-INV-RETIRED-ORDER.1",
            Self::RetiredBound => "COOP-INV-RETIRED-BOUND.1",
            Self::LiveBound => "COOP-INV-LIVE-BOUND.1",
            Self::LivePhase => "COOP-INV-LIVE-PHASE.1",
            Self::Age => "COOP-INV-AGE.1",
            Self::Module => "COOP-INV-MODULE.1",
        }
    }
}

impl fmt::Display for Invariant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.tag())
    }
}

/// A broken invariant: a bug in this library, never the caller's fault.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Violation {
    /// Which invariant.
    pub invariant: Invariant,
    /// The scene it was found at, when it concerns one.
    pub id: Option<SceneId>,
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.id {
            Some(id) => write!(f, "invariant {} broken at scene {id}", self.invariant),
            None => write!(f, "invariant {} broken", self.invariant),
        }
    }
}

impl std::error::Error for Violation {}
