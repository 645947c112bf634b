//! The RTC interfaces, answered from the core: every call converts its arguments, sends the core
//! an input or asks it a query, and converts the answer back.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

use cooperation::{
    Decision, Distance, Input, Module, OperatorDecision, Policy, PolicySetting, Scene, SceneId,
    Transition,
};

use super::binding::distances;
use super::{
    AutoModeStatus, AutoModeStatusArray, AutoModeWithModuleRequest, AutoModeWithModuleResponse,
    Binding, Command, CooperateCommandsRequest, CooperateCommandsResponse, CooperateStatus,
    CooperateStatusArray, RtcError,
};
use crate::Time;

/// The policy an auto-mode switch stands for: on (scenes proceed without approval) is
/// `optional`, off (they wait for the operator) is `required`.
#[must_use]
pub const fn policy_for_auto_mode(enable: bool) -> Policy {
    if enable {
        Policy::Optional
    } else {
        Policy::Required
    }
}

/// A service's wire response together with what the core did: the transition, or the typed
/// reason nothing changed. Upstream sends the response and logs the reason; here the caller
/// gets both (`[COOP-DEV-SILENT-DROP.1]`).
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Reply<T> {
    /// The response to send.
    pub response: T,
    /// The transition the call made, or why it made none.
    pub result: Result<Transition, RtcError>,
}

/// One of an adapter's interfaces, found by name once ([`Rtc::find`]), so that a caller making
/// many calls through it (a planning module, each cycle) does not search the bindings by name
/// each time.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct InterfaceId(usize);

/// The RTC interfaces of a planner, over a core [`State`](cooperation::State) that the caller owns.
///
/// It holds the interfaces' [`Binding`]s and, for each scene registered through one, which
/// interface that was: routing, as upstream's separate per-interface registries route. It holds
/// no decision, command, auto mode, phase or time: every answer is a core query and every
/// change a core input.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Rtc {
    /// The bindings, fixed when the adapter is made and shared by its copies (a model checker
    /// copies a host for every transition; the routes are all a copy needs of its own).
    bindings: Arc<[Binding]>,
    /// Each binding's core modules, listed once when the adapter is made: every call checks
    /// that the core has a policy for each, and reads them here rather than building them.
    /// Shared by copies, as the bindings are.
    modules: Arc<[Box<[Module]>]>,
    /// The interface (index into `bindings`) each scene registered through, and each
    /// interface's scenes. Entries for identifiers the core no longer remembers are pruned when
    /// they could outnumber the live and retired identifiers.
    routes: Routes,
    /// At most this many live scenes per interface, if set ([`Rtc::with_scene_quota`]).
    quota: Option<usize>,
}

impl Default for Rtc {
    /// [`Rtc::standard`].
    fn default() -> Self {
        Self::standard()
    }
}

/// The live scenes each RTC interface of a node may hold unless told otherwise
/// ([`Rtc::with_scene_quota`]): the default of both nodes' `--scene-quota` and of the C++ class.
/// The core's default table (4,096 live scenes) shared by the 19 standard interfaces, so that
/// their quotas together never fill it (`engine::EngineError::QuotaOverTable`).
pub const SCENE_QUOTA: usize = 215;

impl Rtc {
    /// Interfaces with these bindings.
    ///
    /// # Errors
    /// [`RtcError::DuplicateInterface`] if two bindings have the same name;
    /// [`RtcError::NoSequence`] if a binding has no sequence.
    pub fn new(bindings: impl IntoIterator<Item = Binding>) -> Result<Self, RtcError> {
        let bindings: Vec<Binding> = bindings.into_iter().collect();
        let mut names = BTreeSet::new();
        for binding in &bindings {
            if !names.insert(binding.name.as_str()) {
                return Err(RtcError::DuplicateInterface {
                    name: binding.name.clone(),
                });
            }
            if binding.sequences.is_empty() {
                return Err(RtcError::NoSequence {
                    name: binding.name.clone(),
                });
            }
        }
        Ok(Self::checked(bindings))
    }

    /// The interfaces of [`Binding::standard`].
    #[must_use]
    pub fn standard() -> Self {
        Self::checked(Binding::standard())
    }

    /// Interfaces with `bindings`, already checked as [`new`](Self::new) checks them.
    fn checked(bindings: Vec<Binding>) -> Self {
        let modules = bindings
            .iter()
            .map(|binding| binding.modules().collect())
            .collect();
        Self {
            routes: Routes::new(bindings.len()),
            bindings: bindings.into(),
            modules,
            quota: None,
        }
    }

    /// The same interfaces, each holding at most `quota` live scenes: a report of a new scene
    /// through an interface that holds as many is refused ([`RtcError::SceneQuota`]), so one
    /// module cannot fill the core's table ([`Limits::max_scenes`](cooperation::Limits)) and
    /// lock the others out. Upstream has no such limit.
    #[must_use]
    pub const fn with_scene_quota(mut self, quota: usize) -> Self {
        self.quota = Some(quota);
        self
    }

    /// The quota of live scenes per interface, if set.
    #[must_use]
    pub const fn scene_quota(&self) -> Option<usize> {
        self.quota
    }

    /// The bindings, in the order given.
    #[must_use]
    pub fn bindings(&self) -> &[Binding] {
        &self.bindings
    }

    /// Every bound core module (each sequence of each binding) with the policy upstream's
    /// `enable_rtc` flag stands for: `false` (auto mode on) is `optional`, `true` is `required`.
    /// For [`Config::new`](cooperation::Config::new).
    #[must_use]
    pub fn policies(&self, enable_rtc: bool) -> BTreeMap<Module, Policy> {
        self.bindings
            .iter()
            .flat_map(Binding::modules)
            .map(|module| (module, policy_for_auto_mode(!enable_rtc)))
            .collect()
    }

    /// The interface named `name`, found once: calls made with the id
    /// ([`interface_at`](Self::interface_at), [`view_at`](Self::view_at)) skip the search by
    /// name. The bindings never change after the adapter is made, so the id stays good for as
    /// long as the adapter lives.
    ///
    /// # Errors
    /// [`RtcError::UnknownInterface`] if no binding has the name (`[COOP-DEV-INTERFACE-NAME.1]`).
    pub fn find(&self, name: &str) -> Result<InterfaceId, RtcError> {
        // [COOP-DEV-INTERFACE-NAME.1]
        self.bindings
            .iter()
            .position(|binding| binding.name == name)
            .map(InterfaceId)
            .ok_or_else(|| RtcError::UnknownInterface {
                name: name.to_owned(),
            })
    }

    /// The interface named `name`, to change the core through: [`find`](Self::find), then
    /// [`interface_at`](Self::interface_at).
    ///
    /// # Errors
    /// As those two.
    pub fn interface<'a>(
        &'a mut self,
        state: &'a mut cooperation::State,
        name: &str,
    ) -> Result<Interface<'a>, RtcError> {
        let id = self.find(name)?;
        self.interface_at(state, id)
    }

    /// The interface `id`, to change the core through.
    ///
    /// # Errors
    /// [`RtcError::Unconfigured`] if the core has no policy for one of its modules;
    /// [`RtcError::UnknownInterface`] if `id` was found on an adapter with more bindings.
    pub fn interface_at<'a>(
        &'a mut self,
        state: &'a mut cooperation::State,
        id: InterfaceId,
    ) -> Result<Interface<'a>, RtcError> {
        let Self {
            bindings,
            modules,
            routes,
            quota,
        } = self;
        let bindings: &'a [Binding] = bindings;
        let (binding, _) = configured(bindings, modules, state, id)?;
        routes.settle(state);
        Ok(Interface {
            bindings,
            binding,
            index: id.0,
            routes,
            state,
            quota: *quota,
        })
    }

    /// The interface named `name`, to query: [`find`](Self::find), then
    /// [`view_at`](Self::view_at).
    ///
    /// # Errors
    /// As those two.
    pub fn view<'a>(
        &'a self,
        state: &'a cooperation::State,
        name: &str,
    ) -> Result<View<'a>, RtcError> {
        self.view_at(state, self.find(name)?)
    }

    /// The interface `id`, to query.
    ///
    /// # Errors
    /// As [`interface_at`](Self::interface_at).
    pub fn view_at<'a>(
        &'a self,
        state: &'a cooperation::State,
        id: InterfaceId,
    ) -> Result<View<'a>, RtcError> {
        let (binding, module_policy) = configured(&self.bindings, &self.modules, state, id)?;
        Ok(View {
            bindings: &self.bindings,
            binding,
            index: id.0,
            routes: &self.routes,
            state,
            module_policy,
        })
    }

    /// The binding of the interface a scene registered through, while the core remembers it.
    #[must_use]
    pub fn owner(&self, state: &cooperation::State, id: SceneId) -> Option<&Binding> {
        let remembered = state.scene(id).is_some() || state.retirement(id).is_some();
        let index = *self.routes.get(&id)?;
        remembered.then(|| self.bindings.get(index)).flatten()
    }

    /// How many identifiers the adapter keeps a route for. Routes of identifiers the core has
    /// forgotten are pruned, so this never exceeds what the core can remember plus one
    /// (`Limits::max_scenes + Limits::retired_capacity + 1`): the adapter's memory is bounded
    /// as the core's is.
    #[must_use]
    pub fn route_count(&self) -> usize {
        self.routes.len()
    }

    /// Time passed: the core's `Tick`. Upstream's `removeExpiredCooperateStatus` compares each
    /// status's stamp with a clock; here the caller says how much time passed, and the
    /// transition lists the scenes that expired (`[COOP-DEV-EXPIRY.1]`).
    ///
    /// # Errors
    /// The core's rejection (a tick is never rejected today).
    pub fn tick(
        &mut self,
        state: &mut cooperation::State,
        elapsed_ms: u64,
    ) -> Result<Transition, RtcError> {
        let transition = state.apply(&Input::Tick { elapsed_ms })?;
        self.routes.retired([&transition]);
        self.routes.prune(state);
        Ok(transition)
    }

    /// The external API's `CooperateCommands` (upstream `/api/external/set/rtc_commands`), for
    /// scenes of every interface: commands are matched by identifier and every command is
    /// answered (`[COOP-DEV-ROUTING.1]`). The batch applies whole or not at all: each response
    /// is `success = true` exactly when it applied (`[COOP-DEV-BATCH.1]`).
    pub fn cooperate_commands(
        &mut self,
        state: &mut cooperation::State,
        request: &CooperateCommandsRequest,
    ) -> Reply<CooperateCommandsResponse> {
        apply_commands(state, request, |_, _| Ok(()))
    }

    /// The external API's `AutoModeWithModule` (upstream `/api/external/set/rtc_auto_mode`):
    /// the auto-mode switch of every interface whose statuses carry this module type, as the
    /// policies of their core modules, every sequence of each (`[COOP-DEV-ROUTING.1]`,
    /// `[COOP-DEV-AUTO-MODE-KEY.1]`, `[COOP-DEV-SEQUENCE.1]`).
    pub fn auto_mode_with_module(
        &mut self,
        state: &mut cooperation::State,
        request: &AutoModeWithModuleRequest,
    ) -> Reply<AutoModeWithModuleResponse> {
        let result = request
            .module
            .module_type()
            .map_err(|e| RtcError::from(e.within("module")))
            .and_then(|module_type| {
                let modules: BTreeSet<Module> = self
                    .bindings
                    .iter()
                    .filter(|binding| binding.module_type == module_type)
                    .flat_map(Binding::modules)
                    .collect();
                if modules.is_empty() {
                    return Err(RtcError::NoInterface {
                        module: module_type,
                    });
                }
                set_auto_mode(state, modules, request.enable)
            });
        Reply {
            response: AutoModeWithModuleResponse {
                success: result.is_ok(),
            },
            result,
        }
    }

    /// Every interface's live scenes as one array (upstream `/api/external/get/rtc_status`),
    /// nearest start first, then by identifier (`[COOP-DEV-ORDER.1]`).
    #[must_use]
    pub fn cooperate_status_array(
        &self,
        state: &cooperation::State,
        stamp: Time,
    ) -> CooperateStatusArray {
        let mut statuses: Vec<CooperateStatus> = state
            .scenes()
            .filter_map(|(id, scene)| {
                let binding = self.bindings.get(*self.routes.get(&id)?)?;
                let policy = || state.policy(scene.module());
                Some(cooperate_status(binding, id, scene, policy, stamp))
            })
            .collect();
        statuses.sort_by(|a, b| {
            Distance(a.start_distance)
                .total_cmp(&Distance(b.start_distance))
                .then(a.uuid.cmp(&b.uuid))
        });
        CooperateStatusArray { stamp, statuses }
    }

    /// Every interface's auto-mode status, in binding order (upstream
    /// `/api/external/get/rtc_auto_mode`).
    #[must_use]
    pub fn auto_mode_status_array(
        &self,
        state: &cooperation::State,
        stamp: Time,
    ) -> AutoModeStatusArray {
        AutoModeStatusArray {
            stamp,
            statuses: self
                .bindings
                .iter()
                .map(|binding| auto_mode_status(binding, state))
                .collect(),
        }
    }
}

/// A binding's module and that module's policy, where it binds one module (every binding but
/// the avoidances').
type ModulePolicy<'a> = Option<(&'a Module, Policy)>;

/// The binding `id`, if the core has a policy for each of its modules; with its
/// [`ModulePolicy`]. Made by every call of an interface, so the refusals are made apart.
#[inline]
fn configured<'b>(
    bindings: &'b [Binding],
    modules: &'b [Box<[Module]>],
    state: &cooperation::State,
    id: InterfaceId,
) -> Result<(&'b Binding, ModulePolicy<'b>), RtcError> {
    let (Some(binding), Some(modules)) = (bindings.get(id.0), modules.get(id.0)) else {
        return Err(unknown_interface(id));
    };
    if let [module] = &**modules {
        return match state.policy(*module) {
            Some(policy) => Ok((binding, Some((module, policy)))),
            None => Err(unconfigured(binding, *module)),
        };
    }
    match modules
        .iter()
        .find(|module| state.policy(**module).is_none())
    {
        Some(module) => Err(unconfigured(binding, *module)),
        None => Ok((binding, None)),
    }
}

/// [`configured`]'s refusal of an interface `id` that is not the adapter's.
#[cold]
fn unknown_interface(id: InterfaceId) -> RtcError {
    RtcError::UnknownInterface {
        name: format!("#{}", id.0),
    }
}

/// [`configured`]'s refusal of `binding`, whose `module` the core has no policy for.
#[cold]
fn unconfigured(binding: &Binding, module: Module) -> RtcError {
    RtcError::Unconfigured {
        name: binding.name.clone(),
        module,
    }
}

/// Parses a command request, checks each command's scene with `check`, and sends the batch to
/// the core.
fn apply_commands(
    state: &mut cooperation::State,
    request: &CooperateCommandsRequest,
    check: impl Fn(&cooperation::State, SceneId) -> Result<(), RtcError>,
) -> Reply<CooperateCommandsResponse> {
    let result = request
        .parse()
        .map_err(RtcError::from)
        .and_then(|commands| {
            for command in &commands {
                check(state, command.id)?;
            }
            // [COOP-DEV-BATCH.1] [COOP-DEV-DUPLICATE.1] [COOP-DEV-STORED-COMMANDS.1]
            Ok(state.apply(&Input::SetCommands { commands })?)
        });
    Reply {
        response: CooperateCommandsResponse::answering(request, result.is_ok()),
        result,
    }
}

/// Sets the policies of `modules` to what the auto-mode switch stands for.
fn set_auto_mode(
    state: &mut cooperation::State,
    modules: BTreeSet<Module>,
    enable: bool,
) -> Result<Transition, RtcError> {
    let policies = modules
        .into_iter()
        .map(|module| PolicySetting {
            module,
            policy: policy_for_auto_mode(enable),
        })
        .collect();
    // [COOP-DEV-POLICY-CLOBBER.1] [COOP-DEV-AUTO-MODE-KEY.1]
    Ok(state.apply(&Input::SetPolicies { policies })?)
}

/// Upstream's `auto_mode` of a scene: it proceeds on the module's judgment, because the operator
/// chose autonomous or has not decided under an optional policy. `requested` is a separate field,
/// as upstream. `policy` gives the policy of the scene's module; it is asked only for a scene no
/// operator has decided.
fn auto_mode_under(scene: &Scene, policy: impl FnOnce() -> Option<Policy>) -> bool {
    match scene.operator_decision() {
        OperatorDecision::Autonomous => true,
        OperatorDecision::Undecided => policy() == Some(Policy::Optional),
        OperatorDecision::Activate | OperatorDecision::Deactivate => false,
    }
}

/// A live scene as an RTC status, `policy` giving the policy of its module (asked only for a
/// scene no operator has decided). The stamp is the owner's last report: `stamp` less the
/// scene's age.
fn cooperate_status(
    binding: &Binding,
    id: SceneId,
    scene: &Scene,
    policy: impl FnOnce() -> Option<Policy>,
    stamp: Time,
) -> CooperateStatus {
    let (start_distance, finish_distance) = distances(scene.geometry());
    // [COOP-DEV-NONE.1]: an undecided (or autonomous) scene reports DEACTIVATE, upstream's
    // initial command status.
    let command = match scene.operator_decision() {
        OperatorDecision::Activate => Decision::Activate,
        _ => Decision::Deactivate,
    };
    CooperateStatus {
        stamp: stamp.before_ms(scene.age_ms()),
        uuid: id.into(),
        module: binding.module_type.into(),
        safe: scene.module_decision() == Decision::Activate,
        requested: scene.is_requested(),
        command_status: Command::from(command),
        state: scene.phase().into(),
        auto_mode: auto_mode_under(scene, policy),
        start_distance,
        finish_distance,
    }
}

/// An interface's auto-mode status: on when every one of its modules' policies is optional, so
/// that each of its scenes may proceed without the operator (`[COOP-DEV-SEQUENCE.1]`).
fn auto_mode_status(binding: &Binding, state: &cooperation::State) -> AutoModeStatus {
    AutoModeStatus {
        module: binding.module_type.into(),
        is_auto_mode: binding
            .modules()
            .all(|module| state.policy(module) == Some(Policy::Optional)),
    }
}

mod interface;
mod routes;

pub use interface::{Answers, Interface, View};
use routes::Routes;
