//! The sequential model: one state, inputs one at a time, every interleaving of owner inputs,
//! commands, policy changes and time over a bounded set of identifiers and modules.
//!
//! `next_state` calls the library's transition, [`State::apply`], on a copy of the state, as a
//! consumer calls it, through [`SequentialModel::transition`], which is exactly that unless a
//! [`Fault`] is injected for a sensitivity test. Then it records what it observed in history
//! variables ([`Ghost`]): the rule that fired, and sticky flags for transition properties (a
//! property of a step, not of a state), among them whether the step is the one the spec's rules
//! (`crate::model::spec::rules`) say. A flag is only ever set when a property is violated, so in a
//! correct run the flags add no states.

use std::borrow::Cow;
use std::sync::Arc;

use cooperation::{
    Behavior, Config, Decision, Input, Limits, Module, Policy, Rejection, Rule, SceneId, Sequence,
    State, TableLayout, Transition,
};
use stateright::{Model, Property};

use crate::check::budget::Halt;
use crate::model::fault::Fault;
use crate::model::ids::{ModelError, MAX_SCENES};
use crate::model::spec::{Tables, SPEC};

mod alphabet;
mod canonical;
mod ghost;
mod properties;
mod step;

use alphabet::alphabet;
pub use canonical::{inverse, renamed_input};
use ghost::{against_spec, observe};
pub use ghost::{Broken, Ghost};
pub use properties::{properties, rule_property, INVARIANTS};
pub use step::{identity, Names, Step};

/// A user-extension module: behaviour `junction`, sequence `approach`. The core keeps an
/// extension module's policy apart from the built-in ones' (a sorted list, not a slot per
/// module), so every model from two modules on holds one of each. Its name sorts directly
/// before `lane-change`, the first configured built-in module, with no built-in module between
/// them, so the module order `get_policies` lists (`[COOP-POL-GET.2]`, checked in every state)
/// decides between the two kinds at the one place where an extension and a configured built-in
/// slot meet: a listing that put the extension one slot late would fail the check.
// Evaluated when compiling: a name the core refuses fails the build, it cannot panic at run
// time.
#[allow(clippy::panic)]
pub const EXTENSION: Module = match (Behavior::named("junction"), Sequence::named("approach")) {
    (Ok(behavior), Ok(sequence)) => Module::with_sequence(behavior, sequence),
    _ => panic!("not a valid extension name"),
};

/// The modules a model draws from, with their default policies: the first `modules` of these.
/// The first is built in, the second a user extension ([`EXTENSION`]); the core never reads a
/// module's name, so which names they have does not change what is reachable
/// (`docs/verification.md`, *Small scopes*).
pub const MODULES: [(Module, Policy); 8] = [
    (Module::new(Behavior::LaneChange), Policy::Optional),
    (EXTENSION, Policy::Required),
    (
        Module::with_sequence(Behavior::Avoidance, Sequence::Change),
        Policy::Optional,
    ),
    (Module::new(Behavior::Crosswalk), Policy::Required),
    (Module::new(Behavior::TrafficSignal), Policy::Optional),
    (Module::new(Behavior::StopSign), Policy::Required),
    (Module::new(Behavior::NoStoppingArea), Policy::Optional),
    (Module::new(Behavior::Merge), Policy::Required),
];

/// A module that is never configured: inputs naming it explore the "no policy" rejections.
pub const STRANGER: Module = Module::new(Behavior::RunOut);

/// The size of a model: how many modules and identifiers, and the core's limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Bounds {
    /// Configured modules (1 to 8), alternately optional and required by default.
    pub modules: usize,
    /// Scene identifiers, `1..=scenes`.
    pub scenes: usize,
    /// The live-scene limit (`max_scenes`).
    pub live: usize,
    /// The retired capacity.
    pub retired: usize,
}

impl Bounds {
    /// `modules` modules and `scenes` identifiers, at most `scenes - 1` live (so the scene limit
    /// is reachable), and room to remember every retired identifier.
    #[must_use]
    pub fn new(modules: usize, scenes: usize) -> Self {
        Self {
            modules,
            scenes,
            live: scenes.saturating_sub(1).max(1),
            retired: scenes,
        }
    }
}

/// The sequential model of the cooperation core.
#[derive(Clone, Debug)]
pub struct SequentialModel {
    bounds: Bounds,
    fault: Option<Fault>,
    focus: Option<&'static str>,
    halt: Halt,
    table: TableLayout,
    merge_stalled: bool,
    canonical: bool,
    config: Config,
    alphabet: Vec<Input>,
    tables: Tables,
}

impl SequentialModel {
    /// The model at these bounds.
    ///
    /// # Errors
    /// If a bound is out of range or the spec's table cannot be read.
    pub fn new(bounds: Bounds) -> Result<Self, ModelError> {
        let Bounds {
            modules,
            scenes,
            live,
            retired,
        } = bounds;
        if !(1..=MODULES.len()).contains(&modules) {
            return Err(ModelError::Bounds(format!(
                "modules must be 1 to {}",
                MODULES.len()
            )));
        }
        if !(1..=MAX_SCENES).contains(&scenes) {
            return Err(ModelError::Bounds(format!(
                "scenes must be 1 to {MAX_SCENES}"
            )));
        }
        if live == 0 || retired == 0 {
            return Err(ModelError::Bounds(
                "the live and retired limits must be at least 1".into(),
            ));
        }
        let config = Config {
            policies: MODULES.iter().take(modules).copied().collect(),
            limits: Limits {
                ttl_ms: 1,
                max_scenes: live,
                retired_capacity: retired,
                max_batch: 2,
            },
        };
        let ids: Vec<SceneId> = (1..=scenes as u128).map(SceneId::from_u128).collect();
        let tables = Tables::from_spec(SPEC).map_err(ModelError::Table)?;
        let alphabet = alphabet(&config, &ids);
        Ok(Self {
            bounds,
            fault: None,
            focus: None,
            halt: Halt::new(),
            table: TableLayout::Adaptive,
            merge_stalled: true,
            canonical: false,
            config,
            alphabet,
            tables,
        })
    }

    /// The same model with a deliberately wrong behaviour injected (sensitivity tests only).
    #[must_use]
    pub fn with_fault(mut self, fault: Fault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The same model checking only the named property (for the shortest counterexample).
    #[must_use]
    pub fn focus(mut self, property: &'static str) -> Self {
        self.focus = Some(property);
        self
    }

    /// The same model with the core's live scenes laid out as `table` says: with
    /// [`TableLayout::Colliding`], every state's table is hashed from its first scene, so the
    /// check explores the shipped hash index (probing, wrap-around deletion, rebuilds). The
    /// layout is invisible to `Eq` and `Hash`, so the counts equal the default layout's.
    #[must_use]
    pub fn with_table(mut self, table: TableLayout) -> Self {
        self.table = table;
        self
    }

    /// The same model keeping every stalled step as a state of its own (`merge` false), instead
    /// of one per rule (the default; see [`Step`]): the unreduced search, for cross-checking
    /// the reduction.
    #[must_use]
    pub fn with_stalled_merged(mut self, merge: bool) -> Self {
        self.merge_stalled = merge;
        self
    }

    /// The layout of the core's scene table.
    #[must_use]
    pub const fn table(&self) -> TableLayout {
        self.table
    }

    /// The same model, stopped by `halt` (see [`crate::check::budget`]).
    #[must_use]
    pub fn with_halt(mut self, halt: Halt) -> Self {
        self.halt = halt;
        self
    }

    /// The bounds.
    #[must_use]
    pub const fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// The injected fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<Fault> {
        self.fault
    }

    /// The core's configuration in this model.
    #[must_use]
    pub const fn config(&self) -> &Config {
        &self.config
    }

    /// Every input the model tries in every state.
    #[must_use]
    pub fn alphabet(&self) -> &[Input] {
        &self.alphabet
    }

    /// The transition under check: the library's `State::after` (`State::apply` on a copy of
    /// `core`, made only for an accepted input), or the faulty wrapper around `apply`. Gives the
    /// state the input left (`core` itself when it was refused), and the result.
    pub fn transition<'a>(
        &self,
        core: &'a State,
        input: &Input,
    ) -> (Cow<'a, State>, Result<Transition, Rejection>) {
        crate::model::fault::transition(self.fault, core, input)
    }

    /// The merged decision under check: `State::merged_decision`, or the faulty wrapper.
    #[must_use]
    pub fn merged_decision(&self, core: &State, id: SceneId) -> Option<Decision> {
        match self.fault {
            None => core.merged_decision(id),
            Some(fault) => fault.merged_decision(core, id),
        }
    }

    /// The state the model starts in.
    ///
    /// # Errors
    /// If the configuration is refused (never, for valid bounds).
    pub fn initial(&self) -> Result<Step, cooperation::ConfigError> {
        let core = Arc::new(State::new(self.config.clone())?.with_table_layout(self.table));
        let order_matters = self.bounds.retired < self.bounds.scenes;
        Ok(Step::new(
            core,
            None,
            Ghost::default(),
            false,
            (order_matters, self.merge_stalled),
        ))
    }

    /// Every step of a path of inputs, the initial state first.
    ///
    /// # Errors
    /// If the configuration is refused (never, for valid bounds).
    pub fn replay(&self, inputs: &[Input]) -> Result<Vec<Step>, ModelError> {
        let first = self
            .initial()
            .map_err(|e| ModelError::Bounds(e.to_string()))?;
        let mut steps = vec![first];
        for input in inputs {
            let next = steps.last().map(|last| self.step(last, input));
            steps.extend(next);
        }
        Ok(steps)
    }

    /// The next step: apply `input`, then record what happened and whether it is what the
    /// spec's rules say.
    #[must_use]
    pub fn step(&self, from: &Step, input: &Input) -> Step {
        match self.outcome(from, input) {
            Outcome::Stalled(rule) => Step::stalled_after(from, rule),
            Outcome::Moved(next) => next,
        }
    }

    /// What [`step`](Self::step) gives, a stalled step told by its rule alone, so that a
    /// caller that drops it has built nothing.
    fn outcome(&self, from: &Step, input: &Input) -> Outcome {
        let (core, result) = self.transition(&from.core, input);
        let rule = match &result {
            Ok(transition) => transition.rule,
            Err(rejection) => rejection.rule(),
        };
        // Compared once: the spec's check of a rejection and the stall below both need it. A
        // refused input gives `core` itself back, unless a fault copied it.
        let unchanged = match &core {
            Cow::Borrowed(_) => true,
            Cow::Owned(next) => *next == *from.core,
        };
        let departures = against_spec(&self.tables, from, input, (&result, &core, unchanged));
        if unchanged {
            // Nothing changed; only a departure from the spec is news.
            let mut ghost = from.ghost;
            ghost.broken = ghost.broken.and(departures);
            if ghost == from.ghost {
                return Outcome::Stalled(rule);
            }
            let core = Arc::clone(&from.core);
            return Outcome::Moved(Step::new(core, Some(rule), ghost, false, from.settings()));
        }
        let mut ghost = observe(from, input, &result, &core);
        ghost.broken = ghost.broken.and(departures);
        Outcome::Moved(Step::new(
            Arc::new(core.into_owned()),
            Some(rule),
            ghost,
            false,
            from.settings(),
        ))
    }
}

/// What an input did to a step: nothing but fire `rule` (a stalled step), or the step it led to.
enum Outcome {
    Stalled(Rule),
    Moved(Step),
}

/// An action of the model: the position of an input in [`SequentialModel::alphabet`].
pub type Action = usize;

impl SequentialModel {
    /// The step input `action` leads to from `from` (in canonical form when the model says so),
    /// stalled or not; `None` only for a position outside the alphabet. What the coverage
    /// search and the tests walk with: the checker's
    /// [`next_state`](stateright::Model::next_state) leaves out the stalled steps it has been
    /// handed already.
    #[must_use]
    pub fn next_step(&self, from: &Step, action: Action) -> Option<Step> {
        self.alphabet
            .get(action)
            .map(|input| self.successor(from, input))
    }
}

impl Model for SequentialModel {
    type State = Step;
    type Action = Action;

    fn init_states(&self) -> Vec<Step> {
        self.initial().into_iter().collect()
    }

    fn actions(&self, step: &Step, actions: &mut Vec<Action>) {
        if self.halt.is_set() {
            return;
        }
        // A step that changed nothing is a dead end: its predecessor, equal to it but for the
        // rule just recorded, is expanded already.
        if !step.stalled {
            actions.extend(0..self.alphabet.len());
        }
    }

    fn within_boundary(&self, _: &Step) -> bool {
        !self.halt.is_set()
    }

    /// The step [`next_step`](SequentialModel::next_step) gives, except a merged stalled step
    /// after the first of its rule among `from`'s inputs: that is a state the checker was
    /// handed already, so it is not handed again ([`Step`], *stalled steps*).
    fn next_state(&self, from: &Step, action: Action) -> Option<Step> {
        let next = match self.outcome(from, self.alphabet.get(action)?) {
            Outcome::Stalled(rule) if from.merge_stalled && !from.first_stall(rule, action) => {
                return None;
            }
            Outcome::Stalled(rule) => Step::stalled_after(from, rule),
            Outcome::Moved(next) => next,
        };
        Some(self.in_form(next))
    }

    fn format_action(&self, action: &Action) -> String {
        self.alphabet.get(*action).map_or_else(
            || format!("input #{action}"),
            crate::model::describe::describe,
        )
    }

    fn properties(&self) -> Vec<Property<Self>> {
        let mut all = properties();
        // Reading a state back, whole and corrupted three ways, costs about 15 µs a state, most
        // of the time again on the two-module configurations; one module exercises the same
        // serialized form and the same invariant checks.
        if self.bounds.modules > 1 {
            all.retain(|p| p.name != properties::SERIALIZES);
        }
        if let Some(focus) = self.focus {
            all.retain(|p| p.name == focus);
        }
        all
    }
}
