//! The relay (`cooperation_adapters::relay`) beside planning modules that behave as upstream's
//! `rtc_interface` ([`Upstream`], written from the upstream facts): the design page's sequence,
//! a refused forward, a module that does not answer, auto-mode switches with standing operator
//! decisions, a module restart, and what the relay refuses.
//!
//! After every exchange settles (no call on its way, every module's newest messages taken),
//! each module's `isActivated` is the merged decision the AD API shows.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod bench;

use cooperation::{Config, Decision, OperatorDecision, Phase, Policy, SceneId};
use cooperation_adapters::engine::{Engine, Options};
use cooperation_adapters::relay::{
    ArrayError, ModuleAnswer, ModuleRequest, OperatorCall, Relay, DEADLINE_MS,
};
use cooperation_adapters::rtc::{self, Rtc};
use cooperation_adapters::wire::{self, ResponseStatus};
use cooperation_adapters::Time;
use cooperation_models::model::relay::peer::Upstream;

use bench::*;

/// The design page's sequence through a module's own endpoints: the scene is shown, the
/// operator's command reaches the module, and only then the AD API shows it.
#[test]
fn coop_relay_forward_1() {
    let mut bench = Bench::new(true);
    // The lane change module creates a scene; it judges the change unsafe.
    bench.register(LANE, 1, false);
    bench.settle();
    // The operator sees it in the factors, undecided, held back by the required policy.
    let publication = bench.relay.poll_publication(bench.now()).unwrap();
    let factor = &publication.steering.factors[0];
    assert_eq!(factor.cooperation.len(), 1);
    assert!(!bench.module(LANE).is_activated(id(1)));
    // The operator activates it: forwarded to the module, which takes it.
    let response = bench.operator(command(id(1), OperatorDecision::Activate));
    assert!(status(&response).success, "{:?}", status(&response));
    assert!(bench.module(LANE).is_activated(id(1)));
    assert_eq!(bench.operator_decision(1), OperatorDecision::Activate);
    bench.settle();
    bench.assert_follows();
}

/// A command the module refuses is not shown and is not a success.
#[test]
fn coop_relay_success_1() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, true);
    bench.settle();
    // The module drops the scene; the relay has not heard yet.
    bench.module(LANE).remove(id(1));
    let response = bench.operator(command(id(1), OperatorDecision::Activate));
    let status = status(&response);
    assert!(!status.success);
    assert_eq!(status.code, ResponseStatus::PARAMETER_ERROR);
    assert!(
        status.message.contains("lane_change_left refused scene"),
        "{status:?}"
    );
    assert_eq!(bench.operator_decision(1), OperatorDecision::Undecided);
    bench.settle();
    assert!(
        bench.relay.state().scene(id(1)).is_none(),
        "gone from the array: removed"
    );
}

#[test]
fn coop_relay_success_1_a_module_that_does_not_answer_gets_a_timeout_naming_it() {
    let mut bench = Bench::new(true);
    bench.register(CROSS, 2, true);
    bench.settle();
    bench.answering.insert(CROSS, false);
    let response = bench.operator(command(id(2), OperatorDecision::Activate));
    let status = status(&response);
    assert!(!status.success);
    assert_eq!(status.code, ResponseStatus::SERVICE_TIMEOUT);
    assert!(
        status
            .message
            .contains("intersection did not answer within 1000 ms"),
        "{status:?}"
    );
    assert_eq!(bench.operator_decision(2), OperatorDecision::Undecided);
}

/// The relay says when a module's deadline passes, so that a host need not poll for it: its
/// timeout is the engine's, or the nearest deadline of a call in flight if that comes first.
#[test]
fn coop_relay_success_1_the_relay_says_when_a_module_s_deadline_passes() {
    let mut bench = Bench::new(true);
    let options = Options {
        publish_every_ms: 60_000,
        max_step_ms: 60_000,
        ..Options::default()
    };
    let config = Config::new(Rtc::standard().policies(true));
    bench.relay = Relay::new(Engine::new(config, options).unwrap(), 300);
    bench.register(CROSS, 2, true);
    bench.settle();
    bench.answering.insert(CROSS, false);
    let now = bench.now();
    assert!(bench.relay.poll_publication(now).is_some());
    assert_eq!(
        bench.relay.until_timeout_ms(now),
        bench.relay.engine().until_timeout_ms(now),
        "nothing in flight: the engine's"
    );
    assert!(bench.relay.engine().until_timeout_ms(now) > 300);
    let request = command(id(2), OperatorDecision::Activate);
    assert!(bench
        .relay
        .handle_operator(OperatorCall(50), &request, now)
        .is_none());
    bench.pump();
    assert_eq!(
        bench.relay.until_timeout_ms(now),
        300,
        "the call's deadline"
    );
    bench.clock_ms += 299;
    let later = bench.now();
    assert_eq!(bench.relay.until_timeout_ms(later), 1);
    bench.relay.handle_timeout(later);
    assert!(bench.relay.poll_answer().is_none(), "not yet");
    bench.clock_ms += 1;
    let deadline = bench.now();
    assert_eq!(bench.relay.until_timeout_ms(deadline), 0);
    bench.relay.handle_timeout(deadline);
    let (_, response) = bench.relay.poll_answer().expect("answered at the deadline");
    assert_eq!(status(&response).code, ResponseStatus::SERVICE_TIMEOUT);
}

/// A policy switch keeps the standing operator decisions on the module.
#[test]
fn coop_relay_policy_1() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, false);
    bench.register(LANE, 3, true);
    bench.settle();
    let response = bench.operator(command(id(1), OperatorDecision::Activate));
    assert!(status(&response).success);
    // Optional: upstream's switch sets every scene's auto_mode, the operator's included.
    let response = bench.operator(policy("lane-change", Policy::Optional));
    assert!(status(&response).success, "{:?}", status(&response));
    bench.settle();
    // Scene 1 still drives by the operator (the module thinks it unsafe); scene 3 by the module.
    assert!(bench.module(LANE).is_activated(id(1)));
    assert!(bench.module(LANE).is_activated(id(3)));
    bench.assert_follows();
    let response = bench.operator(policy("lane-change", Policy::Required));
    assert!(status(&response).success);
    bench.settle();
    assert!(bench.module(LANE).is_activated(id(1)));
    assert!(!bench.module(LANE).is_activated(id(3)));
    bench.assert_follows();
}

/// A module switched by someone else is switched back, its standing decisions sent again.
#[test]
fn coop_relay_follow_1() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, true);
    bench.register(LANE, 4, true);
    bench.settle();
    let response = bench.operator(command(id(4), OperatorDecision::Deactivate));
    assert!(status(&response).success);
    bench.module(LANE).enable_auto_mode(true);
    assert!(bench.module(LANE).is_activated(id(1)));
    bench.settle();
    assert!(!bench.module(LANE).auto_mode);
    bench.assert_follows();
}

#[test]
fn coop_relay_report_1_a_restarted_module_has_new_scenes_and_its_old_ones_retire() {
    let mut bench = Bench::new(false);
    bench.register(LANE, 1, true);
    bench.settle();
    let response = bench.operator(command(id(1), OperatorDecision::Deactivate));
    assert!(status(&response).success);
    // The planner restarts: a new interface, built with enable_rtc = true, new identifiers.
    *bench.module(LANE) = Upstream::new(rtc::Module::LANE_CHANGE_LEFT, true);
    bench.register(LANE, 5, true);
    bench.settle();
    assert!(bench.relay.state().scene(id(1)).is_none());
    assert!(bench.relay.state().retirement(id(1)).is_some());
    // The AD API's policy (optional) is put back on the module.
    assert!(bench.module(LANE).auto_mode);
    bench.assert_follows();
}

#[test]
fn coop_relay_report_1_a_silent_module_s_scenes_age_out() {
    let mut bench = Bench::new(true);
    bench.register(CROSS, 2, true);
    bench.settle();
    let ttl = i64::try_from(bench.relay.state().limits().ttl_ms).unwrap();
    // The host tells the time every 100 ms, as it does at least once per step limit
    // ([COOP-ENGINE-STEP.1]).
    let until = bench.clock_ms + ttl + 1;
    while bench.clock_ms < until {
        bench.clock_ms = (bench.clock_ms + 100).min(until);
        let now = bench.now();
        bench.relay.handle_timeout(now);
    }
    assert!(bench.relay.state().scene(id(2)).is_none());
}

/// Commands a module cannot take are refused and nothing is forwarded; the core's refusals
/// come first.
#[test]
fn coop_relay_inexpressible_1() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, true);
    bench.settle();
    for decision in [OperatorDecision::Autonomous, OperatorDecision::Undecided] {
        let now = bench.now();
        let response = bench
            .relay
            .handle_operator(OperatorCall(99), &command(id(1), decision), now)
            .expect("answered at once");
        let status = status(&response);
        assert!(!status.success);
        assert_eq!(
            status.message,
            format!(
                "commands[0] sets scene {} to {decision}, which a planning module's RTC \
                 interface cannot take for one scene (it takes activate or deactivate)",
                id(1)
            )
        );
        assert!(bench.relay.poll_forward(now).is_none());
    }
    // The core's refusals come first: an unknown scene is the core's.
    let now = bench.now();
    let response = bench
        .relay
        .handle_operator(
            OperatorCall(100),
            &command(id(9), OperatorDecision::Activate),
            now,
        )
        .expect("answered at once");
    assert!(
        status(&response).message.contains("unknown scene"),
        "{:?}",
        status(&response)
    );
    assert!(bench.relay.poll_forward(now).is_none());
}

/// Late, repeated and undefined arrays, and unknown interfaces, are refused whole.
#[test]
fn coop_relay_report_1() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, true);
    bench.cycle();
    let now = bench.now();
    let array = bench.module(LANE).status_array(now.stamp);
    let error = bench.relay.take_statuses(LANE, &array, now).unwrap_err();
    assert!(matches!(error, ArrayError::Late { .. }), "{error}");
    assert!(error.to_string().contains("late or repeated, not taken"));
    let mut array = bench.module(LANE).status_array(Time::new(9_999, 0));
    array.statuses[0].state = rtc::Lifecycle::new(7);
    let error = bench.relay.take_statuses(LANE, &array, now).unwrap_err();
    assert_eq!(
        error.to_string(),
        "the status array of lane_change_left is refused: statuses[0].state.type is 7, which is \
         not WAITING_FOR_EXECUTION (0), RUNNING (1), ABORTING (2), SUCCEEDED (3) or FAILED (4)"
    );
    let error = bench
        .relay
        .take_statuses("nowhere", &array, now)
        .unwrap_err();
    assert_eq!(
        error.to_string(),
        "no RTC interface named nowhere is relayed"
    );
    assert!(bench.relay.state().scene(id(1)).is_some());
}

#[test]
fn coop_relay_inexpressible_1_policies_that_split_an_interface_and_scenes_no_module_reported() {
    let mut bench = Bench::new(true);
    let now = bench.now();
    let json = br#"{"policies": [{"behavior": "avoidance", "sequence": "change", "policy": 1}]}"#;
    let request = wire::Service::SetPolicies.read(json).unwrap();
    let response = bench
        .relay
        .handle_operator(OperatorCall(1), &request, now)
        .expect("answered at once");
    assert_eq!(
        status(&response).message,
        "the policies would differ between the modules of static_obstacle_avoidance_left, which \
         has one auto-mode switch for all of them"
    );
    assert_eq!(
        bench
            .relay
            .state()
            .policy(cooperation::Module::with_sequence(
                cooperation::Behavior::Avoidance,
                cooperation::Sequence::Change
            )),
        Some(Policy::Required)
    );
    // A core a host fed itself: its scene has no module to forward to.
    let config = Config::new(Rtc::standard().policies(true));
    let mut state = cooperation::State::new(config).unwrap();
    let lane = cooperation::Module::new(cooperation::Behavior::LaneChange);
    let geometry = cooperation::Geometry::steering(cooperation::Direction::Left, 10.0, 60.0);
    state
        .apply(&cooperation::Input::Register {
            id: id(6),
            module: lane,
            report: cooperation::Report::new(Decision::Activate, geometry),
        })
        .unwrap();
    let engine = Engine::from_state(state, Options::default()).unwrap();
    let mut relay = Relay::new(engine, DEADLINE_MS);
    let response = relay
        .handle_operator(
            OperatorCall(2),
            &command(id(6), OperatorDecision::Activate),
            now,
        )
        .expect("answered at once");
    assert_eq!(
        status(&response).message,
        format!(
            "commands[0] names scene {}, which no relayed planning module reported: there is no \
             module to forward it to",
            id(6)
        )
    );
    assert!(relay.poll_forward(now).is_none());
}

#[test]
fn coop_relay_success_1_what_one_module_took_applies_when_another_refused() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, true);
    bench.register(CROSS, 2, true);
    bench.settle();
    bench.module(CROSS).remove(id(2));
    let json = format!(
        r#"{{"commands": [{{"uuid": {{"uuid": {:?}}}, "cooperator": {{"decision": 2}}}},
                          {{"uuid": {{"uuid": {:?}}}, "cooperator": {{"decision": 2}}}}]}}"#,
        id(1).to_bytes(),
        id(2).to_bytes()
    );
    let request = wire::Service::SetCommands.read(json.as_bytes()).unwrap();
    let response = bench.operator(request);
    let status = status(&response);
    assert!(!status.success);
    assert_eq!(
        status.message,
        format!("1 of 2 applied; intersection refused scene {}", id(2))
    );
    assert_eq!(bench.operator_decision(1), OperatorDecision::Activate);
    assert!(bench.module(LANE).is_activated(id(1)));
}

#[test]
fn coop_relay_forward_1_a_module_has_one_call_unanswered_at_a_time() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, true);
    bench.register(LANE, 3, true);
    bench.settle();
    let now = bench.now();
    for (call, scene) in [(1, id(1)), (2, id(3))] {
        let request = command(scene, OperatorDecision::Activate);
        assert!(bench
            .relay
            .handle_operator(OperatorCall(call), &request, now)
            .is_none());
    }
    let first = bench.relay.poll_forward(now).expect("the first call");
    assert!(bench.relay.poll_forward(now).is_none(), "the second waits");
    let ModuleRequest::Commands(request) = &first.request else {
        panic!("a commands call");
    };
    assert_eq!(SceneId::from(request.commands[0].uuid), id(1));
    let answer = ModuleAnswer::Commands(bench.module(LANE).cooperate_commands(request));
    assert!(bench.relay.take_answer(first.call, &answer, now));
    let second = bench.relay.poll_forward(now).expect("now the second");
    let ModuleRequest::Commands(request) = &second.request else {
        panic!("a commands call");
    };
    assert_eq!(SceneId::from(request.commands[0].uuid), id(3));
}

#[test]
fn coop_relay_report_1_a_finished_scene_still_listed_is_not_reported_again() {
    let mut bench = Bench::new(false);
    bench.register(LANE, 1, true);
    bench.settle();
    bench
        .module(LANE)
        .update(id(1), true, Phase::Running, false);
    bench
        .module(LANE)
        .update(id(1), true, Phase::Succeeded, false);
    // Each cycle asserts that no status was refused.
    bench.settle();
    assert!(bench.relay.state().scene(id(1)).is_none());
    assert!(bench.relay.state().retirement(id(1)).is_some());
}

#[test]
fn coop_relay_report_1_an_avoidance_scene_is_the_shift_outs() {
    let mut bench = Bench::new(true);
    const AVOID: &str = "static_obstacle_avoidance_left";
    bench
        .modules
        .insert(AVOID, Upstream::new(rtc::Module::AVOIDANCE_LEFT, true));
    bench.answering.insert(AVOID, true);
    bench.register(AVOID, 7, true);
    bench.settle();
    let module = bench.relay.state().scene(id(7)).unwrap().module();
    assert_eq!(module.sequence, cooperation::Sequence::Change);
    let response = bench.operator(command(id(7), OperatorDecision::Activate));
    assert!(status(&response).success);
    bench.assert_follows();
}

#[test]
fn coop_relay_policy_1_the_standing_decisions_follow_the_switch_at_once() {
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, false);
    bench.settle();
    let response = bench.operator(command(id(1), OperatorDecision::Activate));
    assert!(status(&response).success);
    let now = bench.now();
    let request = policy("lane-change", Policy::Optional);
    assert!(bench
        .relay
        .handle_operator(OperatorCall(50), &request, now)
        .is_none());
    let switch = bench.relay.poll_forward(now).expect("the switch");
    assert_eq!(
        switch.request,
        ModuleRequest::AutoMode(rtc::AutoModeRequest { enable: true })
    );
    let answer = ModuleAnswer::AutoMode(bench.module(LANE).enable_auto_mode(true));
    assert!(bench.relay.take_answer(switch.call, &answer, now));
    // No array has come since: the standing decision goes out with the switch's answer.
    let resend = bench
        .relay
        .poll_forward(now)
        .expect("the standing decision again");
    let ModuleRequest::Commands(request) = &resend.request else {
        panic!("a commands call");
    };
    assert_eq!(request.commands.len(), 1);
    assert_eq!(SceneId::from(request.commands[0].uuid), id(1));
    assert_eq!(request.commands[0].command.r#type, rtc::Command::ACTIVATE);
}

#[test]
fn coop_relay_policy_1_a_switch_the_module_answered_is_not_sent_again() {
    // Auto mode on (optional), then required: the module switches it off.
    let mut bench = Bench::new(false);
    bench.register(LANE, 1, false);
    bench.settle();
    let response = bench.operator(command(id(1), OperatorDecision::Activate));
    assert!(status(&response).success);
    let response = bench.operator(policy("lane-change", Policy::Required));
    assert!(status(&response).success);
    bench.pump();
    // The module's next array comes before its auto-mode status, which still said "on" when
    // the relay last read it: the switch it answered is not sent again.
    bench.clock_ms += 10;
    let now = bench.now();
    let array = bench.module(LANE).status_array(now.stamp);
    bench.relay.take_statuses(LANE, &array, now).unwrap();
    bench.relay.handle_timeout(now);
    while let Some(forward) = bench.relay.poll_forward(now) {
        assert_ne!(
            forward.request,
            ModuleRequest::AutoMode(rtc::AutoModeRequest { enable: false }),
            "the switch sent again"
        );
    }
}

#[test]
fn coop_relay_follow_1_a_queued_switch_the_module_has_since_taken_is_not_sent() {
    // Required, the module's auto mode off; the operator makes it optional before the relay
    // has heard from the module, so the relay queues the switch on when it does ...
    let mut bench = Bench::new(true);
    bench.register(LANE, 1, false);
    let response = bench.operator(policy("lane-change", Policy::Optional));
    assert!(status(&response).success);
    bench.cycle();
    // ... but before it is handed out, someone else switches the module on, and the relay is
    // told: the queued switch is not sent.
    bench.module(LANE).enable_auto_mode(true);
    bench.cycle();
    let now = bench.now();
    if let Some(forward) = bench.relay.poll_forward(now) {
        let answer = match &forward.request {
            ModuleRequest::AutoMode(request) => {
                assert!(
                    !request.enable,
                    "a switch to the auto mode the module was heard to have"
                );
                ModuleAnswer::AutoMode(bench.module(LANE).enable_auto_mode(request.enable))
            }
            ModuleRequest::Commands(request) => {
                ModuleAnswer::Commands(bench.module(LANE).cooperate_commands(request))
            }
        };
        assert!(bench.relay.take_answer(forward.call, &answer, now));
    }
    // The module, left alone, drives as the AD API shows.
    bench.settle();
    bench.assert_follows();
}
