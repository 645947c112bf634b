//! The RTC compatibility adapter: upstream's edge cases (`upstream-rtc` notes §6) as they apply
//! here, the statuses it publishes, and the messages' JSON shapes and round trips.

mod common;

use common::*;
use cooperation::rtc::{self, Rtc};
use cooperation::*;
use proptest::prelude::*;

const LEFT: &str = "lane_change_left";

fn report(
    rtc: &mut Rtc,
    state: &mut State,
    name: &str,
    id: SceneId,
    safe: bool,
    rtc_state: u8,
) -> Result<Vec<Rule>, rtc::RtcError> {
    let mut interface = rtc.interface(state, name).expect("bound");
    let transitions = interface.update_cooperate_status(id, safe, rtc_state, 10.0, 60.0, false)?;
    Ok(transitions.into_iter().map(|t| t.rule).collect())
}

fn command(rtc: &mut Rtc, state: &mut State, name: &str, id: SceneId, command: u8) -> bool {
    let mut interface = rtc.interface(state, name).expect("bound");
    let reply = interface.cooperate_commands(&rtc_commands(&[(id, command)]));
    assert_eq!(reply.response.responses.len(), 1);
    let success = reply.response.responses[0].success;
    assert_eq!(success, reply.result.is_ok(), "{reply:?}");
    success
}

fn auto_mode(rtc: &mut Rtc, state: &mut State, name: &str, enable: bool) {
    let reply = rtc
        .interface(state, name)
        .expect("bound")
        .auto_mode(&rtc::AutoModeRequest { enable });
    assert!(reply.response.success, "{reply:?}");
}

// ---------------------------------------------------------------------------------------------
// Registration and lifecycle
// ---------------------------------------------------------------------------------------------

/// §6.1: an unknown identifier reported running registers and runs; the other fields are
/// stored; the command status starts DEACTIVATE.
#[test]
fn an_unknown_scene_reported_running_registers_with_its_fields() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut interface = rtc.interface(&mut state, LEFT).expect("bound");
    interface
        .update_cooperate_status(id(1), false, rtc::State::RUNNING, 12.5, 80.0, true)
        .expect("registers");
    let array = interface
        .view()
        .cooperate_status_array(rtc::Time::new(5, 0));
    let status = array.statuses[0];
    assert_eq!(status.uuid, id(1).into());
    assert_eq!(status.module.r#type, rtc::Module::LANE_CHANGE_LEFT);
    assert!(!status.safe);
    assert!(status.requested);
    assert_eq!(status.command_status.r#type, rtc::Command::DEACTIVATE);
    assert_eq!(status.state.r#type, rtc::State::RUNNING);
    assert!(status.auto_mode);
    assert_eq!(
        (status.start_distance, status.finish_distance),
        (12.5, 80.0)
    );
    assert_eq!(status.stamp, rtc::Time::new(5, 0));
}

/// §6.2: a forbidden transition changes nothing at all, and says so.
#[test]
fn a_forbidden_transition_changes_nothing_and_is_reported() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let before = state.clone();
    let error = report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        false,
        rtc::State::SUCCEEDED,
    )
    .expect_err("waiting cannot become succeeded");
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::OwnerTransition)
    );
    assert_eq!(state, before);
}

/// §6.3: a scene whose updates are all refused ages and expires, as upstream (a refused update
/// refreshes nothing); the expiring tick names it.
#[test]
fn a_scene_kept_only_by_refused_updates_expires() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    for _ in 0..10 {
        report(
            &mut rtc,
            &mut state,
            LEFT,
            id(1),
            true,
            rtc::State::ABORTING,
        )
        .expect_err("waiting cannot become aborting");
        let tick = rtc.tick(&mut state, 1_000).expect("ticks");
        assert_eq!(tick.rule, Rule::TimeAge);
    }
    let tick = rtc.tick(&mut state, 1).expect("ticks");
    assert_eq!((tick.rule, tick.retired), (Rule::TimeExpire, vec![id(1)]));
    let view = rtc.view(&state, LEFT).expect("bound");
    assert!(!view.is_registered(id(1)));
    assert_eq!(
        view.is_terminated(id(1)),
        Some(false),
        "expired, not finished"
    );
}

/// §6.4 and §6.5: succeeded retires at once (upstream keeps it listed and accepts succeeded
/// again); reporting it again is refused and it stays terminated.
#[test]
fn succeeded_retires_at_once_and_cannot_be_reported_again() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(&mut rtc, &mut state, LEFT, id(1), true, rtc::State::RUNNING).expect("runs");
    assert_eq!(
        report(
            &mut rtc,
            &mut state,
            LEFT,
            id(1),
            true,
            rtc::State::SUCCEEDED
        ),
        Ok(vec![Rule::OwnerFinish])
    );
    let error = report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::SUCCEEDED,
    )
    .expect_err("retired");
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::RegisterRetired)
    );
    let view = rtc.view(&state, LEFT).expect("bound");
    assert!(view
        .cooperate_status_array(rtc::Time::default())
        .statuses
        .is_empty());
    assert_eq!(view.is_terminated(id(1)), Some(true));
}

/// §6.6: one identifier cannot live in two interfaces, even two of the same core module; and
/// each interface answers only for its own scenes.
#[test]
fn a_scene_belongs_to_the_interface_that_registered_it() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let before = state.clone();
    for other in ["lane_change_right", "intersection"] {
        let error = report(
            &mut rtc,
            &mut state,
            other,
            id(1),
            true,
            rtc::State::RUNNING,
        )
        .expect_err("another interface's scene");
        assert_eq!(
            error.to_string(),
            format!(
                "scene {} belongs to RTC interface \"lane_change_left\", not \"{other}\"",
                id(1)
            )
        );
        let mut interface = rtc.interface(&mut state, other).expect("bound");
        assert!(!interface.view().is_registered(id(1)));
        assert!(!interface.view().is_activated(id(1)));
        assert_eq!(interface.view().is_rtc_enabled(id(1)), None);
        assert_eq!(interface.view().is_terminated(id(1)), None);
        assert!(interface.remove_cooperate_status(id(1)).is_err());
        assert!(interface
            .clear_cooperate_status()
            .expect("clears")
            .is_empty());
        assert!(!command(
            &mut rtc,
            &mut state,
            other,
            id(1),
            rtc::Command::ACTIVATE
        ));
    }
    assert_eq!(state, before);
    assert_eq!(
        rtc.owner(&state, id(1)).map(|b| b.name.as_str()),
        Some(LEFT)
    );
}

/// §6.33: after a clear the same identifier does not register afresh.
#[test]
fn a_cleared_identifier_is_not_registered_again() {
    let (mut rtc, mut state) = rtc_setup(false);
    for n in 1..=2 {
        report(
            &mut rtc,
            &mut state,
            LEFT,
            id(n),
            true,
            rtc::State::WAITING_FOR_EXECUTION,
        )
        .expect("registers");
    }
    let cleared = rtc
        .interface(&mut state, LEFT)
        .expect("bound")
        .clear_cooperate_status()
        .expect("clears");
    assert_eq!(cleared, [id(1), id(2)]);
    assert_eq!(state.scene_count(), 0);
    let error = report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect_err("retired");
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::RegisterRetired)
    );
}

// ---------------------------------------------------------------------------------------------
// Commands
// ---------------------------------------------------------------------------------------------

/// §6.7 and §6.15: a command for an unknown identifier fails and does not wait for the scene.
#[test]
fn a_command_for_an_unknown_scene_fails_and_is_not_kept() {
    let (mut rtc, mut state) = rtc_setup(true);
    assert!(!command(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        rtc::Command::ACTIVATE
    ));
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        false,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let view = rtc.view(&state, LEFT).expect("bound");
    assert!(!view.is_activated(id(1)));
    assert!(!view.is_force_activated(id(1)));
}

/// §6.8: a command for an aborting scene fails.
#[test]
fn a_command_for_an_aborting_scene_fails() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(&mut rtc, &mut state, LEFT, id(1), true, rtc::State::RUNNING).expect("runs");
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::ABORTING,
    )
    .expect("aborts");
    let mut interface = rtc.interface(&mut state, LEFT).expect("bound");
    let reply = interface.cooperate_commands(&rtc_commands(&[(id(1), rtc::Command::DEACTIVATE)]));
    assert!(!reply.response.responses[0].success);
    let rejection = reply.result.expect_err("refused");
    assert_eq!(
        rejection.rejection().map(Rejection::rule),
        Some(Rule::CommandNotCancellable)
    );
}

/// §6.9: a command takes the one scene out of auto mode; the others and the module's auto mode
/// are unaffected.
#[test]
fn a_command_affects_only_its_scene() {
    let (mut rtc, mut state) = rtc_setup(false);
    for n in 1..=2 {
        report(
            &mut rtc,
            &mut state,
            LEFT,
            id(n),
            true,
            rtc::State::WAITING_FOR_EXECUTION,
        )
        .expect("registers");
    }
    assert!(command(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        rtc::Command::DEACTIVATE
    ));
    let view = rtc.view(&state, LEFT).expect("bound");
    assert_eq!(view.is_rtc_enabled(id(1)), Some(true));
    assert!(!view.is_activated(id(1)));
    assert_eq!(view.is_rtc_enabled(id(2)), Some(false));
    assert!(view.is_activated(id(2)));
    assert!(view.auto_mode_status().is_auto_mode);
    let statuses = view.cooperate_status_array(rtc::Time::default()).statuses;
    let auto: Vec<bool> = statuses.iter().map(|s| s.auto_mode).collect();
    assert_eq!(auto, [false, true]);
}

/// §6.11 and §6.12: a command's module and the request's stamp do not select the scene; the
/// identifier does.
#[test]
fn commands_are_matched_by_identifier() {
    let (mut rtc, mut state) = rtc_setup(true);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let mut request = rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]);
    request.stamp = rtc::Time::new(-5, 7);
    request.commands[0].module = rtc::Module::new(rtc::Module::INTERSECTION);
    let reply = rtc
        .interface(&mut state, LEFT)
        .expect("bound")
        .cooperate_commands(&request);
    assert!(reply.response.responses[0].success);
    assert_eq!(
        reply.response.responses[0].module,
        request.commands[0].module
    );
    assert_eq!(reply.response.responses[0].uuid, request.commands[0].uuid);
    assert!(rtc.view(&state, LEFT).expect("bound").is_activated(id(1)));
}

/// A batch with one failing command applies none of them, and every response says so.
#[test]
fn a_failing_command_withholds_the_batch() {
    let (mut rtc, mut state) = rtc_setup(true);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let reply = rtc
        .interface(&mut state, LEFT)
        .expect("bound")
        .cooperate_commands(&rtc_commands(&[
            (id(1), rtc::Command::ACTIVATE),
            (id(9), rtc::Command::ACTIVATE),
        ]));
    let successes: Vec<bool> = reply.response.responses.iter().map(|r| r.success).collect();
    assert_eq!(successes, [false, false]);
    let Some(Rejection::Commands { outcomes, .. }) =
        reply.result.expect_err("refused").rejection().cloned()
    else {
        panic!("a command rejection")
    };
    assert_eq!(
        outcomes,
        [
            CommandOutcome::Withheld,
            CommandOutcome::Failed(CommandFailure::UnknownScene)
        ]
    );
    assert!(!rtc.view(&state, LEFT).expect("bound").is_activated(id(1)));
}

// ---------------------------------------------------------------------------------------------
// Auto mode, `safe` and `requested`
// ---------------------------------------------------------------------------------------------

/// §6.19 and §6.25: with auto mode on, activated follows `safe`, unless `requested`.
#[test]
fn auto_mode_follows_safe_unless_requested() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut interface = rtc.interface(&mut state, "crosswalk").expect("bound");
    for (n, safe, requested, activated) in [
        (1, true, false, true),
        (2, false, false, false),
        (3, true, true, false),
    ] {
        interface
            .update_cooperate_status(
                id(n),
                safe,
                rtc::State::WAITING_FOR_EXECUTION,
                8.0,
                8.0,
                requested,
            )
            .expect("registers");
        assert_eq!(interface.view().is_activated(id(n)), activated, "scene {n}");
    }
}

/// §6.20: an auto-mode switch keeps operator decisions (upstream overwrites them) and always
/// answers.
#[test]
fn auto_mode_switches_keep_operator_decisions() {
    let (mut rtc, mut state) = rtc_setup(true);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        false,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    assert!(command(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        rtc::Command::ACTIVATE
    ));
    for enable in [true, false, true] {
        auto_mode(&mut rtc, &mut state, LEFT, enable);
        let view = rtc.view(&state, LEFT).expect("bound");
        assert_eq!(view.auto_mode_status().is_auto_mode, enable);
        assert!(view.is_activated(id(1)), "the operator's ACTIVATE stands");
        assert_eq!(view.is_rtc_enabled(id(1)), Some(true));
    }
}

/// §6.21: switching auto mode off under a running auto-executed scene holds it back, and that
/// is the policy's doing, not the operator's: it is not force-deactivated (upstream: it is).
#[test]
fn auto_mode_off_is_not_a_force_deactivation() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(&mut rtc, &mut state, LEFT, id(1), true, rtc::State::RUNNING).expect("runs");
    assert!(rtc.view(&state, LEFT).expect("bound").is_activated(id(1)));
    auto_mode(&mut rtc, &mut state, LEFT, false);
    let view = rtc.view(&state, LEFT).expect("bound");
    assert!(!view.is_activated(id(1)));
    assert!(!view.is_force_deactivated(id(1)), "[COOP-DEV-FORCE.1]");
}

/// §6.22: an operator's ACTIVATE of an unsafe scene stays activated when auto mode comes on;
/// force-activated and activated agree (upstream: not activated, yet force-activated).
#[test]
fn force_activated_agrees_with_activated_after_auto_mode_on() {
    let (mut rtc, mut state) = rtc_setup(true);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        false,
        rtc::State::RUNNING,
    )
    .expect("runs");
    assert!(command(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        rtc::Command::ACTIVATE
    ));
    auto_mode(&mut rtc, &mut state, LEFT, true);
    let view = rtc.view(&state, LEFT).expect("bound");
    assert!(view.is_force_activated(id(1)));
    assert!(
        view.is_activated(id(1)),
        "[COOP-DEV-FORCE.1] [COOP-DEV-POLICY-CLOBBER.1]"
    );
}

/// §6.26 and §6.27: ACTIVATE on a requested scene is forced even when safe; force-deactivated
/// ignores `requested`.
#[test]
fn requested_scenes_and_the_force_flags() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut interface = rtc
        .interface(&mut state, "static_obstacle_avoidance_left")
        .expect("bound");
    interface
        .update_cooperate_status(
            id(1),
            true,
            rtc::State::WAITING_FOR_EXECUTION,
            3.0,
            20.0,
            true,
        )
        .expect("registers");
    assert!(!interface.view().is_activated(id(1)));
    let reply = interface.cooperate_commands(&rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]));
    assert!(reply.result.is_ok());
    assert!(interface.view().is_activated(id(1)));
    assert!(interface.view().is_force_activated(id(1)));
    interface
        .update_cooperate_status(id(1), true, rtc::State::RUNNING, 0.0, 17.0, true)
        .expect("runs");
    let reply = interface.cooperate_commands(&rtc_commands(&[(id(1), rtc::Command::DEACTIVATE)]));
    assert!(reply.result.is_ok());
    assert!(interface.view().is_force_deactivated(id(1)));
}

/// §6.28: an aborting scene can still be activated (auto mode, safe), as upstream; it is not
/// force-activated, since no command is accepted while aborting.
#[test]
fn an_aborting_scene_can_be_activated_as_upstream() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(&mut rtc, &mut state, LEFT, id(1), true, rtc::State::RUNNING).expect("runs");
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::ABORTING,
    )
    .expect("aborts");
    let view = rtc.view(&state, LEFT).expect("bound");
    assert!(view.is_activated(id(1)));
    assert!(!view.is_force_activated(id(1)));
    assert_eq!(view.is_terminated(id(1)), Some(false));
}

// ---------------------------------------------------------------------------------------------
// Statuses
// ---------------------------------------------------------------------------------------------

/// §6.29: each status is stamped with its owner's last report: the array's stamp less the
/// scene's age.
#[test]
fn statuses_are_stamped_with_the_last_report() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    rtc.tick(&mut state, 1_500).expect("ticks");
    report(
        &mut rtc,
        &mut state,
        LEFT,
        id(2),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    rtc.tick(&mut state, 250).expect("ticks");
    let array = rtc
        .view(&state, LEFT)
        .expect("bound")
        .cooperate_status_array(rtc::Time::new(10, 100_000_000));
    let stamps: Vec<rtc::Time> = array.statuses.iter().map(|s| s.stamp).collect();
    assert_eq!(
        stamps,
        [
            rtc::Time::new(8, 350_000_000),
            rtc::Time::new(9, 850_000_000)
        ]
    );
    assert_eq!(
        rtc::Time::new(0, 0).before_ms(1),
        rtc::Time::new(-1, 999_000_000)
    );
    assert_eq!(
        rtc::Time::new(i32::MIN, 0).before_ms(u64::MAX),
        rtc::Time::new(i32::MIN, 0)
    );
}

/// §6.31: the external API's array holds every interface's scenes, nearest start first; a
/// velocity scene reports its one distance as start and finish.
#[test]
fn the_external_array_is_ordered_by_start_distance() {
    let (mut rtc, mut state) = rtc_setup(false);
    for (n, name, start) in [
        (1, LEFT, 50.0),
        (2, "intersection", 20.0),
        (3, "static_obstacle_avoidance_right", -3.0),
        (4, "crosswalk", f32::NAN),
    ] {
        rtc_register_at(&mut rtc, &mut state, name, n, start);
    }
    let array = rtc.cooperate_status_array(&state, rtc::Time::new(3, 0));
    let order: Vec<SceneId> = array.statuses.iter().map(|s| s.uuid.into()).collect();
    assert_eq!(order, [id(3), id(2), id(1), id(4)], "NaN last");
    let intersection = array.statuses[1];
    assert_eq!(intersection.module.r#type, rtc::Module::INTERSECTION);
    assert_eq!(
        (intersection.start_distance, intersection.finish_distance),
        (20.0, 20.0)
    );
    let modes = rtc.auto_mode_status_array(&state, rtc::Time::new(3, 0));
    assert_eq!(modes.statuses.len(), rtc.bindings().len());
    assert!(modes.statuses.iter().all(|s| s.is_auto_mode));
}

/// The same scenes are the AD API's factors: a steering interface's scene is a steering
/// factor of its core module, turning its way.
#[test]
fn rtc_scenes_are_ad_api_factors() {
    let (mut rtc, mut state) = rtc_setup(false);
    report(
        &mut rtc,
        &mut state,
        "lane_change_right",
        id(1),
        true,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    report(
        &mut rtc,
        &mut state,
        "traffic_light",
        id(2),
        false,
        rtc::State::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let mut steering = Vec::new();
    state.steering_factors_into(&mut steering);
    assert_eq!(steering.len(), 1);
    assert_eq!(steering[0].behavior, Behavior::LaneChange);
    assert_eq!(steering[0].direction, Direction::Right);
    assert_eq!(steering[0].distances, [Distance(10.0), Distance(60.0)]);
    let mut velocity = Vec::new();
    state.velocity_factors_into(&mut velocity);
    assert_eq!(velocity.len(), 1);
    assert_eq!(velocity[0].behavior, Behavior::TrafficSignal);
    assert_eq!(
        velocity[0].cooperation.module_decision,
        Decision::Deactivate
    );
}

// ---------------------------------------------------------------------------------------------
// Configuration
// ---------------------------------------------------------------------------------------------

#[test]
fn bindings_are_checked() {
    let twice = [
        rtc::Binding::standard()[0].clone(),
        rtc::Binding::standard()[0].clone(),
    ];
    assert_eq!(
        rtc::Rtc::new(twice),
        Err(rtc::RtcError::DuplicateInterface { name: LEFT.into() })
    );
    let names: std::collections::BTreeSet<String> = rtc::Binding::standard()
        .into_iter()
        .map(|b| b.name)
        .collect();
    assert_eq!(names.len(), rtc::Binding::standard().len());
    // A core without the module's policy cannot serve the interface.
    let mut state = State::new(Config::new([(
        Module::new(Behavior::Crosswalk),
        Policy::Optional,
    )]))
    .expect("valid");
    let mut rtc = Rtc::standard();
    assert!(rtc.interface(&mut state, "crosswalk").is_ok());
    let error = rtc.interface(&mut state, LEFT).expect_err("unconfigured");
    assert_eq!(
        error.to_string(),
        "RTC interface \"lane_change_left\" is bound to module lane-change, which has no cooperation policy"
    );
}

#[test]
fn routes_follow_what_the_core_remembers() {
    let mut config = Config::new(Rtc::standard().policies(false));
    config.limits.retired_capacity = 2;
    let mut state = State::new(config).expect("valid");
    let mut rtc = Rtc::standard();
    for n in 1..=5 {
        let mut interface = rtc.interface(&mut state, LEFT).expect("bound");
        interface
            .update_cooperate_status(
                id(n),
                true,
                rtc::State::WAITING_FOR_EXECUTION,
                1.0,
                2.0,
                false,
            )
            .expect("registers");
        interface.remove_cooperate_status(id(n)).expect("removes");
    }
    let owners: Vec<bool> = (1..=5)
        .map(|n| rtc.owner(&state, id(n)).is_some())
        .collect();
    assert_eq!(
        owners,
        [false, false, false, true, true],
        "the core forgot 1 to 3"
    );
    let view = rtc.view(&state, LEFT).expect("bound");
    assert_eq!(view.is_terminated(id(1)), None);
    assert_eq!(view.is_terminated(id(5)), Some(false));
}

// ---------------------------------------------------------------------------------------------
// Messages
// ---------------------------------------------------------------------------------------------

#[test]
fn json_shapes_are_rosbridge_shapes() {
    let status = rtc::CooperateStatus {
        stamp: rtc::Time::new(1, 2),
        uuid: SceneId::from_u128(0x0102).into(),
        module: rtc::Module::new(rtc::Module::CROSSWALK),
        safe: true,
        requested: false,
        command_status: rtc::Command::new(rtc::Command::ACTIVATE),
        state: rtc::State::new(rtc::State::RUNNING),
        auto_mode: false,
        start_distance: 1.5,
        finish_distance: 2.5,
    };
    let json = serde_json::to_value(status).expect("serializes");
    assert_eq!(
        json,
        serde_json::json!({
            "stamp": {"sec": 1, "nanosec": 2},
            "uuid": {"uuid": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2]},
            "module": {"type": 10},
            "safe": true,
            "requested": false,
            "command_status": {"type": 1},
            "state": {"type": 1},
            "auto_mode": false,
            "start_distance": 1.5,
            "finish_distance": 2.5
        })
    );
    // `requested` is absent in messages from before it existed.
    let mut older = json.clone();
    older.as_object_mut().expect("object").remove("requested");
    assert_eq!(
        serde_json::from_value::<rtc::CooperateStatus>(older).expect("reads"),
        status
    );
}

#[test]
fn a_hand_written_command_request_parses() {
    let text = r#"{
        "stamp": {"sec": 0, "nanosec": 0},
        "commands": [
            {"uuid": {"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,7]}, "module": {"type": 1}, "command": {"type": 1}},
            {"uuid": {"uuid": "AAAAAAAAAAAAAAAAAAAACA=="}, "module": {"type": 0}, "command": {"type": 0}}
        ]
    }"#;
    let request: rtc::CooperateCommandsRequest = serde_json::from_str(text).expect("reads");
    assert_eq!(
        request.parse(),
        Ok(vec![
            Command {
                id: id(7),
                decision: OperatorDecision::Activate
            },
            Command {
                id: id(8),
                decision: OperatorDecision::Deactivate
            },
        ])
    );
    for bad in [
        r#"{"uuid": [1, 2, 3]}"#,
        r#"{"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]}"#,
        r#"{"uuid": [0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,256]}"#,
        r#"{"uuid": "AAAA"}"#,
        r#"{"uuid": 5}"#,
    ] {
        assert!(serde_json::from_str::<rtc::Uuid>(bad).is_err(), "{bad}");
    }
}

#[test]
fn statuses_parse_with_the_field_named() {
    let mut array = rtc::CooperateStatusArray {
        stamp: rtc::Time::default(),
        statuses: vec![rtc::CooperateStatus::default(); 2],
    };
    let parsed = array.parse().expect("all zero is valid");
    assert_eq!(parsed[0].phase, Phase::WaitingForExecution);
    assert_eq!(parsed[0].module, rtc::ModuleType::None);
    assert_eq!(parsed[0].command, Decision::Deactivate);
    array.statuses[1].state = rtc::State::new(9);
    assert_eq!(
        array.parse().expect_err("undefined").field,
        "statuses[1].state.type"
    );
    array.statuses[1].state = rtc::State::new(rtc::State::ABORTING);
    array.statuses[1].module = rtc::Module::new(20);
    assert_eq!(
        array.parse().expect_err("undefined").to_string(),
        "statuses[1].module.type is 20, which is not a Module constant (0 to 19)"
    );
}

#[test]
fn constants_convert_both_ways() {
    for phase in Phase::ALL {
        assert_eq!(rtc::State::from(phase).phase(), Ok(phase));
    }
    for decision in Decision::ALL {
        assert_eq!(rtc::Command::from(decision).decision(), Ok(decision));
    }
    for module in rtc::ModuleType::ALL {
        assert_eq!(rtc::Module::from(module).module_type(), Ok(module));
    }
    assert_eq!(rtc::policy_for_auto_mode(true), Policy::Optional);
    assert_eq!(rtc::policy_for_auto_mode(false), Policy::Required);
}

fn any_time() -> impl Strategy<Value = rtc::Time> {
    (any::<i32>(), 0..1_000_000_000u32).prop_map(|(sec, nanosec)| rtc::Time { sec, nanosec })
}

fn any_uuid() -> impl Strategy<Value = rtc::Uuid> {
    any::<[u8; 16]>().prop_map(|uuid| rtc::Uuid { uuid })
}

fn any_module() -> impl Strategy<Value = rtc::Module> {
    any::<u8>().prop_map(rtc::Module::new)
}

fn any_distance() -> impl Strategy<Value = f32> {
    // JSON has no NaN or infinity.
    prop_oneof![
        -1.0e6f32..1.0e6,
        Just(0.0),
        Just(-0.0),
        Just(f32::MAX),
        Just(f32::MIN_POSITIVE)
    ]
}

fn any_status() -> impl Strategy<Value = rtc::CooperateStatus> {
    (
        (
            any_time(),
            any_uuid(),
            any_module(),
            any::<bool>(),
            any::<bool>(),
        ),
        (
            any::<u8>(),
            any::<u8>(),
            any::<bool>(),
            any_distance(),
            any_distance(),
        ),
    )
        .prop_map(
            |(
                (stamp, uuid, module, safe, requested),
                (command, state, auto_mode, start, finish),
            )| {
                rtc::CooperateStatus {
                    stamp,
                    uuid,
                    module,
                    safe,
                    requested,
                    command_status: rtc::Command::new(command),
                    state: rtc::State::new(state),
                    auto_mode,
                    start_distance: start,
                    finish_distance: finish,
                }
            },
        )
}

fn any_command() -> impl Strategy<Value = rtc::CooperateCommand> {
    (any_uuid(), any_module(), any::<u8>()).prop_map(|(uuid, module, command)| {
        rtc::CooperateCommand {
            uuid,
            module,
            command: rtc::Command::new(command),
        }
    })
}

fn round_trips<T>(value: &T) -> Result<(), TestCaseError>
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + core::fmt::Debug,
{
    let text = serde_json::to_string(value).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let back: T = serde_json::from_str(&text).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(&back, value, "{}", text);
    Ok(())
}

proptest! {
    #[test]
    fn every_message_round_trips_through_json(
        time in any_time(),
        uuid in any_uuid(),
        module in any_module(),
        command in any::<u8>(),
        state in any::<u8>(),
        statuses in proptest::collection::vec(any_status(), 0..4),
        commands in proptest::collection::vec(any_command(), 0..4),
        flags in any::<[bool; 2]>(),
    ) {
        let [enable, success] = flags;
        round_trips(&time)?;
        round_trips(&uuid)?;
        round_trips(&module)?;
        round_trips(&rtc::Command::new(command))?;
        round_trips(&rtc::State::new(state))?;
        for status in &statuses {
            round_trips(status)?;
        }
        round_trips(&rtc::CooperateStatusArray { stamp: time, statuses })?;
        for command in &commands {
            round_trips(command)?;
            round_trips(&rtc::CooperateResponse { uuid: command.uuid, module: command.module, success })?;
        }
        round_trips(&rtc::CooperateCommandsResponse {
            responses: commands
                .iter()
                .map(|c| rtc::CooperateResponse { uuid: c.uuid, module: c.module, success })
                .collect(),
        })?;
        round_trips(&rtc::CooperateCommandsRequest { stamp: time, commands })?;
        let auto = rtc::AutoModeStatus { module, is_auto_mode: enable };
        round_trips(&auto)?;
        round_trips(&rtc::AutoModeStatusArray { stamp: time, statuses: vec![auto; 3] })?;
        round_trips(&rtc::AutoModeRequest { enable })?;
        round_trips(&rtc::AutoModeResponse { success })?;
        round_trips(&rtc::AutoModeWithModuleRequest { module, enable })?;
        round_trips(&rtc::AutoModeWithModuleResponse { success })?;
        round_trips(&rtc::ModuleType::from_value(module.r#type).unwrap_or(rtc::ModuleType::None))?;
    }

    /// A UUID reads the same from its array and from rosbridge's base64 form.
    #[test]
    fn uuid_reads_from_base64(bytes in any::<[u8; 16]>()) {
        let base64 = encode_base64(&bytes);
        let from_text: rtc::Uuid =
            serde_json::from_value(serde_json::json!({ "uuid": base64 })).expect("reads");
        prop_assert_eq!(from_text.uuid, bytes);
    }
}

/// Standard base64 with padding, to check the decoder against.
fn encode_base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let mut block = [0u8; 3];
        block[..chunk.len()].copy_from_slice(chunk);
        let n = (u32::from(block[0]) << 16) | (u32::from(block[1]) << 8) | u32::from(block[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                out.push(char::from(ALPHABET[((n >> (18 - 6 * i)) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}
