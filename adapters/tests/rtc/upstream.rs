//! Upstream's unit test of `rtc_interface` (`test_rtc_interface.cpp`, one test stepping through
//! twelve conditions), replayed call for call through the RTC adapter.
//!
//! The fixture is upstream's: one interface named `TestRTC`, built with `enable_rtc = false`,
//! so auto mode is on (here: its module's policy is optional). After every step the six answers
//! (registered, activated, force-activated, force-deactivated, RTC-enabled, terminated) are
//! asserted. Where this library answers differently, the assertion states this library's
//! value, and both the comment and the assertion's message name the deviation
//! (`spec/cooperation.md` §9) that explains it.

use crate::common::*;
use cooperation::*;
use cooperation_adapters::rtc::{self, Binding, Kind, ModuleType, Rtc};

/// The six answers upstream's test checks after each step.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Answers {
    registered: bool,
    activated: bool,
    force_activated: bool,
    force_deactivated: bool,
    /// `None`: no live scene of this interface, so no answer (`[COOP-DEV-UNKNOWN-QUERY.1]`).
    rtc_enabled: Option<bool>,
    /// `None`: this interface never registered the identifier.
    terminated: Option<bool>,
}

const fn answers(
    registered: bool,
    activated: bool,
    force_activated: bool,
    force_deactivated: bool,
    rtc_enabled: Option<bool>,
    terminated: Option<bool>,
) -> Answers {
    Answers {
        registered,
        activated,
        force_activated,
        force_deactivated,
        rtc_enabled,
        terminated,
    }
}

fn ask(rtc: &Rtc, state: &State, id: SceneId) -> Answers {
    let view = rtc.view(state, "TestRTC").expect("bound");
    Answers {
        registered: view.is_registered(id),
        activated: view.is_activated(id),
        force_activated: view.is_force_activated(id),
        force_deactivated: view.is_force_deactivated(id),
        rtc_enabled: view.is_rtc_enabled(id),
        terminated: view.is_terminated(id),
    }
}

/// Upstream's fixture: `RTCInterface(node, "TestRTC", enable_rtc = false)`. Upstream accepts
/// any name and reports module `NONE` for one it does not know; here a name needs a binding
/// (`[COOP-DEV-INTERFACE-NAME.1]`), so `TestRTC` is bound, to module type `NONE` as upstream
/// reports it, and to the lane-change module, turning left.
fn fixture() -> (Rtc, State) {
    let binding = Binding::new(
        "TestRTC",
        ModuleType::None,
        Module::new(Behavior::LaneChange),
        Kind::Steering(Direction::Left),
    );
    let rtc = Rtc::new([binding]).expect("one binding");
    let enable_rtc = false;
    let state = State::new(Config::new(rtc.policies(enable_rtc))).expect("valid");
    (rtc, state)
}

/// `updateCooperateStatus(uuid, safe, state, 10.0, 100.0, stamp, requested)`.
fn report(
    rtc: &mut Rtc,
    state: &mut State,
    id: SceneId,
    safe: bool,
    rtc_state: u8,
    requested: bool,
) -> Result<Vec<Rule>, rtc::RtcError> {
    let mut interface = rtc.interface(state, "TestRTC").expect("bound");
    let transitions = interface.update_as_upstream(id, safe, rtc_state, 10.0, 100.0, requested)?;
    Ok(transitions.into_iter().map(|t| t.rule).collect())
}

/// The private `updateCooperateCommandStatus(commands)` upstream's test calls; here the
/// interface's `CooperateCommands` service, whose responses must all succeed.
fn command(rtc: &mut Rtc, state: &mut State, id: SceneId, command: u8) {
    let mut interface = rtc.interface(state, "TestRTC").expect("bound");
    let reply = interface.cooperate_commands(&rtc_commands(&[(id, command)]));
    assert_eq!(
        reply.result.as_ref().map(|t| t.rule),
        Ok(Rule::CommandApply),
        "{reply:?}"
    );
    assert!(reply.response.responses.iter().all(|r| r.success));
}

fn clear(rtc: &mut Rtc, state: &mut State) -> Vec<SceneId> {
    let mut interface = rtc.interface(state, "TestRTC").expect("bound");
    interface.clear_cooperate_status().expect("clears")
}

#[test]
fn upstream_unit_test_sequence() {
    use rtc::Lifecycle as S;
    let (mut rtc, mut state) = fixture();
    // Upstream uses one UUID throughout and registers it again after each removal or clear.
    // Here an identifier never comes back once retired ([COOP-DEV-ID-REUSE.1]), so each
    // re-registration uses a fresh one: id(1) .. id(5).
    let first = id(1);

    // Step 1. No registered UUID. Upstream: F F F F T T; its RTC-enabled and terminated answers
    // are the interface's auto-mode flag. Here: no answer ([COOP-DEV-UNKNOWN-QUERY.1]).
    assert_eq!(
        ask(&rtc, &state, first),
        answers(false, false, false, false, None, None),
        "step 1: RTC-enabled and terminated are None, not upstream's true, true \
         [COOP-DEV-UNKNOWN-QUERY.1]"
    );

    // Step 2. Register waiting, safe. Upstream: T T F F F F. Same here: auto mode (optional
    // policy) follows `safe`.
    assert_eq!(
        report(
            &mut rtc,
            &mut state,
            first,
            true,
            S::WAITING_FOR_EXECUTION,
            false
        ),
        Ok(vec![Rule::RegisterNew])
    );
    assert_eq!(
        ask(&rtc, &state, first),
        answers(true, true, false, false, Some(false), Some(false)),
        "step 2: as upstream"
    );

    // Step 3. Remove. Upstream checks only registered = F. Same here; the identifier retires
    // as removed, so it is not terminated (it neither succeeded nor failed). Upstream's
    // unchecked RTC-enabled and terminated answers would be its auto-mode flag for the now
    // unknown UUID; here RTC-enabled has no answer ([COOP-DEV-UNKNOWN-QUERY.1]).
    let removed = rtc
        .interface(&mut state, "TestRTC")
        .expect("bound")
        .remove_cooperate_status(first)
        .expect("removes");
    assert_eq!(removed.rule, Rule::OwnerRemove);
    assert_eq!(
        ask(&rtc, &state, first),
        answers(false, false, false, false, None, Some(false)),
        "step 3: registered is false, as upstream; RTC-enabled None and terminated false \
         [COOP-DEV-UNKNOWN-QUERY.1]"
    );

    // Step 4. Register with FAILED. Upstream registers the same UUID again, stored as waiting:
    // T T F F F F. Here the removed identifier is refused ([COOP-DEV-ID-REUSE.1]) ...
    let before = state.clone();
    let refused = report(&mut rtc, &mut state, first, true, S::FAILED, false)
        .expect_err("a retired identifier is never registered again");
    assert_eq!(
        refused.rejection().map(Rejection::rule),
        Some(Rule::RegisterRetired),
        "step 4 [COOP-DEV-ID-REUSE.1]"
    );
    assert_eq!(state, before, "a refusal changes nothing");
    // ... and a fresh identifier reported FAILED registers and fails in one step, as the
    // lifecycle allows waiting to become failed: it retires at once
    // ([COOP-DEV-REGISTER-PHASE.1], [COOP-DEV-TERMINAL.1]).
    let second = id(2);
    assert_eq!(
        report(&mut rtc, &mut state, second, true, S::FAILED, false),
        Ok(vec![Rule::RegisterNew, Rule::OwnerFinish])
    );
    assert_eq!(
        ask(&rtc, &state, second),
        answers(false, false, false, false, None, Some(true)),
        "step 4: not upstream's T T F F F F: a scene first reported failed registers and \
         retires as failed [COOP-DEV-REGISTER-PHASE.1] [COOP-DEV-TERMINAL.1]"
    );

    // Step 5. Update to RUNNING, unsafe, then an ACTIVATE command. Upstream continues with
    // its waiting scene; here the identifier of step 4 has retired, so a fresh one is
    // reported running: it registers and runs in one step ([COOP-DEV-REGISTER-PHASE.1]).
    // Upstream: T T T F T F; same here: the operator activated what the module judges unsafe.
    let third = id(3);
    assert_eq!(
        report(&mut rtc, &mut state, third, false, S::RUNNING, false),
        Ok(vec![Rule::RegisterNew, Rule::OwnerUpdate])
    );
    command(&mut rtc, &mut state, third, rtc::Command::ACTIVATE);
    assert_eq!(
        ask(&rtc, &state, third),
        answers(true, true, true, false, Some(true), Some(false)),
        "step 5: as upstream"
    );

    // Step 6. Update to SUCCEEDED. Upstream: T F F F T T, the scene stays listed. Here it
    // retires at once ([COOP-DEV-TERMINAL.1]), so it is not registered and has no RTC-enabled
    // answer ([COOP-DEV-UNKNOWN-QUERY.1]); it is terminated, as upstream.
    assert_eq!(
        report(&mut rtc, &mut state, third, false, S::SUCCEEDED, false),
        Ok(vec![Rule::OwnerFinish])
    );
    assert_eq!(
        ask(&rtc, &state, third),
        answers(false, false, false, false, None, Some(true)),
        "step 6: registered false and RTC-enabled None, not upstream's true, true \
         [COOP-DEV-TERMINAL.1] [COOP-DEV-UNKNOWN-QUERY.1]"
    );

    // Step 7. Clear. Upstream: registered = F and its stored commands are empty. Here there is
    // nothing live to clear, and no command is ever stored ([COOP-DEV-STORED-COMMANDS.1]): a
    // command for the finished scene is refused, and so is one for a scene not yet registered.
    assert_eq!(clear(&mut rtc, &mut state), Vec::<SceneId>::new());
    assert!(!ask(&rtc, &state, third).registered, "step 7: as upstream");
    for stray in [third, id(4)] {
        let reply = rtc
            .interface(&mut state, "TestRTC")
            .expect("bound")
            .cooperate_commands(&rtc_commands(&[(stray, rtc::Command::ACTIVATE)]));
        assert!(
            !reply.response.responses[0].success,
            "step 7: nothing stored [COOP-DEV-STORED-COMMANDS.1]"
        );
    }

    // Step 8. Register waiting (safe), update to RUNNING, DEACTIVATE command. Upstream reuses
    // its UUID; here a fresh one ([COOP-DEV-ID-REUSE.1]). Upstream: T F F T T F; same here:
    // the operator stopped a running manoeuvre the module judges safe.
    let fourth = id(4);
    assert_eq!(
        report(
            &mut rtc,
            &mut state,
            fourth,
            true,
            S::WAITING_FOR_EXECUTION,
            false
        ),
        Ok(vec![Rule::RegisterNew])
    );
    assert_eq!(
        report(&mut rtc, &mut state, fourth, true, S::RUNNING, false),
        Ok(vec![Rule::OwnerUpdate])
    );
    command(&mut rtc, &mut state, fourth, rtc::Command::DEACTIVATE);
    assert_eq!(
        ask(&rtc, &state, fourth),
        answers(true, false, false, true, Some(true), Some(false)),
        "step 8: as upstream"
    );

    // Step 9. Update to ABORTING. Upstream: T F F F T F; same here.
    assert_eq!(
        report(&mut rtc, &mut state, fourth, true, S::ABORTING, false),
        Ok(vec![Rule::OwnerUpdate])
    );
    assert_eq!(
        ask(&rtc, &state, fourth),
        answers(true, false, false, false, Some(true), Some(false)),
        "step 9: as upstream"
    );

    // Step 10. Update to FAILED. Upstream: T F F F T T. Here the scene retires
    // ([COOP-DEV-TERMINAL.1]): not registered, no RTC-enabled answer
    // ([COOP-DEV-UNKNOWN-QUERY.1]), terminated as upstream.
    assert_eq!(
        report(&mut rtc, &mut state, fourth, true, S::FAILED, false),
        Ok(vec![Rule::OwnerFinish])
    );
    assert_eq!(
        ask(&rtc, &state, fourth),
        answers(false, false, false, false, None, Some(true)),
        "step 10: registered false and RTC-enabled None, not upstream's true, true \
         [COOP-DEV-TERMINAL.1] [COOP-DEV-UNKNOWN-QUERY.1]"
    );

    // Step 11. Clear; register waiting with `requested`, update to RUNNING with `requested`.
    // Upstream reuses its UUID; here a fresh one ([COOP-DEV-ID-REUSE.1]). Upstream:
    // T F F F F F; same here: a requested scene waits for the operator although auto mode is
    // on and the module judges it safe ([COOP-REQUESTED.1]).
    assert_eq!(clear(&mut rtc, &mut state), Vec::<SceneId>::new());
    let fifth = id(5);
    assert_eq!(
        report(
            &mut rtc,
            &mut state,
            fifth,
            true,
            S::WAITING_FOR_EXECUTION,
            true
        ),
        Ok(vec![Rule::RegisterNew])
    );
    assert_eq!(
        report(&mut rtc, &mut state, fifth, true, S::RUNNING, true),
        Ok(vec![Rule::OwnerUpdate])
    );
    assert_eq!(
        ask(&rtc, &state, fifth),
        answers(true, false, false, false, Some(false), Some(false)),
        "step 11: as upstream"
    );

    // Step 12. ACTIVATE command. Upstream: T T T F T F; same here: activating a requested
    // scene counts as forced.
    command(&mut rtc, &mut state, fifth, rtc::Command::ACTIVATE);
    assert_eq!(
        ask(&rtc, &state, fifth),
        answers(true, true, true, false, Some(true), Some(false)),
        "step 12: as upstream"
    );

    state.check_invariants().expect("invariants hold");
}
