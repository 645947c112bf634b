//! Validation: comparing what the real system reported with what the spec says.

use std::collections::BTreeMap;
use std::ops::ControlFlow;

use cooperation::{CooperationStatus, FactorKind, SceneId, State};

use crate::{Cause, Observation, Replayer, Sink, Step, TraceError};

/// A status field that can depart.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub enum Field {
    /// Whether the scene is listed at all.
    Scene,
    /// `module_decision`.
    ModuleDecision,
    /// `operator_decision`.
    OperatorDecision,
    /// `cancellable`.
    Cancellable,
}

impl Field {
    /// The field's name, as in the status's serde form (`scene` for presence).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Scene => "scene",
            Self::ModuleDecision => "module_decision",
            Self::OperatorDecision => "operator_decision",
            Self::Cancellable => "cancellable",
        }
    }
}

/// One field of one scene where the observation departs from the spec.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Difference {
    /// The scene.
    pub id: SceneId,
    /// The field.
    pub field: Field,
    /// What the spec says, in the spec's words.
    pub expected: String,
    /// What was observed.
    pub observed: String,
    /// The rule involved: the step whose rule last changed the scene or rejected an input
    /// naming it; `None` if no remembered input named it.
    pub cause: Option<Cause>,
}

/// The first observation that departs from the spec.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Departure {
    /// The observation's line.
    pub line: usize,
    /// The number of steps applied before it (its step is "after step `after_step`").
    pub after_step: u64,
    /// The trace's time at the observation.
    pub at_ms: Option<u64>,
    /// The step of the last of the trace's own inputs before the observation.
    pub last_input: Option<Cause>,
    /// Every departing field of the observation, in scene order, then field order.
    pub differences: Vec<Difference>,
}

/// The result of validating a trace.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Verdict {
    /// Every observation agrees with the spec.
    Conforms {
        /// Steps applied.
        steps: u64,
        /// Observations checked.
        observations: u64,
    },
    /// An observation departs from the spec; nothing after it was read.
    Departs(Departure),
}

impl Verdict {
    /// Whether the trace conforms.
    #[must_use]
    pub const fn conforms(&self) -> bool {
        matches!(self, Self::Conforms { .. })
    }
}

/// Every difference between `observation` and the statuses the spec gives for the replayer's
/// state; empty when they agree (or before the configuration, when nothing is known).
#[must_use]
pub fn compare(observation: &Observation, replayer: &Replayer) -> Vec<Difference> {
    let Some(state) = replayer.state() else {
        return Vec::new();
    };
    let expected: BTreeMap<SceneId, CooperationStatus> = state
        .scenes()
        .filter(|(_, scene)| {
            observation
                .factors
                .map_or(true, |kind| scene.geometry().kind() == kind)
        })
        .filter_map(|(id, _)| state.status(id).map(|status| (id, status)))
        .collect();
    let observed: BTreeMap<SceneId, CooperationStatus> = observation
        .statuses
        .iter()
        .map(|status| (status.id, *status))
        .collect();
    let mut ids: Vec<SceneId> = expected.keys().chain(observed.keys()).copied().collect();
    ids.sort_unstable();
    ids.dedup();
    let mut differences = Vec::new();
    for id in ids {
        let mut differ = |field, expected: String, observed: String| {
            differences.push(Difference {
                id,
                field,
                expected,
                observed,
                cause: replayer.cause(id),
            });
        };
        match (expected.get(&id), observed.get(&id)) {
            (Some(_), None) => differ(Field::Scene, "live".into(), "absent".into()),
            (None, Some(_)) => differ(
                Field::Scene,
                absence(state, id, observation.factors),
                "live".into(),
            ),
            (Some(spec), Some(seen)) => {
                if spec.module_decision != seen.module_decision {
                    differ(
                        Field::ModuleDecision,
                        spec.module_decision.to_string(),
                        seen.module_decision.to_string(),
                    );
                }
                if spec.operator_decision != seen.operator_decision {
                    differ(
                        Field::OperatorDecision,
                        spec.operator_decision.to_string(),
                        seen.operator_decision.to_string(),
                    );
                }
                if spec.cancellable != seen.cancellable {
                    differ(
                        Field::Cancellable,
                        spec.cancellable.to_string(),
                        seen.cancellable.to_string(),
                    );
                }
            }
            (None, None) => {}
        }
    }
    differences
}

/// Why the spec lists no scene `id` (in the factor list of kind `factors`, if given).
fn absence(state: &State, id: SceneId, factors: Option<FactorKind>) -> String {
    if let (Some(scene), Some(kind)) = (state.scene(id), factors) {
        return format!(
            "not a {} factor: a {} scene",
            kind_word(kind),
            kind_word(scene.geometry().kind())
        );
    }
    match state.retirement(id) {
        Some(retirement) => format!("absent: retired ({})", retirement.reason),
        None => "absent: not registered".into(),
    }
}

const fn kind_word(kind: FactorKind) -> &'static str {
    match kind {
        FactorKind::Velocity => "velocity",
        FactorKind::Steering => "steering",
    }
}

/// A sink that checks every observation and stops at the first departure.
#[derive(Clone, Debug, Default)]
pub struct Validator {
    /// The first departure, once found.
    pub departure: Option<Departure>,
}

impl Sink for Validator {
    fn step(&mut self, _: &Step, _: &Replayer) -> Result<ControlFlow<()>, TraceError> {
        Ok(ControlFlow::Continue(()))
    }

    fn observed(
        &mut self,
        line: usize,
        observation: &Observation,
        replayer: &Replayer,
    ) -> Result<ControlFlow<()>, TraceError> {
        let differences = compare(observation, replayer);
        if differences.is_empty() {
            return Ok(ControlFlow::Continue(()));
        }
        self.departure = Some(Departure {
            line,
            after_step: replayer.steps(),
            at_ms: replayer.clock_ms(),
            last_input: replayer.last_input(),
            differences,
        });
        Ok(ControlFlow::Break(()))
    }
}
