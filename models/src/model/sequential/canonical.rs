//! Canonical states: symmetry reduction for breadth-first search.
//!
//! stateright applies a [`Representative`](stateright::Representative) only in its
//! depth-first search, whose pending states each carry their whole path, so its memory grows
//! with the square of the depth. With canonical states on,
//! [`next_state`](stateright::Model::next_state) itself returns each successor already renamed
//! to its canonical form (the identifiers renamed `1, 2, …` in the order of their signatures,
//! [`Step::canonical_step`]): breadth-first search, which keeps
//! one fingerprint per state and a frontier as long as a level, then meets each class of
//! states equal up to renaming once, as depth-first search with symmetry does. The classes,
//! and so the unique and generated counts, are the same (`models/tests/canonical.rs`
//! compares them).
//!
//! A path of actions taken from canonical states names identifiers as each canonical state
//! does; [`SequentialModel::raw_inputs`] turns it into the inputs that take the model without
//! renaming through the same states up to renaming, which is what a trace records and replays.

use cooperation::{Input, SceneId, TableLayout};

use super::step::{identity, Names};
use super::{Action, SequentialModel, Step};
use crate::model::ids::index;

impl SequentialModel {
    /// The same model returning every successor in its canonical form (the module's doc),
    /// on the default table only: a renamed state's scene table is built anew, without the
    /// history (tombstones, wrap-around) the hashed table's checks explore, so with
    /// [`TableLayout::Colliding`] this has no effect ([`canonical_states`](Self::canonical_states)
    /// says whether it has). Off by default; the coverage search keeps it off.
    #[must_use]
    pub fn with_canonical_states(mut self, on: bool) -> Self {
        self.canonical = on;
        self
    }

    /// Whether successors are returned in canonical form: asked for, on the default table.
    #[must_use]
    pub fn canonical_states(&self) -> bool {
        self.canonical && self.table == TableLayout::Adaptive
    }

    /// The successor of `from` by `input`, in canonical form when the model says so.
    pub(super) fn successor(&self, from: &Step, input: &Input) -> Step {
        self.in_form(self.step(from, input))
    }

    /// `next` in canonical form when the model says so.
    pub(super) fn in_form(&self, next: Step) -> Step {
        if self.canonical_states() {
            next.canonical_step()
        } else {
            next
        }
    }

    /// The inputs that take the model without renaming where `actions` take this one from the
    /// initial state: each action's input with its identifiers named as the unrenamed path
    /// names them. Without canonical states, each action's input as it is.
    #[must_use]
    pub fn raw_inputs(&self, actions: &[Action]) -> Vec<Input> {
        let inputs = actions.iter().filter_map(|a| self.alphabet.get(*a));
        if !self.canonical_states() {
            return inputs.cloned().collect();
        }
        let Ok(mut state) = self.initial() else {
            return Vec::new();
        };
        // Identifier `j + 1` of the canonical state is identifier `to_raw[j] + 1` on the path
        // without renaming.
        let mut to_raw = identity();
        let mut raw = Vec::with_capacity(actions.len());
        for input in inputs {
            raw.push(renamed_input(input, &to_raw));
            let next = self.step(&state, input);
            let back = inverse(&next.representative_names());
            to_raw = core::array::from_fn(|j| {
                back.get(j)
                    .and_then(|i| to_raw.get(*i))
                    .copied()
                    .unwrap_or(j)
            });
            state = next.canonical_step();
        }
        raw
    }
}

/// The inverse of a permutation.
#[must_use]
pub fn inverse(names: &Names) -> Names {
    let mut inverse = identity();
    for (old, new) in names.iter().enumerate() {
        if let Some(slot) = inverse.get_mut(*new) {
            *slot = old;
        }
    }
    inverse
}

/// `input` with its scene identifiers renamed by `names` (identifier `i + 1` becomes
/// `names[i] + 1`), everything else as it is.
#[must_use]
pub fn renamed_input(input: &Input, names: &Names) -> Input {
    let rename = |id: &mut SceneId| {
        if let Some(new) = index(*id).and_then(|i| names.get(i)) {
            *id = SceneId::from_u128(*new as u128 + 1);
        }
    };
    let mut renamed = input.clone();
    match &mut renamed {
        Input::Register { id, .. } | Input::Update { id, .. } | Input::Remove { id, .. } => {
            rename(id);
        }
        Input::SetCommands { commands } => {
            for command in commands {
                rename(&mut command.id);
            }
        }
        Input::SetPolicies { .. } | Input::Tick { .. } => {}
    }
    renamed
}
