//! A sequence of inputs applied all or none: [`State::apply_all`].
//!
//! Each input is decided and committed exactly as [`State::apply`] does it, by the same
//! `decide` and `commit`. The only addition is a journal: before each write, `commit` records
//! what the write overwrites, and if a later input of the sequence is refused the journal is
//! played back, newest first, which restores the state exactly. Nothing is cloned but the
//! values a write overwrites (a scene, a policy, a retired identifier, the ages on a tick), so
//! taking a two-input registration back costs what the registration cost.

use core::fmt;
use std::sync::Arc;

use super::State;
use crate::{Input, Module, Policy, Rejection, Retirement, Scene, SceneId, Transition};

/// What one write of `commit` overwrote.
pub(super) enum Undo {
    /// A scene was registered under this identifier.
    Registered(SceneId),
    /// This live scene was changed (an update, an operator decision); it was this.
    Changed(SceneId, Scene),
    /// This scene retired; it was this, live.
    Retired(SceneId, Scene),
    /// The retired set was full and forgot its oldest identifier, this one.
    Forgot(SceneId, Retirement),
    /// Time passed: every live scene's age, before.
    Aged(Vec<(SceneId, u64)>),
    /// A module's policy changed; it was this.
    Policy(Module, Policy),
}

/// Where `commit` records what it overwrites.
pub(super) trait Journal {
    /// Records the undo `undo` makes; called before the write it undoes.
    fn record(&mut self, undo: impl FnOnce() -> Undo);
}

/// The journal of [`State::apply`]: it keeps nothing, and costs nothing once inlined.
pub(super) struct Forget;

impl Journal for Forget {
    #[inline(always)]
    fn record(&mut self, _: impl FnOnce() -> Undo) {}
}

impl Journal for Vec<Undo> {
    fn record(&mut self, undo: impl FnOnce() -> Undo) {
        self.push(undo());
    }
}

/// An input of a sequence given to [`State::apply_all`] was refused, so none of the sequence
/// was applied.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct SequenceRejection {
    /// The position of the refused input in the sequence.
    pub index: usize,
    /// Why it was refused, as [`State::apply`] would have said in the state the inputs before
    /// it made.
    pub rejection: Box<Rejection>,
}

impl fmt::Display for SequenceRejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "input {} of the sequence: {}; no input of the sequence was applied",
            self.index, self.rejection
        )
    }
}

impl std::error::Error for SequenceRejection {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(self.rejection.as_ref())
    }
}

impl State {
    /// Applies `inputs` in order as one step: every one of them, or, if one is refused, none.
    ///
    /// Each input is decided and committed as [`apply`](Self::apply) does it, in the state the
    /// inputs before it made, so the transitions are the ones `apply` would return one by one.
    /// If an input is refused, what the inputs before it wrote is taken back and the state is
    /// exactly as it was. An adapter whose one call is several inputs (an owner reporting a new
    /// scene already running: a registration, then an update) uses it so that the call is whole
    /// or nothing, without copying the state.
    ///
    /// # Errors
    /// [`SequenceRejection`]: the first refused input's position and rejection; nothing is
    /// changed.
    pub fn apply_all(&mut self, inputs: &[Input]) -> Result<Vec<Transition>, SequenceRejection> {
        let mut journal = Vec::new();
        let mut transitions = Vec::with_capacity(inputs.len());
        for (index, input) in inputs.iter().enumerate() {
            match self.decide(input) {
                Ok(plan) => {
                    transitions.push(self.commit(plan, &mut journal));
                    debug_assert_eq!(self.check_invariants(), Ok(()), "after {input:?}");
                }
                Err(rejection) => {
                    self.revert(journal);
                    debug_assert_eq!(self.check_invariants(), Ok(()), "after a revert");
                    return Err(SequenceRejection {
                        index,
                        rejection: Box::new(rejection),
                    });
                }
            }
        }
        Ok(transitions)
    }

    /// Plays `journal` back, newest first: each entry restores what its write overwrote, in the
    /// state the later writes' undoing has restored, so the end is the state before the first.
    fn revert(&mut self, journal: Vec<Undo>) {
        for undo in journal.into_iter().rev() {
            match undo {
                Undo::Registered(id) => {
                    self.scenes.remove(id);
                }
                Undo::Changed(id, scene) => {
                    if let Some(live) = self.scenes.get_mut(id) {
                        *live = scene;
                    }
                }
                Undo::Retired(id, scene) => {
                    // The newest retirement, so the last in the retirement order.
                    if self.retired_order.back() == Some(&id) {
                        Arc::make_mut(&mut self.retired_order).pop_back();
                    }
                    Arc::make_mut(&mut self.retired).remove(&id);
                    self.scenes.insert(id, scene);
                }
                Undo::Forgot(id, retirement) => {
                    // Forgotten as the oldest, so it goes back to the front.
                    Arc::make_mut(&mut self.retired_order).push_front(id);
                    Arc::make_mut(&mut self.retired).insert(id, retirement);
                }
                Undo::Aged(ages) => {
                    for (id, age_ms) in ages {
                        if let Some(scene) = self.scenes.get_mut(id) {
                            scene.age_ms = age_ms;
                        }
                    }
                }
                Undo::Policy(module, policy) => {
                    if let Some(slot) = self.policies.get_mut(module) {
                        *slot = policy;
                    }
                }
            }
        }
    }
}
