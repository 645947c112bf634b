//! The RTC model: the library's RTC compatibility adapter (`cooperation_adapters::rtc`) over the core,
//! every interleaving of its calls over a few interfaces and scene identifiers.
//!
//! `next_state` makes one call of the adapter ([`RtcModel::invoke`]: `update_cooperate_status`,
//! `remove_cooperate_status`, `clear_cooperate_status`, the interfaces' and the external API's
//! `cooperate_commands`, `auto_mode`, `auto_mode_with_module`, `tick`; beside them, the AD
//! API's `set_policies` for a module of an interface bound to several sequences) on a copy of
//! the core's state and the adapter's, unless an [`RtcFault`] is injected for a sensitivity
//! test. No guard,
//! table or rule of the specification is restated here. It then records what the call answered
//! ([`Outcome`]) and, as sticky flags, which step properties the step broke ([`Broken`]); the
//! properties ([`properties`]) are stated from the specification's §5, §6 and §9 and from
//! upstream's own test answers.
//!
//! A state ([`RtcStep`]) is the core's `State` and the adapter's `Rtc` (its bindings and
//! routes), the last call's [`Outcome`], the interface whose status update registered each
//! remembered identifier (as the model saw it), the sticky flags, and an injected fault's
//! memory. A call that changes nothing leaves a stalled leaf that is not expanded again. The
//! alphabet ([`alphabet`]) is fixed and closed under renaming identifiers, so depth-first
//! search with symmetry reduction applies: a state's representative hashes its identifiers'
//! signatures sorted, which is canonical, so the count is the same with any number of threads.

mod call;
mod fault;
mod observe;
mod properties;
mod render;
mod step;

use std::sync::Arc;

use cooperation::{Config, Input, Limits, Module, PolicySetting, SceneId, State};
use cooperation_adapters::rtc::{
    self, AutoModeRequest, AutoModeWithModuleRequest, Binding, Rtc, View,
};
use serde::{Deserialize, Serialize};
use stateright::{Model, Property};

use crate::check::budget::Halt;
use crate::model::ids::{ModelError, MAX_SMALL_SCENES};

pub use call::{
    alphabet, describe, request, state_name, Call, Order, FINISH_DISTANCE, START_DISTANCE,
    UNBOUND_MODULE, UNDEFINED_COMMAND, UNDEFINED_MODULE, UNDEFINED_STATE,
};
pub use fault::RtcFault;
pub use observe::Said;
pub use properties::{properties, properties_for};
pub use render::answer;
pub use step::{Answer, Broken, Interface, Kind, Outcome, Refusal, RtcStep};

/// The interfaces a model draws from, in order: `interfaces` of these, from
/// `first_interface`. The two lane changes share one core module (`lane-change`), so only the
/// adapter's routes keep their scenes apart; the intersection is a module of its own; the two
/// avoidances are each bound to two modules (`avoidance/change` and `avoidance/return`), the
/// same two, so their owner states each scene's sequence, the two sequences can have different
/// policies, and again only the routes keep the interfaces' scenes apart.
pub const INTERFACES: [&str; 5] = [
    "lane_change_left",
    "lane_change_right",
    "intersection",
    "static_obstacle_avoidance_left",
    "static_obstacle_avoidance_right",
];

/// The position in [`INTERFACES`] of the first avoidance interface.
pub const AVOIDANCE: usize = 3;

/// The core modules a binding declares its scenes may belong to, from its fields (the model's
/// own reading, not the adapter's `Binding::modules`).
#[must_use]
pub fn modules_of(binding: &Binding) -> Vec<Module> {
    binding
        .sequences
        .iter()
        .map(|sequence| Module::with_sequence(binding.behavior, *sequence))
        .collect()
}

/// The size of an RTC model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RtcBounds {
    /// How many interfaces: [`INTERFACES`] from `first_interface`.
    pub interfaces: usize,
    /// The position in [`INTERFACES`] of the first interface (0, the first lane change, unless
    /// said).
    #[serde(default)]
    pub first_interface: usize,
    /// Scene identifiers, `1..=scenes`, shared by the interfaces.
    pub scenes: usize,
    /// The live-scene limit (`max_scenes`).
    pub live: usize,
    /// The retired capacity.
    pub retired: usize,
    /// The adapter's quota of live scenes per interface, if it has one
    /// (`Rtc::with_scene_quota`, `[COOP-DEV-QUOTA.1]`).
    #[serde(default)]
    pub quota: Option<usize>,
}

impl RtcBounds {
    /// `interfaces` interfaces and `scenes` identifiers, at most `scenes - 1` live (so the
    /// scene limit is reachable), and room to remember every retired identifier.
    #[must_use]
    pub fn new(interfaces: usize, scenes: usize) -> Self {
        Self {
            interfaces,
            first_interface: 0,
            scenes,
            live: scenes.saturating_sub(1).max(1),
            retired: scenes,
            quota: None,
        }
    }

    /// The same bounds, drawing the interfaces from position `first` of [`INTERFACES`].
    #[must_use]
    pub const fn from_interface(mut self, first: usize) -> Self {
        self.first_interface = first;
        self
    }
}

/// The adapter as the library ships it, over `bindings`, with the quota if there is one.
fn adapter(bindings: &[Binding], quota: Option<usize>) -> Result<Rtc, ModelError> {
    let rtc = Rtc::new(bindings.to_vec()).map_err(|e| ModelError::Bounds(e.to_string()))?;
    Ok(match quota {
        Some(quota) => rtc.with_scene_quota(quota),
        None => rtc,
    })
}

/// The RTC model.
#[derive(Clone, Debug)]
pub struct RtcModel {
    bounds: RtcBounds,
    fault: Option<RtcFault>,
    focus: Option<&'static str>,
    halt: Halt,
    bindings: Vec<Binding>,
    names: Vec<String>,
    ids: Vec<SceneId>,
    config: Config,
    alphabet: Vec<Call>,
}

impl RtcModel {
    /// The model at these bounds. The core starts with every module's policy optional
    /// (upstream's `enable_rtc = false`: auto mode on), a time-to-live of 1 ms and a batch
    /// limit of 2.
    ///
    /// # Errors
    /// If a bound is out of range.
    pub fn new(bounds: RtcBounds) -> Result<Self, ModelError> {
        let RtcBounds {
            interfaces,
            first_interface,
            scenes,
            live,
            retired,
            quota,
        } = bounds;
        let most = INTERFACES.len().saturating_sub(first_interface);
        if !(1..=most).contains(&interfaces) {
            return Err(ModelError::Bounds(format!(
                "interfaces must be 1 to {most} from interface {first_interface} of {}",
                INTERFACES.len()
            )));
        }
        if !(1..=MAX_SMALL_SCENES).contains(&scenes) {
            return Err(ModelError::Bounds(format!(
                "scenes must be 1 to {MAX_SMALL_SCENES}"
            )));
        }
        if live == 0 || retired == 0 || quota == Some(0) {
            return Err(ModelError::Bounds(
                "the live and retired limits and the quota must be at least 1".into(),
            ));
        }
        // Upstream's interfaces, as the adapter ships them, by name.
        let standard = Rtc::standard();
        let bindings: Vec<Binding> = INTERFACES
            .iter()
            .skip(first_interface)
            .take(interfaces)
            .filter_map(|name| {
                standard
                    .bindings()
                    .iter()
                    .find(|b| b.name == *name)
                    .cloned()
            })
            .collect();
        let rtc = adapter(&bindings, quota)?;
        let limits = Limits {
            ttl_ms: 1,
            max_scenes: live,
            retired_capacity: retired,
            max_batch: 2,
        };
        let config = Config {
            policies: rtc.policies(false),
            limits,
        };
        let ids: Vec<SceneId> = (1..=scenes as u128).map(SceneId::from_u128).collect();
        let alphabet = alphabet(&bindings, &ids, limits.max_batch);
        let names = bindings.iter().map(|b| b.name.clone()).collect();
        Ok(Self {
            bounds,
            fault: None,
            focus: None,
            halt: Halt::new(),
            bindings,
            names,
            ids,
            config,
            alphabet,
        })
    }

    /// The same model with a deliberately wrong adapter (sensitivity tests only).
    #[must_use]
    pub const fn with_fault(mut self, fault: RtcFault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The same model checking only the named property (for the shortest counterexample).
    #[must_use]
    pub const fn focus(mut self, property: &'static str) -> Self {
        self.focus = Some(property);
        self
    }

    /// The same model, stopped by `halt` (see [`crate::check::budget`]).
    #[must_use]
    pub fn with_halt(mut self, halt: Halt) -> Self {
        self.halt = halt;
        self
    }

    /// The bounds.
    #[must_use]
    pub const fn bounds(&self) -> RtcBounds {
        self.bounds
    }

    /// The injected fault, if any.
    #[must_use]
    pub const fn fault(&self) -> Option<RtcFault> {
        self.fault
    }

    /// Every call the model tries in every state.
    #[must_use]
    pub fn alphabet(&self) -> &[Call] {
        &self.alphabet
    }

    /// The scene identifiers.
    #[must_use]
    pub fn ids(&self) -> &[SceneId] {
        &self.ids
    }

    /// The interfaces' bindings.
    #[must_use]
    pub fn bindings(&self) -> &[Binding] {
        &self.bindings
    }

    /// The interfaces' names.
    #[must_use]
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Interface `interface`'s binding.
    #[must_use]
    pub fn binding(&self, interface: usize) -> Option<&Binding> {
        self.bindings.get(interface)
    }

    /// Interface `interface` of a step, to query.
    #[must_use]
    pub fn view<'a>(&'a self, step: &'a RtcStep, interface: usize) -> Option<View<'a>> {
        let name = self.names.get(interface)?;
        step.rtc.view(&step.core, name).ok()
    }

    /// The state the model starts in.
    ///
    /// # Errors
    /// If the configuration is refused (never, for valid bounds).
    pub fn initial(&self) -> Result<RtcStep, ModelError> {
        let core =
            State::new(self.config.clone()).map_err(|e| ModelError::Bounds(e.to_string()))?;
        let rtc = adapter(&self.bindings, self.bounds.quota)?;
        let order_matters = self.bounds.retired < self.bounds.scenes;
        Ok(RtcStep::new(Arc::new(core), Arc::new(rtc), order_matters))
    }

    /// The adapter's call, as the library ships it.
    pub fn invoke(&self, core: &mut State, rtc: &mut Rtc, call: &Call) -> Said {
        let kind = kind(call);
        let name = |interface: &usize| self.names.get(*interface).map_or("", String::as_str);
        match call {
            Call::Update {
                interface,
                id,
                sequence,
                safe,
                state,
                requested,
            } => {
                // As an owner's status message arrives: read into a report (an undefined
                // state is refused there), then reported through the interface.
                let status = rtc::CooperateStatus {
                    uuid: (*id).into(),
                    safe: *safe,
                    requested: *requested,
                    state: rtc::Lifecycle::new(*state),
                    start_distance: START_DISTANCE,
                    finish_distance: FINISH_DISTANCE,
                    ..rtc::CooperateStatus::default()
                };
                let result = rtc.interface(core, name(interface)).and_then(|mut it| {
                    let report = status.report()?;
                    let report = match sequence {
                        Some(sequence) => report.in_sequence(*sequence),
                        None => report,
                    };
                    it.update_cooperate_status(&report)
                });
                Said::transitions(kind, result)
            }
            Call::Remove { interface, id } => {
                let result = rtc
                    .interface(core, name(interface))
                    .and_then(|mut it| it.remove_cooperate_status(*id));
                Said::transitions(kind, result)
            }
            Call::Clear { interface } => {
                match rtc
                    .interface(core, name(interface))
                    .and_then(|mut it| it.clear_cooperate_status())
                {
                    Ok(ids) => {
                        let count = u8::try_from(ids.len()).unwrap_or(u8::MAX);
                        let mut said = Said::of(kind, Answer::Cleared(count));
                        said.ids = ids;
                        said
                    }
                    Err(error) => Said::refused(kind, &error),
                }
            }
            Call::Commands {
                interface: Some(interface),
                orders,
            } => match rtc.interface(core, name(interface)) {
                Ok(mut it) => Said::commands(kind, it.cooperate_commands(&request(orders))),
                Err(error) => Said::refused(kind, &error),
            },
            Call::Commands {
                interface: None,
                orders,
            } => Said::commands(kind, rtc.cooperate_commands(core, &request(orders))),
            Call::AutoMode { interface, enable } => match rtc.interface(core, name(interface)) {
                Ok(mut it) => {
                    let reply = it.auto_mode(&AutoModeRequest { enable: *enable });
                    Said::auto_mode(kind, reply.result, reply.response.success)
                }
                Err(error) => Said::refused(kind, &error),
            },
            Call::AutoModeWithModule { module, enable } => {
                let reply = rtc.auto_mode_with_module(
                    core,
                    &AutoModeWithModuleRequest {
                        module: cooperation_adapters::rtc::Module::new(*module),
                        enable: *enable,
                    },
                );
                Said::auto_mode(kind, reply.result, reply.response.success)
            }
            Call::Tick => Said::transitions(kind, rtc.tick(core, 1)),
            Call::SetPolicy { module, policy } => {
                let policies = vec![PolicySetting {
                    module: *module,
                    policy: *policy,
                }];
                let result = core.apply(&Input::SetPolicies { policies });
                Said::transitions(kind, result.map_err(Into::into))
            }
        }
    }

    /// The next step: make the call (through the fault, if one is injected), then record what
    /// it answered and what it did.
    #[must_use]
    pub fn step(&self, from: &RtcStep, call: &Call) -> RtcStep {
        let mut core = State::clone(&from.core);
        let mut rtc = Rtc::clone(&from.rtc);
        let mut stash = from.stash.clone();
        let said = match self.fault {
            None => self.invoke(&mut core, &mut rtc, call),
            Some(fault) => fault.invoke(self, &mut core, &mut rtc, &mut stash, call),
        };
        let mut next = from.successor(core, rtc, stash, said.outcome);
        observe::observe(self, from, call, &said, &mut next);
        next.settle(from);
        next
    }

    /// Every step of a path of calls, the initial state first.
    ///
    /// # Errors
    /// If the configuration is refused (never, for valid bounds).
    pub fn replay(&self, calls: &[Call]) -> Result<Vec<RtcStep>, ModelError> {
        let mut steps = vec![self.initial()?];
        for call in calls {
            let next = steps.last().map(|last| self.step(last, call));
            steps.extend(next);
        }
        Ok(steps)
    }

    /// Whether the model has an interface bound to several sequences.
    #[must_use]
    pub fn has_sequences(&self) -> bool {
        self.bindings.iter().any(|b| b.sequences.len() > 1)
    }

    /// The core modules an auto-mode call asks to switch: every module of the interface, or of
    /// every interface reporting the module type (`[COOP-DEV-SEQUENCE.1]`).
    #[must_use]
    pub fn switched_modules(&self, call: &Call) -> Vec<Module> {
        let mut modules: Vec<Module> = match call {
            Call::AutoMode { interface, .. } => {
                self.binding(*interface).map(modules_of).unwrap_or_default()
            }
            Call::AutoModeWithModule { module, .. } => self
                .bindings
                .iter()
                .filter(|b| {
                    cooperation_adapters::rtc::Module::from(b.module_type).r#type == *module
                })
                .flat_map(modules_of)
                .collect(),
            _ => Vec::new(),
        };
        modules.sort_unstable();
        modules.dedup();
        modules
    }

    /// Whether an accepted auto-mode call set the policy of every module it names to what it
    /// asked and left every other module's, and switched the auto-mode status of every
    /// interface all of whose modules it names, leaving that of every interface none of whose
    /// modules it names (`[COOP-DEV-AUTO-MODE-KEY.1]`, `[COOP-DEV-ROUTING.1]`,
    /// `[COOP-DEV-SEQUENCE.1]`).
    fn switched_as_asked(&self, from: &RtcStep, call: &Call, to: &RtcStep) -> bool {
        let enable = match call {
            Call::AutoMode { enable, .. } | Call::AutoModeWithModule { enable, .. } => *enable,
            _ => return true,
        };
        let modules = self.switched_modules(call);
        let asked = cooperation_adapters::rtc::policy_for_auto_mode(enable);
        let policies = to.core.policies().all(|setting| {
            let expected = if modules.contains(&setting.module) {
                Some(asked)
            } else {
                from.core.policy(setting.module)
            };
            Some(setting.policy) == expected
        });
        let auto = |step: &RtcStep, j: usize| {
            self.view(step, j)
                .map(|view| view.auto_mode_status().is_auto_mode)
        };
        !modules.is_empty()
            && policies
            && self.bindings.iter().enumerate().all(|(j, binding)| {
                let own = modules_of(binding);
                if own.iter().all(|m| modules.contains(m)) {
                    auto(to, j) == Some(enable)
                } else if own.iter().all(|m| !modules.contains(m)) {
                    auto(to, j) == auto(from, j)
                } else {
                    true
                }
            })
    }
}

/// The kind of a call.
const fn kind(call: &Call) -> Kind {
    match call {
        Call::Update { .. } => Kind::Update,
        Call::Remove { .. } => Kind::Remove,
        Call::Clear { .. } => Kind::Clear,
        Call::Commands {
            interface: Some(_), ..
        } => Kind::Commands,
        Call::Commands {
            interface: None, ..
        } => Kind::ExternalCommands,
        Call::AutoMode { .. } => Kind::AutoMode,
        Call::AutoModeWithModule { .. } => Kind::AutoModeWithModule,
        Call::Tick => Kind::Tick,
        Call::SetPolicy { .. } => Kind::SetPolicy,
    }
}

impl Model for RtcModel {
    type State = RtcStep;
    type Action = usize;

    fn init_states(&self) -> Vec<RtcStep> {
        self.initial().into_iter().collect()
    }

    fn actions(&self, step: &RtcStep, actions: &mut Vec<usize>) {
        if self.halt.is_set() {
            return;
        }
        // A step that changed nothing is a dead end: its predecessor, equal to it but for the
        // outcome just recorded, is expanded already.
        if !step.stalled {
            actions.extend(0..self.alphabet.len());
        }
    }

    fn within_boundary(&self, _: &RtcStep) -> bool {
        !self.halt.is_set()
    }

    fn next_state(&self, from: &RtcStep, action: usize) -> Option<RtcStep> {
        self.alphabet.get(action).map(|call| self.step(from, call))
    }

    fn format_action(&self, action: &usize) -> String {
        self.alphabet.get(*action).map_or_else(
            || format!("call #{action}"),
            |call| describe(call, &self.names),
        )
    }

    fn properties(&self) -> Vec<Property<Self>> {
        let mut all = properties_for(self.has_sequences(), self.bounds.quota.is_some());
        if let Some(focus) = self.focus {
            all.retain(|p| p.name == focus);
        }
        all
    }
}
