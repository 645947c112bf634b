//! The work the runtime benchmarks measure, shared by `benches/runtime.rs` and
//! `tests/allocations.rs` so that the allocation test checks the very cycle that is timed.
//!
//! A [`Planner`] holds N live scenes spread over [`MODULES`] and drives them through a
//! [`Registry`]: the library's [`State`], or
//! [`LinearRegistry`](baseline::LinearRegistry), an upstream-style registry written here only
//! as the baseline. `rtc_interface` keeps its statuses in a vector and finds a scene by
//! scanning it for the UUID on every update, command and query (`upstream-rtc.md` §3.3–3.5);
//! `LinearRegistry` does the same, with the library's rules for the decisions so that both
//! sides do the same work per scene. [`PerModuleRegistry`](baseline::PerModuleRegistry) splits
//! that vector by module, as upstream has one `RTCInterface` per module.
#![allow(dead_code, unreachable_pub)]

use std::collections::VecDeque;

pub mod baseline;

use cooperation::{
    Behavior, Command, CooperationStatus, Decision, Direction, FactorKind, FactorLists, Geometry,
    Input, Limits, Module, OperatorDecision, Phase, Policy, PolicySetting, Report, SceneId,
    Sequence, State,
};

/// The modules the scenes are spread over, round robin: steering and velocity scenes, optional
/// and required policies.
pub const MODULES: [(Module, Policy, FactorKind); 8] = [
    (
        Module::new(Behavior::LaneChange),
        Policy::Optional,
        FactorKind::Steering,
    ),
    (
        Module::with_sequence(Behavior::Avoidance, Sequence::Change),
        Policy::Required,
        FactorKind::Steering,
    ),
    (
        Module::with_sequence(Behavior::Avoidance, Sequence::Return),
        Policy::Optional,
        FactorKind::Steering,
    ),
    (
        Module::new(Behavior::StartPlanner),
        Policy::Required,
        FactorKind::Steering,
    ),
    (
        Module::new(Behavior::Crosswalk),
        Policy::Required,
        FactorKind::Velocity,
    ),
    (
        Module::new(Behavior::Intersection),
        Policy::Optional,
        FactorKind::Velocity,
    ),
    (
        Module::new(Behavior::TrafficSignal),
        Policy::Optional,
        FactorKind::Velocity,
    ),
    (
        Module::new(Behavior::NoStoppingArea),
        Policy::Required,
        FactorKind::Velocity,
    ),
];

/// The time between two planning cycles.
pub const CYCLE_MS: u64 = 100;

/// Limits that admit `scenes` live scenes and batches of that many entries; the defaults
/// otherwise (the default `max_scenes` is 4 096, too few for the largest N).
pub fn limits(scenes: usize) -> Limits {
    let defaults = Limits::default();
    Limits {
        max_scenes: scenes.max(defaults.max_scenes),
        max_batch: scenes.max(defaults.max_batch),
        ..defaults
    }
}

/// The `Register` input an owner sends. Every input the benchmarks send is built by this
/// function or by [`update_input`].
pub fn register_input(
    id: SceneId,
    module: Module,
    decision: Decision,
    geometry: Geometry,
) -> Input {
    Input::Register {
        id,
        module,
        report: Report::new(decision, geometry),
    }
}

/// The `Update` input an owner sends.
pub fn update_input(
    id: SceneId,
    module: Module,
    phase: Phase,
    decision: Decision,
    geometry: Geometry,
) -> Input {
    Input::Update {
        id,
        module,
        phase,
        report: Report::new(decision, geometry),
    }
}

/// SplitMix64's finaliser: a bijection on `u64` that scatters consecutive numbers.
const fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce5_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The `n`-th scene identifier: random-looking, as owners draw version-4 UUIDs, so identifier
/// order is unrelated to creation order; distinct for distinct `n` (its low half is `n`).
pub fn scene_id(n: u64) -> SceneId {
    SceneId::from_u128((u128::from(mix(n)) << 64) | u128::from(n))
}

/// One scene's owner: what it reports, cycle by cycle.
#[derive(Clone, Copy, Debug)]
pub struct Owner {
    /// The scene.
    pub id: SceneId,
    /// Its module.
    pub module: Module,
    kind: FactorKind,
    salt: u64,
    running: bool,
}

impl Owner {
    /// The owner of the `n`-th scene, of the `n`-th module round robin.
    pub fn new(n: u64) -> Self {
        let (module, _, kind) = MODULES[n as usize % MODULES.len()];
        Self::of_module(n, module, kind)
    }

    /// The owner of the `n`-th scene, of `module`.
    pub fn of_module(n: u64, module: Module, kind: FactorKind) -> Self {
        Self {
            id: scene_id(n),
            module,
            kind,
            salt: mix(n ^ 0x5eed),
            running: false,
        }
    }

    /// The geometry reported in `cycle`: each scene at its own distance, drawing nearer
    /// cycle by cycle, so that the factor lists are sorted afresh every cycle.
    pub fn geometry(&self, cycle: u64) -> Geometry {
        let start = (self.salt % 2_000) as f32 / 10.0 + 10.0 - (cycle % 16) as f32 * 0.5;
        match self.kind {
            FactorKind::Velocity => Geometry::velocity(start),
            FactorKind::Steering => {
                let direction = if self.salt & 1 == 0 {
                    Direction::Left
                } else {
                    Direction::Right
                };
                Geometry::steering(direction, start, start + 30.0)
            }
        }
    }

    /// The module decision reported in `cycle`: mostly safe, unsafe one cycle in four.
    pub fn decision(&self, cycle: u64) -> Decision {
        if (self.salt.wrapping_add(cycle)) % 4 == 0 {
            Decision::Deactivate
        } else {
            Decision::Activate
        }
    }

    /// The phase reported every cycle: waiting or running, for ever (both are cancellable).
    pub fn phase(&self) -> Phase {
        if self.running {
            Phase::Running
        } else {
            Phase::Waiting
        }
    }
}

/// Caller-owned output buffers, reused cycle after cycle.
#[derive(Default, Debug)]
pub struct Outputs {
    /// Every live scene's status.
    pub statuses: Vec<CooperationStatus>,
    /// The velocity factors and the steering factors, each nearest first.
    pub factors: FactorLists,
}

/// What one planning cycle saw; the benchmarks keep it from being optimised away and the
/// allocation test checks it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Summary {
    /// Updates accepted.
    pub accepted: usize,
    /// Merged decisions that were `Activate`.
    pub activated: usize,
    /// Statuses produced.
    pub statuses: usize,
    /// Factors produced, velocity and steering.
    pub factors: usize,
}

/// The operations a planning cycle, an operator and a policy change need, on either side.
pub trait Registry {
    /// An empty registry for at most `scenes` live scenes, with the default policies of
    /// `modules`.
    fn new(modules: &[(Module, Policy, FactorKind)], scenes: usize) -> Self;
    /// An owner opens a scene. Whether it was accepted.
    fn register(
        &mut self,
        id: SceneId,
        module: Module,
        decision: Decision,
        geometry: Geometry,
    ) -> bool;
    /// An owner reports on its scene. Whether it was accepted.
    fn update(
        &mut self,
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        geometry: Geometry,
    ) -> bool;
    /// An owner drops its scene. Whether it was accepted.
    fn remove(&mut self, id: SceneId, module: Module) -> bool;
    /// Time passed.
    fn tick(&mut self, elapsed_ms: u64) -> bool;
    /// The merged decision the planner drives the scene with, asked by the scene's module.
    fn merged_decision(&self, id: SceneId, module: Module) -> Option<Decision>;
    /// Fills the caller's buffers with the statuses and the factor lists.
    fn outputs(&self, out: &mut Outputs);
    /// The AD API `set_commands` call. Whether it succeeded.
    fn set_commands(&mut self, commands: Vec<Command>) -> bool;
    /// The AD API `set_policies` call. Whether it succeeded.
    fn set_policies(&mut self, policies: Vec<PolicySetting>) -> bool;
    /// How many retired identifiers are remembered at most (none for the baseline).
    fn retired_capacity(&self) -> usize;
}

impl Registry for State {
    fn new(modules: &[(Module, Policy, FactorKind)], scenes: usize) -> Self {
        let config = cooperation::Config {
            policies: modules.iter().map(|&(m, p, _)| (m, p)).collect(),
            limits: limits(scenes),
        };
        Self::new(config).expect("the benchmark's configuration is valid")
    }

    fn register(
        &mut self,
        id: SceneId,
        module: Module,
        decision: Decision,
        geometry: Geometry,
    ) -> bool {
        self.apply(&register_input(id, module, decision, geometry))
            .is_ok()
    }

    fn update(
        &mut self,
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        geometry: Geometry,
    ) -> bool {
        self.apply(&update_input(id, module, phase, decision, geometry))
            .is_ok()
    }

    fn remove(&mut self, id: SceneId, module: Module) -> bool {
        self.apply(&Input::Remove { id, module }).is_ok()
    }

    fn tick(&mut self, elapsed_ms: u64) -> bool {
        self.apply(&Input::Tick { elapsed_ms }).is_ok()
    }

    fn merged_decision(&self, id: SceneId, _module: Module) -> Option<Decision> {
        Self::merged_decision(self, id)
    }

    fn outputs(&self, out: &mut Outputs) {
        self.statuses_into(&mut out.statuses);
        self.factors_into(&mut out.factors);
    }

    fn set_commands(&mut self, commands: Vec<Command>) -> bool {
        self.apply(&Input::SetCommands { commands }).is_ok()
    }

    fn set_policies(&mut self, policies: Vec<PolicySetting>) -> bool {
        self.apply(&Input::SetPolicies { policies }).is_ok()
    }

    fn retired_capacity(&self) -> usize {
        self.limits().retired_capacity
    }
}

/// A planner with live scenes, driven through a [`Registry`].
#[derive(Debug)]
pub struct Planner<R> {
    /// The registry.
    pub registry: R,
    /// The owners of the live scenes, oldest first.
    pub owners: VecDeque<Owner>,
    modules: Vec<(Module, Policy, FactorKind)>,
    cycle: u64,
    next: u64,
}

impl<R: Registry> Planner<R> {
    /// `scenes` live scenes spread over [`MODULES`] round robin; half of them running; one in
    /// five with an operator decision.
    pub fn new(scenes: usize) -> Self {
        Self::with_modules(&MODULES, scenes)
    }

    /// `scenes` live scenes spread over `modules` round robin; half of them running; one in
    /// five with an operator decision.
    pub fn with_modules(modules: &[(Module, Policy, FactorKind)], scenes: usize) -> Self {
        let mut planner = Self {
            registry: R::new(modules, scenes),
            owners: VecDeque::with_capacity(scenes),
            modules: modules.to_vec(),
            cycle: 0,
            next: 0,
        };
        for _ in 0..scenes {
            planner.open();
        }
        for (at, owner) in planner.owners.iter_mut().enumerate() {
            owner.running = at % 2 == 1;
            let accepted = planner.registry.update(
                owner.id,
                owner.module,
                owner.phase(),
                owner.decision(0),
                owner.geometry(0),
            );
            assert!(accepted, "setting up the benchmark's scenes");
        }
        let commands: Vec<Command> = planner
            .owners
            .iter()
            .step_by(5)
            .enumerate()
            .map(|(at, owner)| Command {
                id: owner.id,
                decision: if at % 2 == 0 {
                    OperatorDecision::Activate
                } else {
                    OperatorDecision::Deactivate
                },
            })
            .collect();
        assert!(
            planner.registry.set_commands(commands),
            "setting up commands"
        );
        planner
    }

    /// A new owner registers a scene, of the next module round robin.
    fn open(&mut self) {
        let n = self.next;
        self.next += 1;
        let (module, _, kind) = self.modules[n as usize % self.modules.len()];
        let owner = Owner::of_module(n, module, kind);
        let accepted =
            self.registry
                .register(owner.id, owner.module, owner.decision(0), owner.geometry(0));
        assert!(accepted, "registering a fresh identifier");
        self.owners.push_back(owner);
    }

    /// One planning cycle: time passes, every owner updates its scene, the planner reads every
    /// merged decision, and the statuses and factor lists are produced into `out`.
    pub fn cycle(&mut self, out: &mut Outputs) -> Summary {
        self.cycle += 1;
        self.registry.tick(CYCLE_MS);
        let accepted = self.update_all();
        let activated = self.decide_all();
        self.registry.outputs(out);
        Summary {
            accepted,
            activated,
            statuses: out.statuses.len(),
            factors: out.factors.velocity.len() + out.factors.steering.len(),
        }
    }

    /// The first part of a cycle: every owner updates its scene with what it reports in the
    /// current cycle. How many updates were accepted.
    pub fn update_all(&mut self) -> usize {
        let cycle = self.cycle;
        let mut accepted = 0;
        for owner in &self.owners {
            let ok = self.registry.update(
                owner.id,
                owner.module,
                owner.phase(),
                owner.decision(cycle),
                owner.geometry(cycle),
            );
            accepted += usize::from(ok);
        }
        accepted
    }

    /// The second part of a cycle: the planner reads every scene's merged decision. How many
    /// were `Activate`.
    pub fn decide_all(&self) -> usize {
        let mut activated = 0;
        for owner in &self.owners {
            let merged = self.registry.merged_decision(owner.id, owner.module);
            activated += usize::from(merged == Some(Decision::Activate));
        }
        activated
    }

    /// Registration and retirement churn: the oldest scene's owner removes it and a new owner
    /// registers a scene under a fresh identifier, so the number of live scenes stays put.
    pub fn churn(&mut self) {
        if let Some(oldest) = self.owners.pop_front() {
            let removed = self.registry.remove(oldest.id, oldest.module);
            debug_assert!(removed);
        }
        self.open();
    }

    /// Churns until the registry's memory of retired identifiers is full, so that every later
    /// churn also forgets the oldest one: the steady state of a long-running planner.
    pub fn fill_retired(&mut self) {
        for _ in 0..self.registry.retired_capacity() {
            self.churn();
        }
    }

    /// `k` commands, all with `decision`, for `k` live scenes spread evenly over the live
    /// ones, each in the middle of its stretch (so that a linear search meets them at
    /// average depth, not all near the front).
    pub fn commands(&self, k: usize, decision: OperatorDecision) -> Vec<Command> {
        let step = (self.owners.len() / k.max(1)).max(1);
        self.owners
            .iter()
            .skip(step / 2)
            .step_by(step)
            .take(k)
            .map(|owner| Command {
                id: owner.id,
                decision,
            })
            .collect()
    }
}
