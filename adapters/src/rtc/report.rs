//! A scene's status as its owner reports it, parsed: what `updateCooperateStatus` takes.

use std::ops::Deref;

use cooperation::{Phase, SceneId, Sequence, Transition};

use super::{CooperateStatus, FieldError};

/// One scene's status as its owner reports it through an RTC interface: upstream's
/// `updateCooperateStatus` arguments, parsed, and the sequence an owner states for a new scene
/// of an interface that binds several ([`Interface::update_cooperate_status`]).
///
/// Built from a [`CooperateStatus`] message with [`CooperateStatus::report`], or field by field;
/// the lifecycle state is a [`Phase`] here, so an undefined state number is refused where it is
/// read (`[COOP-DEV-CONSTANTS.1]`), before anything reaches the core.
///
/// [`Interface::update_cooperate_status`]: super::Interface::update_cooperate_status
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct StatusReport {
    /// The scene.
    pub id: SceneId,
    /// The module's own judgment: the module decision is activate.
    pub safe: bool,
    /// Where the scene is in its lifecycle.
    pub phase: Phase,
    /// Distance to the start of the section the scene changes, in metres.
    pub start_distance: f32,
    /// Distance to its end, in metres.
    pub finish_distance: f32,
    /// The owner asks the operator explicitly.
    pub requested: bool,
    /// The scene's sequence, stated by its owner: needed to register a scene of an interface
    /// that binds several (the avoidances' change and return, `[COOP-DEV-SEQUENCE.1]`).
    pub sequence: Option<Sequence>,
}

impl StatusReport {
    /// A report of scene `id`, not requested, its sequence not stated.
    #[must_use]
    pub const fn new(
        id: SceneId,
        safe: bool,
        phase: Phase,
        start_distance: f32,
        finish_distance: f32,
    ) -> Self {
        Self {
            id,
            safe,
            phase,
            start_distance,
            finish_distance,
            requested: false,
            sequence: None,
        }
    }

    /// The same report, with the owner asking the operator explicitly.
    #[must_use]
    pub const fn requesting(self) -> Self {
        Self {
            requested: true,
            ..self
        }
    }

    /// The same report, stating the scene's sequence.
    #[must_use]
    pub const fn in_sequence(self, sequence: Sequence) -> Self {
        Self {
            sequence: Some(sequence),
            ..self
        }
    }
}

impl CooperateStatus {
    /// The report an owner makes with this status: its `uuid`, `safe`, `state`, distances and
    /// `requested`. The fields an interface fills itself when it publishes (`stamp`, `module`,
    /// `command_status`, `auto_mode`) are not read.
    ///
    /// # Errors
    /// A [`FieldError`] on `state.type` if it is none of the lifecycle constants
    /// (`[COOP-DEV-CONSTANTS.1]`).
    pub fn report(&self) -> Result<StatusReport, FieldError> {
        Ok(StatusReport {
            id: self.uuid.into(),
            safe: self.safe,
            phase: self.state.phase().map_err(|e| e.within("state"))?,
            start_distance: self.start_distance,
            finish_distance: self.finish_distance,
            requested: self.requested,
            sequence: None,
        })
    }
}

/// What one status report did to the core ([`Interface::update_cooperate_status`]): one
/// transition, or two when it registered a scene already past waiting (its registration, then
/// its update). A report of a live scene, a planning cycle's usual call, answers its one
/// transition without a vector of its own. Read it as a slice.
///
/// [`Interface::update_cooperate_status`]: super::Interface::update_cooperate_status
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Transitions(Held);

#[derive(Clone, PartialEq, Eq, Debug)]
enum Held {
    One(Transition),
    Several(Vec<Transition>),
}

impl From<Transition> for Transitions {
    fn from(transition: Transition) -> Self {
        Self(Held::One(transition))
    }
}

impl From<Vec<Transition>> for Transitions {
    fn from(transitions: Vec<Transition>) -> Self {
        Self(Held::Several(transitions))
    }
}

impl From<Transitions> for Vec<Transition> {
    fn from(transitions: Transitions) -> Self {
        match transitions.0 {
            Held::One(transition) => vec![transition],
            Held::Several(transitions) => transitions,
        }
    }
}

impl Deref for Transitions {
    type Target = [Transition];

    fn deref(&self) -> &[Transition] {
        match &self.0 {
            Held::One(transition) => std::slice::from_ref(transition),
            Held::Several(transitions) => transitions,
        }
    }
}

impl<'a> IntoIterator for &'a Transitions {
    type Item = &'a Transition;
    type IntoIter = std::slice::Iter<'a, Transition>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use cooperation::Rule;

    use super::*;

    /// One transition or several read as the same slice and give the same vector back.
    #[test]
    fn one_or_several_transitions_read_alike() {
        let one = Transitions::from(Transition {
            rule: Rule::OwnerUpdate,
            retired: Vec::new(),
        });
        let several = Transitions::from(vec![one[0].clone()]);
        assert_eq!(*one, *several);
        assert_eq!(one.len(), 1);
        assert_eq!((&one).into_iter().count(), 1);
        assert_eq!(Vec::from(one), Vec::from(several));
    }
}
