//! Auto mode, `safe` and `requested`, and the force flags.

use super::*;

// ---------------------------------------------------------------------------------------------
// Auto mode, `safe` and `requested`
// ---------------------------------------------------------------------------------------------

/// §6.19 and §6.25: with auto mode on, activated follows `safe`, unless `requested`.
#[test]
fn auto_mode_follows_safe_unless_requested() {
    let mut fx = Fixture::new(false);
    let mut interface = fx.rtc.interface(&mut fx.state, "crosswalk").expect("bound");
    for (n, safe, requested, activated) in [
        (1, true, false, true),
        (2, false, false, false),
        (3, true, true, false),
    ] {
        interface
            .update_as_upstream(
                id(n),
                safe,
                rtc::Lifecycle::WAITING_FOR_EXECUTION,
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
    let mut fx = Fixture::new(true);
    fx.report(LEFT, id(1), false, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    assert!(fx.command(LEFT, id(1), rtc::Command::ACTIVATE));
    for enable in [true, false, true] {
        fx.auto_mode(LEFT, enable);
        let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
        assert_eq!(view.auto_mode_status().is_auto_mode, enable);
        assert!(view.is_activated(id(1)), "the operator's ACTIVATE stands");
        assert_eq!(view.is_rtc_enabled(id(1)), Some(true));
    }
}

/// §6.21: switching auto mode off under a running auto-executed scene holds it back, and that
/// is the policy's doing, not the operator's: it is not force-deactivated (upstream: it is).
#[test]
fn auto_mode_off_is_not_a_force_deactivation() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::RUNNING)
        .expect("runs");
    assert!(fx
        .rtc
        .view(&fx.state, LEFT)
        .expect("bound")
        .is_activated(id(1)));
    fx.auto_mode(LEFT, false);
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
    assert!(!view.is_activated(id(1)));
    assert!(!view.is_force_deactivated(id(1)), "[COOP-DEV-FORCE.1]");
}

/// §6.22: an operator's ACTIVATE of an unsafe scene stays activated when auto mode comes on;
/// force-activated and activated agree (upstream: not activated, yet force-activated).
#[test]
fn force_activated_agrees_with_activated_after_auto_mode_on() {
    let mut fx = Fixture::new(true);
    fx.report(LEFT, id(1), false, rtc::Lifecycle::RUNNING)
        .expect("runs");
    assert!(fx.command(LEFT, id(1), rtc::Command::ACTIVATE));
    fx.auto_mode(LEFT, true);
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
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
    let mut fx = Fixture::new(false);
    let mut interface = fx
        .rtc
        .interface(&mut fx.state, "static_obstacle_avoidance_left")
        .expect("bound");
    interface
        .update_as_upstream_in(
            id(1),
            Sequence::Change,
            true,
            rtc::Lifecycle::WAITING_FOR_EXECUTION,
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
        .update_as_upstream(id(1), true, rtc::Lifecycle::RUNNING, 0.0, 17.0, true)
        .expect("runs");
    let reply = interface.cooperate_commands(&rtc_commands(&[(id(1), rtc::Command::DEACTIVATE)]));
    assert!(reply.result.is_ok());
    assert!(interface.view().is_force_deactivated(id(1)));
}

/// §6.28: an aborting scene can still be activated (auto mode, safe), as upstream; it is not
/// force-activated, since no command is accepted while aborting.
#[test]
fn an_aborting_scene_can_be_activated_as_upstream() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::RUNNING)
        .expect("runs");
    fx.report(LEFT, id(1), true, rtc::Lifecycle::ABORTING)
        .expect("aborts");
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
    assert!(view.is_activated(id(1)));
    assert!(!view.is_force_activated(id(1)));
    assert_eq!(view.is_terminated(id(1)), Some(false));
}
