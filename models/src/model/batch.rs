//! The batch model: inputs applied as one step, all or none (`State::apply_all`, spec §4).
//!
//! The sequential model applies one input at a time, with `State::apply`. Here every step is a
//! pair of inputs from the sequential model's alphabet, applied with the library's
//! `State::apply_all`, and the property compares it with `State::apply` applied to a copy,
//! input by input (the transition the sequential model checks against the spec's rules): when
//! both inputs fire, the same transitions and the same state; when one is refused, its position
//! and rejection, and the state before the pair, exactly. At the bounds of [`BatchModel::new`]
//! the retired set holds one identifier, so an input that retires a scene forgets another, and
//! a pair refused after it must take the forgetting back: the witness property says that
//! happens.

use cooperation::{Input, SceneId, SequenceRejection, State, Transition};
use stateright::{Model, Property};

use crate::model::fault;
use crate::model::ids::ModelError;
use crate::model::sequential::{Bounds, SequentialModel};

/// The property: a pair is applied as `apply` would apply its inputs one by one, or not at
/// all.
pub const ALL_OR_NONE: &str =
    "§4 a sequence of inputs: every input as apply says, or none and the state as it was";

/// The witness: a pair whose first input forgot a retired identifier is refused at its second,
/// and the identifier is retired again.
pub const FORGETTING_TAKEN_BACK: &str =
    "witness: a refused sequence takes back the forgetting of a retired identifier";

/// A deliberately wrong batch, for showing that the property can fail.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BatchFault {
    /// The inputs are applied one by one and what the first did is kept when the second is
    /// refused, as a caller without `apply_all` would leave it.
    KeptPartial,
}

/// A state of the batch model: the core, and what the step that led here showed.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct BatchState {
    /// The core's state.
    pub core: State,
    /// The step did not do what `apply`, input by input, does (a dead end).
    pub broken: bool,
    /// The step was a refused pair whose first input forgot a retired identifier, taken back
    /// (a dead end: the state is its predecessor's, whose successors are explored).
    pub took_back_forgetting: bool,
}

/// The batch model: pairs of inputs over one module and two identifiers, one live and one
/// retired at most.
#[derive(Clone, Debug)]
pub struct BatchModel {
    sequential: SequentialModel,
    fault: Option<BatchFault>,
}

impl BatchModel {
    /// The bounds: one module, two identifiers, one live scene and one retired identifier.
    pub const BOUNDS: Bounds = Bounds {
        modules: 1,
        scenes: 2,
        live: 1,
        retired: 1,
    };

    /// The model at [`BatchModel::BOUNDS`].
    ///
    /// # Errors
    /// If the sequential model at those bounds cannot be made (never).
    pub fn new() -> Result<Self, ModelError> {
        Ok(Self {
            sequential: SequentialModel::new(Self::BOUNDS)?,
            fault: None,
        })
    }

    /// The same model with a wrong batch (sensitivity tests only).
    #[must_use]
    pub const fn with_fault(mut self, fault: BatchFault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The inputs a pair is drawn from: the sequential model's alphabet at the same bounds.
    #[must_use]
    pub fn alphabet(&self) -> &[Input] {
        self.sequential.alphabet()
    }
}

/// `inputs` applied to a copy of `core` one by one with `State::apply`, until one is refused.
fn one_by_one(
    core: &State,
    inputs: &[Input],
) -> (State, Result<Vec<Transition>, SequenceRejection>) {
    let mut state = core.clone();
    let mut transitions = Vec::with_capacity(inputs.len());
    for (index, input) in inputs.iter().enumerate() {
        let (next, result) = fault::transition(None, &state, input);
        state = next.into_owned();
        match result {
            Ok(transition) => transitions.push(transition),
            Err(rejection) => {
                let refused = SequenceRejection {
                    index,
                    rejection: Box::new(rejection),
                };
                return (state, Err(refused));
            }
        }
    }
    (state, Ok(transitions))
}

/// Whether `after` has forgotten an identifier `before` held retired.
fn forgot(before: &State, after: &State) -> bool {
    before
        .retired_by_id()
        .any(|(id, _): (SceneId, _)| after.retirement(id).is_none())
}

impl Model for BatchModel {
    type State = BatchState;
    type Action = (usize, usize);

    fn init_states(&self) -> Vec<BatchState> {
        State::new(self.sequential.config().clone())
            .map(|core| BatchState {
                core,
                broken: false,
                took_back_forgetting: false,
            })
            .into_iter()
            .collect()
    }

    fn actions(&self, state: &BatchState, actions: &mut Vec<(usize, usize)>) {
        if state.broken || state.took_back_forgetting {
            return;
        }
        let inputs = self.alphabet().len();
        actions
            .extend((0..inputs).flat_map(|first| (0..inputs).map(move |second| (first, second))));
    }

    fn next_state(
        &self,
        state: &BatchState,
        (first, second): (usize, usize),
    ) -> Option<BatchState> {
        let inputs = [
            self.alphabet().get(first)?.clone(),
            self.alphabet().get(second)?.clone(),
        ];
        let (core, result) = match self.fault {
            None => fault::sequence(&state.core, &inputs),
            Some(BatchFault::KeptPartial) => one_by_one(&state.core, &inputs),
        };
        let (expected_core, expected) = one_by_one(&state.core, &inputs);
        let broken = match (&result, &expected) {
            (Ok(_), Ok(_)) => result != expected || core != expected_core,
            (Err(_), Err(_)) => result != expected || core != state.core,
            _ => true,
        };
        let refused = expected.is_err();
        if refused && !broken {
            // Nothing changed: the witness is all this step can show. Input by input, the state
            // is the one the inputs before the refused one made.
            return forgot(&state.core, &expected_core).then_some(BatchState {
                core,
                broken: false,
                took_back_forgetting: true,
            });
        }
        Some(BatchState {
            core,
            broken,
            took_back_forgetting: false,
        })
    }

    fn properties(&self) -> Vec<Property<Self>> {
        vec![
            Property::always(ALL_OR_NONE, |_: &Self, state: &BatchState| !state.broken),
            Property::sometimes(FORGETTING_TAKEN_BACK, |_: &Self, state: &BatchState| {
                state.took_back_forgetting
            }),
        ]
    }
}
