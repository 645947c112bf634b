//! The state invariants of spec §8: what they are, and the check of a state against them.

use core::fmt;

use std::collections::BTreeSet;

use super::State;
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

impl State {
    /// Whether the retirement order lists exactly the retired identifiers, each once. One
    /// algorithm for every size, so that the small sets a model checker sees run the same code
    /// as a full retired set.
    fn retired_order_is_exact(&self) -> bool {
        let order = &self.retired_order;
        // Same length, every entry retired, and no entry repeated: exactly the retired set.
        order.len() == self.retired.len()
            && order.iter().all(|id| self.retired.contains_key(id))
            && order.iter().collect::<BTreeSet<_>>().len() == order.len()
    }

    /// Checks every invariant of spec §8. `apply` asserts this after every input in debug
    /// builds; the models and the property tests call it too.
    ///
    /// # Errors
    /// The first [`Violation`] found.
    pub fn check_invariants(&self) -> Result<(), Violation> {
        let fail = |invariant, id| Err(Violation { invariant, id });
        // [COOP-INV-DISJOINT.1]
        if let Some((id, _)) = self
            .scenes
            .iter()
            .find(|(id, _)| self.retired.contains_key(id))
        {
            return fail(Invariant::Disjoint, Some(id));
        }
        // [COOP-INV-RETIRED-ORDER.1]
        if !self.retired_order_is_exact() {
            return fail(Invariant::RetiredOrder, None);
        }
        // [COOP-INV-RETIRED-BOUND.1]
        if self.retired.len() > self.limits.retired_capacity {
            return fail(Invariant::RetiredBound, None);
        }
        // [COOP-INV-LIVE-BOUND.1]
        if self.scenes.len() > self.limits.max_scenes {
            return fail(Invariant::LiveBound, None);
        }
        for (id, scene) in self.scenes.iter() {
            // [COOP-INV-LIVE-PHASE.1]
            if scene.phase.is_terminal() {
                return fail(Invariant::LivePhase, Some(id));
            }
            // [COOP-INV-AGE.1]
            if scene.age_ms > self.limits.ttl_ms {
                return fail(Invariant::Age, Some(id));
            }
            // [COOP-INV-MODULE.1] The scene keeps the place of its module's policy too.
            if !self
                .policies
                .slot(scene.module)
                .is_some_and(|slot| slot.is(scene.slot))
            {
                return fail(Invariant::Module, Some(id));
            }
        }
        Ok(())
    }
}
