//! Operator commands through an interface and the external API.

use super::*;

// ---------------------------------------------------------------------------------------------
// Commands
// ---------------------------------------------------------------------------------------------

/// §6.7 and §6.15: a command for an unknown identifier fails and does not wait for the scene.
#[test]
fn a_command_for_an_unknown_scene_fails_and_is_not_kept() {
    let mut fx = Fixture::new(true);
    assert!(!fx.command(LEFT, id(1), rtc::Command::ACTIVATE));
    fx.report(LEFT, id(1), false, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
    assert!(!view.is_activated(id(1)));
    assert!(!view.is_force_activated(id(1)));
}

/// §6.8: a command for an aborting scene fails.
#[test]
fn a_command_for_an_aborting_scene_fails() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::RUNNING)
        .expect("runs");
    fx.report(LEFT, id(1), true, rtc::Lifecycle::ABORTING)
        .expect("aborts");
    let mut interface = fx.rtc.interface(&mut fx.state, LEFT).expect("bound");
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
    let mut fx = Fixture::new(false);
    for n in 1..=2 {
        fx.report(LEFT, id(n), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
            .expect("registers");
    }
    assert!(fx.command(LEFT, id(1), rtc::Command::DEACTIVATE));
    let view = fx.rtc.view(&fx.state, LEFT).expect("bound");
    assert_eq!(view.is_rtc_enabled(id(1)), Some(true));
    assert!(!view.is_activated(id(1)));
    assert_eq!(view.is_rtc_enabled(id(2)), Some(false));
    assert!(view.is_activated(id(2)));
    assert!(view.auto_mode_status().is_auto_mode);
    let statuses = view.cooperate_status_array(Time::default()).statuses;
    let auto: Vec<bool> = statuses.iter().map(|s| s.auto_mode).collect();
    assert_eq!(auto, [false, true]);
}

/// §6.11 and §6.12: a command's module and the request's stamp do not select the scene; the
/// identifier does.
#[test]
fn commands_are_matched_by_identifier() {
    let mut fx = Fixture::new(true);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    let mut request = rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]);
    request.stamp = Time::new(-5, 7);
    request.commands[0].module = rtc::Module::new(rtc::Module::INTERSECTION);
    let reply = fx
        .rtc
        .interface(&mut fx.state, LEFT)
        .expect("bound")
        .cooperate_commands(&request);
    assert!(reply.response.responses[0].success);
    assert_eq!(
        reply.response.responses[0].module,
        request.commands[0].module
    );
    assert_eq!(reply.response.responses[0].uuid, request.commands[0].uuid);
    assert!(fx
        .rtc
        .view(&fx.state, LEFT)
        .expect("bound")
        .is_activated(id(1)));
}

/// A batch with one failing command applies none of them, and every response says so.
#[test]
fn a_failing_command_withholds_the_batch() {
    let mut fx = Fixture::new(true);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    let reply = fx
        .rtc
        .interface(&mut fx.state, LEFT)
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
    assert!(!fx
        .rtc
        .view(&fx.state, LEFT)
        .expect("bound")
        .is_activated(id(1)));
}
