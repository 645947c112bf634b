//! Replaying records through the core: time into ticks, inputs into `State::apply`, and a
//! bounded memory of which rule last touched each scene.

use std::collections::BTreeMap;
use std::ops::ControlFlow;

use cooperation::{Input, Rejection, Rule, SceneId, State, Transition};

use crate::{ErrorKind, Event, Observation, Record, TraceError};

/// One step: one input applied to the core, from a record or made from its time.
#[derive(Clone, PartialEq, Debug)]
pub struct Step {
    /// The step's number, from 1.
    pub number: u64,
    /// The line of the record it comes from.
    pub line: usize,
    /// The trace's time at the step (`None` before the first `at_ms`).
    pub at_ms: Option<u64>,
    /// The input: the record's, or the `Tick` made from an increase of `at_ms`.
    pub input: Input,
    /// Whether the input is a tick made from `at_ms` rather than the record's input.
    pub generated: bool,
    /// What the core did: the transition, or the rejection.
    pub outcome: Result<Transition, Rejection>,
}

impl Step {
    /// The rule that fired or rejected the input.
    #[must_use]
    pub fn rule(&self) -> Rule {
        match &self.outcome {
            Ok(transition) => transition.rule,
            Err(rejection) => rejection.rule(),
        }
    }

    /// This step as a [`Cause`].
    #[must_use]
    pub fn cause(&self) -> Cause {
        Cause {
            rule: self.rule(),
            step: self.number,
            line: self.line,
        }
    }
}

/// The step whose rule last touched a scene: the transition that last changed it, or the
/// rejection of the last input naming it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Cause {
    /// The rule.
    pub rule: Rule,
    /// The step.
    pub step: u64,
    /// The step's line.
    pub line: usize,
}

/// What a replay reports to, as it goes.
pub trait Sink {
    /// After each step, with the replayer in the state the step left.
    ///
    /// # Errors
    /// Whatever the sink cannot do (writing output); the replay stops with it.
    fn step(&mut self, step: &Step, replayer: &Replayer) -> Result<ControlFlow<()>, TraceError>;

    /// At each observation, after the steps before it.
    ///
    /// # Errors
    /// As [`step`](Self::step).
    fn observed(
        &mut self,
        line: usize,
        observation: &Observation,
        replayer: &Replayer,
    ) -> Result<ControlFlow<()>, TraceError>;
}

/// Replays records, one at a time, through the core.
///
/// Memory is bounded by the configuration's limits: the core's state, and one [`Cause`] per
/// scene the core still knows (live or remembered as retired) plus the scenes of the latest
/// input.
#[derive(Clone, Debug)]
pub struct Replayer {
    state: Option<State>,
    records: u64,
    clock_ms: Option<u64>,
    steps: u64,
    observations: u64,
    last: Option<Cause>,
    causes: BTreeMap<SceneId, Cause>,
}

impl Replayer {
    /// A replayer with the configuration from outside the trace, if any; without one, the
    /// trace's first record must be its configuration.
    ///
    /// # Errors
    /// [`ErrorKind::InvalidConfig`] if the core refuses the configuration.
    pub fn new(config: Option<cooperation::Config>) -> Result<Self, TraceError> {
        let state = config
            .map(State::new)
            .transpose()
            .map_err(|error| TraceError::nowhere(ErrorKind::InvalidConfig(error)))?;
        Ok(Self {
            state,
            records: 0,
            clock_ms: None,
            steps: 0,
            observations: 0,
            last: None,
            causes: BTreeMap::new(),
        })
    }

    /// The core's state, once configured.
    #[must_use]
    pub const fn state(&self) -> Option<&State> {
        self.state.as_ref()
    }

    /// The trace's time: the last `at_ms` seen.
    #[must_use]
    pub const fn clock_ms(&self) -> Option<u64> {
        self.clock_ms
    }

    /// How many steps were applied.
    #[must_use]
    pub const fn steps(&self) -> u64 {
        self.steps
    }

    /// How many observations were read.
    #[must_use]
    pub const fn observations(&self) -> u64 {
        self.observations
    }

    /// The last step of one of the trace's own inputs (not a tick made from `at_ms`), as a
    /// cause.
    #[must_use]
    pub const fn last_input(&self) -> Option<Cause> {
        self.last
    }

    /// The step whose rule last touched `id`, while the core remembers `id` (or `id` was
    /// named by a recent input).
    #[must_use]
    pub fn cause(&self, id: SceneId) -> Option<Cause> {
        self.causes.get(&id).copied()
    }

    /// How many scenes have a remembered cause; bounded as the type's documentation says.
    #[must_use]
    pub fn tracked_scenes(&self) -> usize {
        self.causes.len()
    }

    /// Replays one record: its time (a tick if `at_ms` increased), then its input or its
    /// observation, reporting each to `sink`. `Break` when the sink asked to stop.
    ///
    /// # Errors
    /// A configuration out of place or missing, time going backwards, or the sink's error.
    pub fn feed(
        &mut self,
        line: usize,
        record: Record,
        sink: &mut dyn Sink,
    ) -> Result<ControlFlow<()>, TraceError> {
        let first = self.records == 0;
        self.records = self.records.saturating_add(1);
        let (at_ms, event) = match record {
            Record::Config(config) => {
                if !first || self.state.is_some() {
                    return Err(TraceError::at(line, ErrorKind::MisplacedConfig));
                }
                let state = State::new(config)
                    .map_err(|error| TraceError::at(line, ErrorKind::InvalidConfig(error)))?;
                self.state = Some(state);
                return Ok(ControlFlow::Continue(()));
            }
            Record::At { at_ms, event } => (at_ms, event),
            // The reader ([`crate::run`]) takes the version from the first record.
            Record::Version(_) => return Err(TraceError::at(line, ErrorKind::MisplacedVersion)),
        };
        if self.state.is_none() {
            return Err(TraceError::at(line, ErrorKind::MissingConfig));
        }
        if let Some(at_ms) = at_ms {
            match self.clock_ms {
                Some(previous_ms) if at_ms < previous_ms => {
                    return Err(TraceError::at(
                        line,
                        ErrorKind::TimeBackwards { previous_ms, at_ms },
                    ));
                }
                Some(previous_ms) if at_ms > previous_ms => {
                    self.clock_ms = Some(at_ms);
                    let tick = Input::Tick {
                        elapsed_ms: at_ms - previous_ms,
                    };
                    if self.step(line, tick, true, sink)?.is_break() {
                        return Ok(ControlFlow::Break(()));
                    }
                }
                // The first time sets the clock; the same time passes none.
                _ => self.clock_ms = Some(at_ms),
            }
        }
        match event {
            Event::Time => Ok(ControlFlow::Continue(())),
            Event::Input(input) => self.step(line, input, false, sink),
            Event::Observed(observation) => {
                self.observations = self.observations.saturating_add(1);
                sink.observed(line, &observation, self)
            }
        }
    }

    fn step(
        &mut self,
        line: usize,
        input: Input,
        generated: bool,
        sink: &mut dyn Sink,
    ) -> Result<ControlFlow<()>, TraceError> {
        let Some(state) = self.state.as_mut() else {
            return Err(TraceError::at(line, ErrorKind::MissingConfig));
        };
        let outcome = state.apply(&input);
        self.steps = self.steps.saturating_add(1);
        let step = Step {
            number: self.steps,
            line,
            at_ms: self.clock_ms,
            input,
            generated,
            outcome,
        };
        self.remember(&step);
        sink.step(&step, self)
    }

    /// Records `step` as the cause for every scene it touched, and forgets the causes of
    /// scenes the core no longer knows once there are too many.
    fn remember(&mut self, step: &Step) {
        let cause = step.cause();
        if !step.generated {
            self.last = Some(cause);
        }
        match (&step.input, &step.outcome) {
            (
                Input::Register { id, .. } | Input::Update { id, .. } | Input::Remove { id, .. },
                _,
            ) => {
                self.causes.insert(*id, cause);
            }
            (Input::SetCommands { commands }, _) => {
                for command in commands {
                    self.causes.insert(command.id, cause);
                }
            }
            (Input::Tick { .. }, Ok(transition)) => {
                for id in &transition.retired {
                    self.causes.insert(*id, cause);
                }
            }
            // Ageing changes no status; a policy names no scene.
            (Input::Tick { .. } | Input::SetPolicies { .. }, _) => {}
        }
        let Some(state) = &self.state else {
            return;
        };
        let limits = state.limits();
        let bound = limits
            .max_scenes
            .saturating_add(limits.retired_capacity)
            .saturating_add(limits.max_batch);
        if self.causes.len() > bound.saturating_mul(2) {
            self.causes.retain(|id, kept| {
                kept.step == cause.step
                    || state.scene(*id).is_some()
                    || state.retirement(*id).is_some()
            });
        }
    }
}
