//! The bench of the relay's tests: the relay and two upstream modules on one clock, and the
//! requests an operator makes.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::collections::BTreeMap;

use cooperation::{Config, Decision, OperatorDecision, Phase, Policy, SceneId};
use cooperation_adapters::engine::{Engine, Now, Options};
use cooperation_adapters::relay::{ModuleAnswer, ModuleRequest, OperatorCall, Relay, DEADLINE_MS};
use cooperation_adapters::rtc::{self, Rtc};
use cooperation_adapters::wire::{self, ResponseStatus};
use cooperation_adapters::Time;
use cooperation_models::model::relay::peer::Upstream;

pub(super) const LANE: &str = "lane_change_left";
pub(super) const CROSS: &str = "intersection";

/// The relay and two upstream modules, on one clock.
pub(super) struct Bench {
    pub(super) relay: Relay,
    pub(super) modules: BTreeMap<&'static str, Upstream>,
    pub(super) clock_ms: i64,
    pub(super) next_operator: u64,
    /// Whether a module answers the calls it gets.
    pub(super) answering: BTreeMap<&'static str, bool>,
}

impl Bench {
    /// Every policy as upstream's `enable_rtc` says; both modules built with it.
    pub(super) fn new(enable_rtc: bool) -> Self {
        let config = Config::new(Rtc::standard().policies(enable_rtc));
        let engine = Engine::new(config, Options::default()).unwrap();
        let modules = BTreeMap::from([
            (
                LANE,
                Upstream::new(rtc::Module::LANE_CHANGE_LEFT, enable_rtc),
            ),
            (CROSS, Upstream::new(rtc::Module::INTERSECTION, enable_rtc)),
        ]);
        Self {
            relay: Relay::new(engine, DEADLINE_MS),
            answering: modules.keys().map(|&name| (name, true)).collect(),
            modules,
            clock_ms: 0,
            next_operator: 0,
        }
    }

    pub(super) fn now(&self) -> Now {
        Now::of_stamp(Time::new(
            i32::try_from(self.clock_ms / 1000).unwrap() + 100,
            u32::try_from(self.clock_ms % 1000).unwrap() * 1_000_000,
        ))
    }

    /// The operator decision the AD API shows for scene `n`.
    pub(super) fn operator_decision(&self, n: u128) -> OperatorDecision {
        self.relay.state().scene(id(n)).unwrap().operator_decision()
    }

    /// Module `name` registers scene `n`, waiting, `safe` or not.
    pub(super) fn register(&mut self, name: &str, n: u128, safe: bool) {
        self.module(name).update(id(n), safe, Phase::Waiting, false);
    }

    pub(super) fn module(&mut self, name: &str) -> &mut Upstream {
        self.modules.get_mut(name).unwrap()
    }

    /// One planning cycle (10 ms): each module publishes, the relay takes it.
    pub(super) fn cycle(&mut self) {
        self.clock_ms += 10;
        let now = self.now();
        for (name, module) in &self.modules {
            let array = module.status_array(now.stamp);
            let taken = self.relay.take_statuses(name, &array, now).unwrap();
            assert!(taken.refused.is_empty(), "{name}: {:?}", taken.refused);
            self.relay
                .take_auto_mode(name, &module.auto_mode_status(), now)
                .unwrap();
        }
        self.relay.handle_timeout(now);
    }

    /// Delivers every call the relay has, and every answer, until nothing moves.
    pub(super) fn pump(&mut self) {
        let now = self.now();
        while let Some(forward) = self.relay.poll_forward(now) {
            let name = forward.interface.as_str();
            if !self.answering.get(name).copied().unwrap_or(false) {
                continue;
            }
            let module = self.modules.get_mut(name).expect("a relayed module");
            let answer = match &forward.request {
                ModuleRequest::Commands(request) => {
                    ModuleAnswer::Commands(module.cooperate_commands(request))
                }
                ModuleRequest::AutoMode(request) => {
                    ModuleAnswer::AutoMode(module.enable_auto_mode(request.enable))
                }
            };
            assert!(self.relay.take_answer(forward.call, &answer, now));
        }
    }

    /// Cycles until the relay has nothing on its way and a cycle changes nothing.
    pub(super) fn settle(&mut self) {
        for _ in 0..50 {
            self.pump();
            let before = self.modules.clone();
            self.cycle();
            self.pump();
            if self.relay.is_idle() && before == self.modules {
                self.cycle();
                if self.relay.is_idle() {
                    return;
                }
            }
        }
        panic!("the relay did not settle");
    }

    /// Each module drives every scene it lists as the AD API shows it.
    pub(super) fn assert_follows(&self) {
        for (name, module) in &self.modules {
            for status in &module.statuses {
                let merged = self.relay.state().merged_decision(status.id);
                let activated = module.is_activated(status.id);
                assert_eq!(
                    merged.map(|d| d == Decision::Activate),
                    Some(activated),
                    "{name}: scene {} drives {activated}, the AD API shows {merged:?}",
                    status.id
                );
            }
        }
    }

    /// An operator's call; its answer once the modules are done.
    pub(super) fn operator(&mut self, request: wire::Request) -> wire::Response {
        let call = OperatorCall(self.next_operator);
        self.next_operator += 1;
        let now = self.now();
        if let Some(response) = self.relay.handle_operator(call, &request, now) {
            return response;
        }
        for _ in 0..200 {
            self.pump();
            if let Some((answered, response)) = self.relay.poll_answer() {
                assert_eq!(answered, call);
                return response;
            }
            self.clock_ms += 10;
            let now = self.now();
            self.relay.handle_timeout(now);
        }
        panic!("no answer");
    }
}

pub(super) fn command(id: SceneId, decision: OperatorDecision) -> wire::Request {
    let json = format!(
        r#"{{"commands": [{{"uuid": {{"uuid": {:?}}}, "cooperator": {{"decision": {}}}}}]}}"#,
        id.to_bytes(),
        match decision {
            OperatorDecision::Deactivate => 1,
            OperatorDecision::Activate => 2,
            OperatorDecision::Autonomous => 3,
            OperatorDecision::Undecided => 4,
        }
    );
    wire::Service::SetCommands.read(json.as_bytes()).unwrap()
}

pub(super) fn policy(behavior: &str, policy: Policy) -> wire::Request {
    let json = format!(
        r#"{{"policies": [{{"behavior": "{behavior}", "sequence": "", "policy": {}}}]}}"#,
        match policy {
            Policy::Optional => 1,
            Policy::Required => 2,
        }
    );
    wire::Service::SetPolicies.read(json.as_bytes()).unwrap()
}

pub(super) fn status(response: &wire::Response) -> &ResponseStatus {
    response.status()
}

pub(super) fn id(n: u128) -> SceneId {
    SceneId::from_u128(n)
}
