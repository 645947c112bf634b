//! The serialized form of a [`State`](super::State): maps as lists, so that any format can
//! carry it. Reading one back accepts exactly the states the core can reach: limits that
//! [`State::new`](super::State::new) accepts, no entry listed twice, and every invariant of
//! spec §8.

use core::fmt;
use std::collections::BTreeSet;

use super::{ConfigError, Limits, Module, Retirement, Scene, SceneId, Violation};
use crate::Policy;

#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct State {
    limits: Limits,
    policies: Vec<(Module, Policy)>,
    scenes: Vec<(SceneId, Scene)>,
    retired: Vec<(SceneId, Retirement)>,
    retired_order: Vec<SceneId>,
}

/// Why a serialized state was refused.
#[derive(Debug)]
pub(super) enum Refusal {
    /// A limit that [`State::new`](super::State::new) refuses.
    Limits(ConfigError),
    /// A module in `policies` twice.
    RepeatedPolicy(Module),
    /// An identifier twice in `scenes` or in `retired`.
    Repeated {
        /// `scenes` or `retired`.
        list: &'static str,
        /// The identifier listed twice.
        id: SceneId,
    },
    /// A state the core cannot reach.
    Invariant(Violation),
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Limits(error) => write!(f, "field `limits`: {error}"),
            Self::RepeatedPolicy(module) => {
                write!(f, "field `policies`: module {module} is listed twice")
            }
            Self::Repeated { list, id } => write!(f, "field `{list}`: {id} is listed twice"),
            Self::Invariant(violation) => write!(f, "not a state the core can reach: {violation}"),
        }
    }
}

/// The first key that `keys` yields twice.
fn repeated<K: Ord + Copy>(keys: impl IntoIterator<Item = K>) -> Option<K> {
    let mut seen = BTreeSet::new();
    keys.into_iter().find(|key| !seen.insert(*key))
}

impl From<super::State> for State {
    fn from(state: super::State) -> Self {
        Self {
            limits: state.limits,
            policies: state.policies.iter().collect(),
            scenes: state.scenes.into_iter().collect(),
            retired: state.retired.iter().map(|(id, r)| (*id, *r)).collect(),
            retired_order: state.retired_order.iter().copied().collect(),
        }
    }
}

impl TryFrom<State> for super::State {
    type Error = Refusal;

    fn try_from(raw: State) -> Result<Self, Refusal> {
        raw.limits.check().map_err(Refusal::Limits)?;
        if let Some(module) = repeated(raw.policies.iter().map(|(module, _)| *module)) {
            return Err(Refusal::RepeatedPolicy(module));
        }
        for (list, entries) in [
            ("scenes", repeated(raw.scenes.iter().map(|(id, _)| *id))),
            ("retired", repeated(raw.retired.iter().map(|(id, _)| *id))),
        ] {
            if let Some(id) = entries {
                return Err(Refusal::Repeated { list, id });
            }
        }
        // A repeat in `retired_order` is refused by `[COOP-INV-RETIRED-ORDER.1]` below.
        let policies: super::Policies = raw.policies.into_iter().collect();
        let mut scenes = raw.scenes;
        // Where each scene's policy is kept, which a serialised scene leaves out. A scene whose
        // module has none keeps the default, and `[COOP-INV-MODULE.1]` refuses it below.
        for (_, scene) in &mut scenes {
            if let Some(slot) = policies.slot(scene.module) {
                scene.slot = slot;
            }
        }
        let state = Self {
            limits: raw.limits,
            policies,
            scenes: scenes.into_iter().collect(),
            retired: std::sync::Arc::new(raw.retired.into_iter().collect()),
            retired_order: std::sync::Arc::new(raw.retired_order.into_iter().collect()),
        };
        state.check_invariants().map_err(Refusal::Invariant)?;
        Ok(state)
    }
}
