//! Registration and lifecycle: how RTC reports open, move and close scenes.

use super::*;

// ---------------------------------------------------------------------------------------------
// Registration and lifecycle
// ---------------------------------------------------------------------------------------------

/// §6.1: an unknown identifier reported running registers and runs; the other fields are
/// stored; the command status starts DEACTIVATE.
#[test]
fn an_unknown_scene_reported_running_registers_with_its_fields() {
    let mut fx = Fixture::new(false);
    let mut interface = fx.rtc.interface(&mut fx.state, LEFT).expect("bound");
    interface
        .update_as_upstream(id(1), false, rtc::Lifecycle::RUNNING, 12.5, 80.0, true)
        .expect("registers");
    let array = interface.view().cooperate_status_array(Time::new(5, 0));
    let status = array.statuses[0];
    assert_eq!(status.uuid, id(1).into());
    assert_eq!(status.module.r#type, rtc::Module::LANE_CHANGE_LEFT);
    assert!(!status.safe);
    assert!(status.requested);
    assert_eq!(status.command_status.r#type, rtc::Command::DEACTIVATE);
    assert_eq!(status.state.r#type, rtc::Lifecycle::RUNNING);
    assert!(status.auto_mode);
    assert_eq!(
        (status.start_distance, status.finish_distance),
        (12.5, 80.0)
    );
    assert_eq!(status.stamp, Time::new(5, 0));
}

/// The answer lists the transitions: a new scene reported running registers and then runs,
/// one reported waiting only registers, and a report of a live scene is its one update.
#[test]
fn a_report_answers_the_transitions_it_made() {
    let mut fx = Fixture::new(false);
    let running = fx.report(LEFT, id(1), false, rtc::Lifecycle::RUNNING);
    assert_eq!(
        running.expect("registers"),
        [Rule::RegisterNew, Rule::OwnerUpdate]
    );
    let waiting = fx.report(LEFT, id(2), true, rtc::Lifecycle::WAITING_FOR_EXECUTION);
    assert_eq!(waiting.expect("registers"), [Rule::RegisterNew]);
    let update = fx.report(LEFT, id(1), true, rtc::Lifecycle::RUNNING);
    assert_eq!(update.expect("updates"), [Rule::OwnerUpdate]);
}

/// §6.2: a forbidden transition changes nothing at all, and says so.
#[test]
fn a_forbidden_transition_changes_nothing_and_is_reported() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    let before = fx.state.clone();
    let error = fx
        .report(LEFT, id(1), false, rtc::Lifecycle::SUCCEEDED)
        .expect_err("waiting cannot become succeeded");
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::OwnerTransition)
    );
    assert_eq!(fx.state, before);
}

/// §6.3: a scene whose updates are all refused ages and expires, as upstream (a refused update
/// refreshes nothing); the expiring tick names it.
#[test]
fn a_scene_kept_only_by_refused_updates_expires() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    for _ in 0..10 {
        fx.report(LEFT, id(1), true, rtc::Lifecycle::ABORTING)
            .expect_err("waiting cannot become aborting");
        let tick = fx.rtc.tick(&mut fx.state, 1_000).expect("ticks");
        assert_eq!(tick.rule, Rule::TimeAge);
    }
    let tick = fx.rtc.tick(&mut fx.state, 1).expect("ticks");
    assert_eq!((tick.rule, tick.retired), (Rule::TimeExpire, vec![id(1)]));
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
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
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::RUNNING)
        .expect("runs");
    assert_eq!(
        fx.report(LEFT, id(1), true, rtc::Lifecycle::SUCCEEDED),
        Ok(vec![Rule::OwnerFinish])
    );
    let error = fx
        .report(LEFT, id(1), true, rtc::Lifecycle::SUCCEEDED)
        .expect_err("retired");
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::RegisterRetired)
    );
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
    assert!(view
        .cooperate_status_array(Time::default())
        .statuses
        .is_empty());
    assert_eq!(view.is_terminated(id(1)), Some(true));
}

/// §6.6: one identifier cannot live in two interfaces, even two of the same core module; and
/// each interface answers only for its own scenes.
#[test]
fn a_scene_belongs_to_the_interface_that_registered_it() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    let before = fx.state.clone();
    for other in ["lane_change_right", "intersection"] {
        let error = fx
            .report(other, id(1), true, rtc::Lifecycle::RUNNING)
            .expect_err("another interface's scene");
        assert_eq!(
            error.to_string(),
            format!(
                "scene {} belongs to RTC interface \"lane_change_left\", not \"{other}\"",
                id(1)
            )
        );
        let mut interface = fx.rtc.interface(&mut fx.state, other).expect("bound");
        assert!(!interface.view().is_registered(id(1)));
        assert!(!interface.view().is_activated(id(1)));
        assert_eq!(interface.view().is_rtc_enabled(id(1)), None);
        assert_eq!(interface.view().is_terminated(id(1)), None);
        assert!(interface.remove_cooperate_status(id(1)).is_err());
        assert!(interface
            .clear_cooperate_status()
            .expect("clears")
            .is_empty());
        assert!(!fx.command(other, id(1), rtc::Command::ACTIVATE));
    }
    assert_eq!(fx.state, before);
    assert_eq!(
        fx.rtc.owner(&fx.state, id(1)).map(|b| b.name.as_str()),
        Some(LEFT)
    );
}

/// §6.33: after a clear the same identifier does not register afresh.
#[test]
fn a_cleared_identifier_is_not_registered_again() {
    let mut fx = Fixture::new(false);
    for n in 1..=2 {
        fx.report(LEFT, id(n), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
            .expect("registers");
    }
    let cleared = fx
        .rtc
        .interface(&mut fx.state, LEFT)
        .expect("bound")
        .clear_cooperate_status()
        .expect("clears");
    assert_eq!(cleared, [id(1), id(2)]);
    assert_eq!(fx.state.scene_count(), 0);
    let error = fx
        .report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect_err("retired");
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::RegisterRetired)
    );
}

/// `[COOP-DEV-QUOTA.1]`: with a scene quota, an interface holding its quota of live scenes
/// refuses a new one, changing nothing, while its live scenes still update and another
/// interface still registers; once one of its scenes is removed, a new one registers.
#[test]
fn coop_dev_quota_1() {
    let mut fx = Fixture::new(false);
    fx.rtc = fx.rtc.clone().with_scene_quota(2);
    assert_eq!(fx.rtc.scene_quota(), Some(2));
    let waiting = rtc::Lifecycle::WAITING_FOR_EXECUTION;
    fx.report(LEFT, id(1), true, waiting).expect("first");
    fx.report(LEFT, id(2), true, waiting).expect("second");
    let before = (fx.rtc.clone(), fx.state.clone());
    let error = fx
        .report(LEFT, id(3), true, waiting)
        .expect_err("over the quota");
    assert!(
        matches!(&error, rtc::RtcError::SceneQuota { interface, quota: 2, .. } if interface == LEFT),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("already has 2 live scenes"),
        "{error}"
    );
    assert_eq!((&fx.rtc, &fx.state), (&before.0, &before.1));
    fx.report(LEFT, id(2), false, waiting)
        .expect("a live scene still updates");
    fx.report("lane_change_right", id(3), true, waiting)
        .expect("another interface has its own quota");
    fx.rtc
        .interface(&mut fx.state, LEFT)
        .expect("bound")
        .remove_cooperate_status(id(1))
        .expect("removed");
    fx.report(LEFT, id(4), true, waiting)
        .expect("a place freed");
}
