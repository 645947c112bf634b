//! The baselines the library is timed against: [`LinearRegistry`], an upstream-style registry
//! (one vector of status records, scanned by UUID), and [`PerModuleRegistry`], one such
//! vector per module. Written here only to be measured against.

use cooperation::{
    merge, Command, CooperationStatus, Decision, Detail, FactorKind, Geometry, Limits, Module,
    OperatorDecision, Phase, Policy, PolicySetting, SceneId, SteeringFactor, VelocityFactor,
};

use super::{limits, Outputs, Registry};

/// One status record of the baseline, as `rtc_interface` keeps one per scene: everything
/// about the scene, the UUID among it, and the policy copied in (upstream's per-status
/// `auto_mode`).
#[derive(Clone, Copy, Debug)]
struct Record {
    id: SceneId,
    module: Module,
    phase: Phase,
    module_decision: Decision,
    operator_decision: OperatorDecision,
    policy: Policy,
    age_ms: u64,
    geometry: Geometry,
}

impl Record {
    fn status(&self) -> CooperationStatus {
        CooperationStatus {
            id: self.id,
            module_decision: self.module_decision,
            operator_decision: self.operator_decision,
            cancellable: self.phase.is_cancellable(),
        }
    }
}

/// The upstream-style baseline: one vector of status records, searched linearly by UUID for
/// every update, command and query; a policy change rewrites every record of the module, as
/// upstream's auto-mode service does.
#[derive(Debug)]
pub struct LinearRegistry {
    records: Vec<Record>,
    defaults: Vec<(Module, Policy)>,
    ttl_ms: u64,
    max_scenes: usize,
}

impl LinearRegistry {
    fn find(&self, id: SceneId) -> Option<&Record> {
        self.records.iter().find(|record| record.id == id)
    }

    fn find_mut(&mut self, id: SceneId) -> Option<&mut Record> {
        self.records.iter_mut().find(|record| record.id == id)
    }

    fn default_policy(&self, module: Module) -> Option<Policy> {
        self.defaults
            .iter()
            .find(|(m, _)| *m == module)
            .map(|(_, p)| *p)
    }
}

impl Registry for LinearRegistry {
    fn new(modules: &[(Module, Policy, FactorKind)], scenes: usize) -> Self {
        Self {
            records: Vec::new(),
            defaults: modules.iter().map(|&(m, p, _)| (m, p)).collect(),
            ttl_ms: Limits::default().ttl_ms,
            max_scenes: limits(scenes).max_scenes,
        }
    }

    fn register(
        &mut self,
        id: SceneId,
        module: Module,
        decision: Decision,
        geometry: Geometry,
    ) -> bool {
        if self.find(id).is_some() || self.records.len() >= self.max_scenes {
            return false;
        }
        let Some(policy) = self.default_policy(module) else {
            return false;
        };
        self.records.push(Record {
            id,
            module,
            phase: Phase::Waiting,
            module_decision: decision,
            operator_decision: OperatorDecision::Undecided,
            policy,
            age_ms: 0,
            geometry,
        });
        true
    }

    fn update(
        &mut self,
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        geometry: Geometry,
    ) -> bool {
        let Some(record) = self.find_mut(id) else {
            return false;
        };
        if record.module != module
            || record.geometry.kind() != geometry.kind()
            || !record.phase.may_become(phase)
        {
            return false;
        }
        if phase.is_terminal() {
            return self.remove(id, module);
        }
        record.phase = phase;
        record.module_decision = decision;
        record.geometry = geometry;
        record.age_ms = 0;
        true
    }

    fn remove(&mut self, id: SceneId, module: Module) -> bool {
        match self.records.iter().position(|record| record.id == id) {
            Some(at) if self.records[at].module == module => {
                self.records.remove(at);
                true
            }
            _ => false,
        }
    }

    fn tick(&mut self, elapsed_ms: u64) -> bool {
        let ttl_ms = self.ttl_ms;
        for record in &mut self.records {
            record.age_ms = record.age_ms.saturating_add(elapsed_ms);
        }
        self.records.retain(|record| record.age_ms <= ttl_ms);
        true
    }

    fn merged_decision(&self, id: SceneId, _module: Module) -> Option<Decision> {
        self.find(id)
            .map(|r| merge(r.operator_decision, r.policy, r.module_decision))
    }

    fn outputs(&self, out: &mut Outputs) {
        out.statuses.clear();
        out.factors.velocity.clear();
        out.factors.steering.clear();
        self.push_outputs(out);
        sort_factors(out);
    }

    fn set_commands(&mut self, commands: Vec<Command>) -> bool {
        // Upstream validates every command (one search each), then applies the valid ones
        // (another search each).
        let responses: Vec<bool> = commands.iter().map(|c| self.accepts(c)).collect();
        for command in &commands {
            self.command(command);
        }
        responses.iter().all(|ok| *ok)
    }

    fn set_policies(&mut self, policies: Vec<PolicySetting>) -> bool {
        let mut success = true;
        for setting in &policies {
            success &= self.policy(*setting);
        }
        success
    }

    fn retired_capacity(&self) -> usize {
        0
    }
}

impl LinearRegistry {
    /// Whether a command for this scene would be accepted.
    fn accepts(&self, command: &Command) -> bool {
        self.find(command.id)
            .is_some_and(|r| r.phase.is_cancellable())
    }

    /// Applies a command if its scene is here and cancellable.
    fn command(&mut self, command: &Command) {
        if let Some(record) = self.find_mut(command.id) {
            if record.phase.is_cancellable() {
                record.operator_decision = command.decision;
            }
        }
    }

    /// Sets a module's policy, for new scenes and every record of the module. Whether the
    /// module is known.
    fn policy(&mut self, setting: PolicySetting) -> bool {
        let known = match self.defaults.iter_mut().find(|(m, _)| *m == setting.module) {
            Some((_, policy)) => {
                *policy = setting.policy;
                true
            }
            None => false,
        };
        for record in &mut self.records {
            if record.module == setting.module {
                record.policy = setting.policy;
            }
        }
        known
    }

    /// Appends every record's status and factor, in record order.
    fn push_outputs(&self, out: &mut Outputs) {
        for record in &self.records {
            let cooperation = record.status();
            out.statuses.push(cooperation);
            let Module { behavior, sequence } = record.module;
            match record.geometry {
                Geometry::Velocity {
                    pose,
                    distance,
                    status,
                } => out.factors.velocity.push(VelocityFactor {
                    pose,
                    distance,
                    status,
                    behavior,
                    sequence,
                    // The workload's owners report no detail.
                    detail: Detail::EMPTY,
                    cooperation: Some(cooperation),
                }),
                Geometry::Steering {
                    poses,
                    distances,
                    direction,
                    status,
                } => out.factors.steering.push(SteeringFactor {
                    poses,
                    distances,
                    direction,
                    status,
                    behavior,
                    sequence,
                    // The workload's owners report no detail.
                    detail: Detail::EMPTY,
                    cooperation: Some(cooperation),
                }),
            }
        }
    }
}

/// Sorts the factor lists nearest first: the same ordering, by the same sort, as the library,
/// so that only the registry differs.
fn sort_factors(out: &mut Outputs) {
    let id = |status: Option<CooperationStatus>| status.map(|status| status.id);
    out.factors.velocity.sort_unstable_by(|a, b| {
        a.distance
            .total_cmp(&b.distance)
            .then_with(|| id(a.cooperation).cmp(&id(b.cooperation)))
    });
    out.factors.steering.sort_unstable_by(|a, b| {
        a.distances[0]
            .total_cmp(&b.distances[0])
            .then_with(|| id(a.cooperation).cmp(&id(b.cooperation)))
    });
}

/// The baseline closer to upstream's layout: one [`LinearRegistry`] per module, as every
/// planning module has its own `RTCInterface`. Owners and policies reach their module's
/// vector directly; an AD API command names only a UUID, so it searches every module's.
#[derive(Debug)]
pub struct PerModuleRegistry {
    modules: Vec<(Module, LinearRegistry)>,
}

impl PerModuleRegistry {
    fn part(&self, module: Module) -> Option<&LinearRegistry> {
        self.modules
            .iter()
            .find(|(m, _)| *m == module)
            .map(|(_, part)| part)
    }

    fn part_mut(&mut self, module: Module) -> Option<&mut LinearRegistry> {
        self.modules
            .iter_mut()
            .find(|(m, _)| *m == module)
            .map(|(_, part)| part)
    }
}

impl Registry for PerModuleRegistry {
    fn new(modules: &[(Module, Policy, FactorKind)], scenes: usize) -> Self {
        Self {
            modules: modules
                .iter()
                .map(|&one| (one.0, LinearRegistry::new(&[one], scenes)))
                .collect(),
        }
    }

    fn register(
        &mut self,
        id: SceneId,
        module: Module,
        decision: Decision,
        geometry: Geometry,
    ) -> bool {
        self.part_mut(module)
            .is_some_and(|part| part.register(id, module, decision, geometry))
    }

    fn update(
        &mut self,
        id: SceneId,
        module: Module,
        phase: Phase,
        decision: Decision,
        geometry: Geometry,
    ) -> bool {
        self.part_mut(module)
            .is_some_and(|part| part.update(id, module, phase, decision, geometry))
    }

    fn remove(&mut self, id: SceneId, module: Module) -> bool {
        self.part_mut(module)
            .is_some_and(|part| part.remove(id, module))
    }

    fn tick(&mut self, elapsed_ms: u64) -> bool {
        for (_, part) in &mut self.modules {
            part.tick(elapsed_ms);
        }
        true
    }

    fn merged_decision(&self, id: SceneId, module: Module) -> Option<Decision> {
        self.part(module)?.merged_decision(id, module)
    }

    fn outputs(&self, out: &mut Outputs) {
        out.statuses.clear();
        out.factors.velocity.clear();
        out.factors.steering.clear();
        for (_, part) in &self.modules {
            part.push_outputs(out);
        }
        sort_factors(out);
    }

    fn set_commands(&mut self, commands: Vec<Command>) -> bool {
        let responses: Vec<bool> = commands
            .iter()
            .map(|c| self.modules.iter().any(|(_, part)| part.accepts(c)))
            .collect();
        for command in &commands {
            for (_, part) in &mut self.modules {
                part.command(command);
            }
        }
        responses.iter().all(|ok| *ok)
    }

    fn set_policies(&mut self, policies: Vec<PolicySetting>) -> bool {
        let mut success = true;
        for setting in &policies {
            success &= self
                .part_mut(setting.module)
                .is_some_and(|part| part.policy(*setting));
        }
        success
    }

    fn retired_capacity(&self) -> usize {
        0
    }
}
