//! The service engine (`cooperation_adapters::engine`, spec §6.7): requests answered at their own
//! time, what the streams show published, and the answers the core's. The engine model checks
//! the same rules over every interleaving (`models/tests/engine_model.rs`).

use cooperation::{Command, Input, OperatorDecision, Policy, PolicySetting, SceneId};
use cooperation_adapters::engine::{Endpoint, Engine, Now, Options, Reply, Request};
use cooperation_adapters::rtc::{self, CooperateStatus};
use cooperation_adapters::sync::{SyncRequest, SyncStatus};
use cooperation_adapters::wire::{self, Service};
use cooperation_adapters::Time;

const TTL_MS: u64 = 100;

fn engine() -> Engine {
    let mut config = cooperation_adapters::settings::load(None)
        .expect("the built-in settings")
        .config;
    config.limits.ttl_ms = TTL_MS;
    let mut engine = Engine::new(config, Options::default()).expect("a configuration");
    engine.handle_timeout(at(0));
    engine
}

/// The reading `ms` milliseconds after the engine's first.
fn at(ms: u64) -> Now {
    Now::new(
        i64::try_from(ms).expect("small") * 1_000_000,
        Time::new(1_000, 0),
    )
}

fn id(n: u128) -> SceneId {
    SceneId::from_u128(n)
}

/// A module's sync reporting scene `n` on the intersection's interface.
fn report(n: u128, safe: bool) -> Request {
    let status = CooperateStatus {
        uuid: id(n).into(),
        safe,
        state: rtc::Lifecycle::new(rtc::Lifecycle::WAITING_FOR_EXECUTION),
        start_distance: 10.0,
        finish_distance: 30.0,
        ..CooperateStatus::default()
    };
    Request::Sync(SyncRequest {
        interface: "intersection".to_owned(),
        statuses: vec![SyncStatus::from(&status)],
        sequences: Vec::new(),
        removed: Vec::new(),
    })
}

fn command(n: u128, decision: OperatorDecision) -> Request {
    let commands = [Command {
        id: id(n),
        decision,
    }];
    Request::Ad(wire::Request::SetCommands(
        commands.iter().copied().collect(),
    ))
}

/// `[COOP-ENGINE-TIME.1]`: a command made after its scene's time to live passed is refused
/// even though no tick came between; a scene lives its time to live from its report's time,
/// not from the time the core was last told.
#[test]
fn coop_engine_time_1() {
    let mut engine = engine();
    assert!(engine.handle(report(1, false), at(10)).reply.success());
    assert!(engine
        .handle(command(1, OperatorDecision::Activate), at(10 + TTL_MS))
        .reply
        .success());
    let late = engine.handle(command(1, OperatorDecision::Deactivate), at(11 + TTL_MS));
    assert!(!late.reply.success(), "{late:?}");
    assert_eq!(engine.state().scene(id(1)), None, "retired by expiry");

    // Reported long after the core was last told: it lives its whole time to live from then.
    assert!(engine.handle(report(2, true), at(1_000)).reply.success());
    engine.handle_timeout(at(1_000 + TTL_MS));
    assert!(engine.state().scene(id(2)).is_some());
    engine.handle_timeout(at(1_001 + TTL_MS));
    assert!(engine.state().scene(id(2)).is_none());
}

/// `[COOP-ENGINE-STEP.1]`: a step of the clock longer than the step limit counts the limit, so
/// a jump does not retire the scenes a planner reports one module after another in the cycle
/// after it; a clock that went back counts nothing and time counts on from there; the host is
/// asked to call again before a step outgrows the limit.
#[test]
fn coop_engine_step_1() {
    const LIMIT_MS: u64 = 20;
    let engine_limited = |max_step_ms| {
        let mut config = cooperation_adapters::settings::load(None)
            .expect("the built-in settings")
            .config;
        config.limits.ttl_ms = TTL_MS;
        let options = Options {
            max_step_ms,
            ..Options::default()
        };
        let mut engine = Engine::new(config, options).expect("a configuration");
        engine.handle_timeout(at(0));
        engine
    };
    for (max_step_ms, survives) in [(LIMIT_MS, true), (u64::MAX, false)] {
        let mut engine = engine_limited(max_step_ms);
        assert!(engine.handle(report(1, true), at(0)).reply.success());
        assert!(engine.handle(report(2, true), at(0)).reply.success());
        // The clock jumps 10 s; the modules report their scenes one after the other. Counted
        // whole, the jump retires both before either is reported again: for good.
        assert_eq!(
            engine.handle(report(1, true), at(10_000)).reply.success(),
            survives
        );
        assert_eq!(engine.state().scene(id(2)).is_some(), survives);
        assert_eq!(
            engine.handle(report(2, true), at(10_000)).reply.success(),
            survives,
            "step limit {max_step_ms}"
        );
    }

    let mut engine = engine_limited(LIMIT_MS);
    assert!(engine.handle(report(1, true), at(0)).reply.success());
    assert!(engine.poll_publication(at(0)).is_some());
    assert_eq!(engine.until_publication_ms(at(5)), 95);
    assert_eq!(engine.until_timeout_ms(at(5)), LIMIT_MS - 5);
    // A jump, then a clock that went back: 20 ms counted, then none.
    engine.handle_timeout(at(10_000));
    engine.handle_timeout(at(5_000));
    assert!(engine.state().scene(id(1)).is_some());
    // Time counts on from the earlier reading, steps within the limit whole: 20 + 80 = 100 ms,
    // the time to live, then beyond it.
    for ms in (5_020..=5_080).step_by(20) {
        engine.handle_timeout(at(ms));
    }
    assert!(engine.state().scene(id(1)).is_some());
    engine.handle_timeout(at(5_081));
    assert!(engine.state().scene(id(1)).is_none());
}

/// `[COOP-ENGINE-PUBLISH.1]`: a change the streams show makes a publication due at once; a
/// report that only renews its scene's time to live does not; the interval makes one due
/// regardless.
#[test]
fn coop_engine_publish_1() {
    let mut engine = engine();
    let first = engine
        .poll_publication(at(0))
        .expect("the first is due at once");
    assert!(first.velocity.factors.is_empty());
    assert!(engine.poll_publication(at(1)).is_none());

    let handled = engine.handle(report(1, true), at(2));
    assert!(handled.change.revision.is_some() && handled.change.publish);
    let shown = engine.poll_publication(at(2)).expect("due at once");
    assert_eq!(shown.velocity.factors.len(), 1);
    assert_eq!(shown.revision, handled.change.revision.expect("changed"));

    // The same report again: the core changed (the time to live renewed), the streams did not.
    let again = engine.handle(report(1, true), at(3));
    assert!(again.change.revision.is_some() && !again.change.publish);
    assert!(engine.poll_publication(at(3)).is_none());

    // A policy change alters what the scenes topic shows.
    let settings = [PolicySetting {
        module: cooperation::Module::new(cooperation::Behavior::Intersection),
        policy: Policy::Required,
    }];
    let request = Request::Ad(wire::Request::SetPolicies(
        settings.iter().copied().collect(),
    ));
    assert!(engine.handle(request, at(4)).change.publish);
    assert!(engine.poll_publication(at(4)).is_some());

    // The interval.
    let every = engine.options().publish_every_ms;
    assert_eq!(engine.until_publication_ms(at(4)), every);
    assert!(engine.poll_publication(at(3 + every)).is_none());
    assert!(engine.poll_publication(at(4 + every)).is_some());

    // A clock that went back (a bag played again): a publication is due at once, with the
    // earlier stamp, and the interval counts on from that reading, not from the later one.
    let later = 10 * every;
    assert!(engine.poll_publication(at(later)).is_some());
    assert_eq!(engine.until_publication_ms(at(later - 1)), 0);
    assert!(engine.poll_publication(at(later - 5 * every)).is_some());
    assert!(engine.poll_publication(at(later - 5 * every + 1)).is_none());
    assert!(engine.poll_publication(at(later - 4 * every)).is_some());
}

/// `[COOP-ENGINE-ANSWER.1]`: an operator's call is answered as the core's transition answers
/// it on the state at the request's time, and a request that does not read is refused with the
/// reader's explanation, the core unchanged.
#[test]
fn coop_engine_answer_1() {
    let mut engine = engine();
    assert!(engine.handle(report(1, false), at(0)).reply.success());

    let mut oracle = engine.state().clone();
    oracle
        .apply(&Input::Tick { elapsed_ms: 50 })
        .expect("time passes");
    let unknown = [Command {
        id: id(9),
        decision: OperatorDecision::Activate,
    }];
    let expected = oracle
        .apply(&Input::SetCommands {
            commands: unknown.to_vec(),
        })
        .expect_err("an unknown scene");
    let handled = engine.handle(command(9, OperatorDecision::Activate), at(50));
    let Reply::Ad(response) = &handled.reply else {
        panic!("an AD API reply: {handled:?}")
    };
    assert_eq!(response.status().message, expected.to_string());
    assert_eq!(engine.state(), &oracle);

    let before = engine.state().clone();
    let malformed = Endpoint::Ad(Service::SetCommands).read_json(br#"{"commands": 7}"#);
    assert!(matches!(malformed, Request::Malformed(..)));
    let handled = engine.handle(malformed, at(50));
    let Reply::Ad(response) = &handled.reply else {
        panic!("an AD API reply: {handled:?}")
    };
    assert_eq!(
        response.status().code,
        wire::ResponseStatus::PARAMETER_ERROR
    );
    assert!(
        response.status().message.contains("commands"),
        "{response:?}"
    );
    assert_eq!(engine.state(), &before);
    assert_eq!(handled.change.revision, None);
}

/// `[COOP-DEV-QUOTA.1]` in a node: the interfaces' quotas together fit the core's table, so
/// with every interface at its quota a module still registers through any interface that is
/// under its own. A quota that could fill the table is refused before anything is served,
/// naming the largest that fits.
#[test]
fn every_interface_at_its_quota_fits_the_table() {
    let config = cooperation_adapters::settings::load(None)
        .expect("the built-in settings")
        .config;
    let max_scenes = config.limits.max_scenes;
    let interfaces = rtc::Binding::standard().len();
    // The default: the table shared evenly by the standard interfaces.
    assert_eq!(Options::default().scene_quota, max_scenes / interfaces);
    assert_eq!(rtc::SCENE_QUOTA, 215);

    let over = Options {
        scene_quota: rtc::SCENE_QUOTA + 1,
        ..Options::default()
    };
    let error = Engine::new(config.clone(), over).expect_err("216 × 19 > 4096");
    assert_eq!(
        error,
        cooperation_adapters::engine::EngineError::QuotaOverTable {
            quota: 216,
            interfaces,
            max_scenes
        }
    );
    assert!(
        error
            .to_string()
            .contains("comes to 4104 live scenes, more than the core's 4096")
            && error.to_string().contains("give a quota of at most 215"),
        "{error}"
    );
    let none = Options {
        scene_quota: 0,
        ..Options::default()
    };
    assert!(
        Engine::new(config.clone(), none).is_ok(),
        "no quota is a choice"
    );

    let mut engine = Engine::new(config, Options::default()).expect("the default fits");
    engine.handle_timeout(at(0));
    let mut n = 0_u128;
    for binding in rtc::Binding::standard() {
        let sequence = binding
            .sequences
            .iter()
            .next()
            .copied()
            .expect("one at least");
        // Each interface to its quota, then one more, which is refused for the quota, not for
        // a full table.
        for scene in 0..=rtc::SCENE_QUOTA {
            n += 1;
            let report = rtc::StatusReport::new(id(n), true, cooperation::Phase::Waiting, 1.0, 2.0)
                .in_sequence(sequence);
            let (result, _) = engine.call(|host| {
                host.interface(&binding.name)?
                    .update_cooperate_status(&report)
                    .map(drop)
            });
            if scene < rtc::SCENE_QUOTA {
                assert!(result.is_ok(), "{}: {result:?}", binding.name);
            } else {
                assert!(
                    matches!(result, Err(rtc::RtcError::SceneQuota { .. })),
                    "{}: {result:?}",
                    binding.name
                );
            }
        }
    }
    assert_eq!(
        engine.state().scene_count(),
        rtc::SCENE_QUOTA * interfaces,
        "every interface holds its quota, and the table has room left"
    );
}

/// Every host takes a publication rate the same way: above 0 and at most 1000 a second, the
/// interval its inverse; any other rate is refused with the engine's reason.
#[test]
fn a_publication_rate_is_taken_once_for_every_host() {
    use cooperation_adapters::engine::{publish_every, EngineError, MAX_PUBLICATION_RATE_HZ};
    use std::time::Duration;
    assert_eq!(publish_every(10.0), Ok(Duration::from_millis(100)));
    assert_eq!(
        publish_every(MAX_PUBLICATION_RATE_HZ),
        Ok(Duration::from_millis(1))
    );
    assert_eq!(publish_every(0.5), Ok(Duration::from_secs(2)));
    for refused in [0.0, -0.0, -1.0, 1000.5, f64::NAN, f64::INFINITY, 1e-20] {
        let error = publish_every(refused).expect_err("refused");
        assert_eq!(error, EngineError::PublicationRate(refused.to_string()));
        assert!(
            error
                .to_string()
                .ends_with("give a rate above 0 and at most 1000"),
            "{error}"
        );
    }
}

/// `[COOP-ENGINE-WAKE.1]`: the engine asks its host to tell the time when the oldest scene's
/// time to live runs out, so that every host shows an expiry at once, whatever its publication
/// interval; otherwise at the next periodic publication or the step limit, whichever is first.
#[test]
fn coop_engine_wake_1() {
    let mut engine = engine();
    engine.set_publish_every(std::time::Duration::from_secs(3_600));
    assert_eq!(engine.until_expiry_ms(at(0)), u64::MAX, "no live scene");
    assert!(engine.handle(report(1, true), at(10)).reply.success());
    assert!(engine.handle(report(2, true), at(40)).reply.success());
    // Scene 1, reported at 10, is over the time to live at 10 + TTL_MS + 1.
    assert_eq!(engine.until_expiry_ms(at(40)), TTL_MS + 11 - 40);
    assert_eq!(
        engine.until_expiry_ms(at(70)),
        TTL_MS + 11 - 70,
        "the host told nothing"
    );
    let _ = engine.poll_publication(at(70));
    assert_eq!(engine.until_timeout_ms(at(70)), TTL_MS + 11 - 70);
    let before = TTL_MS + 10;
    assert!(engine
        .advance(at(before))
        .1
        .is_some_and(|t| t.retired.is_empty()));
    assert_eq!(engine.until_expiry_ms(at(before)), 1);
    let (change, transition) = engine.advance(at(before + 1));
    assert_eq!(transition.expect("time passed").retired, vec![id(1)]);
    assert!(change.publish, "an expiry is published at once");
    assert_eq!(engine.until_expiry_ms(at(before + 1)), 30, "scene 2's");
    assert_eq!(engine.until_expiry_ms(at(before + 40)), 0, "overdue");

    // No live scene: the periodic publication, or the step limit when that comes first.
    let mut engine = self::engine();
    engine.set_publish_every(std::time::Duration::from_millis(300));
    let _ = engine.poll_publication(at(0));
    assert_eq!(engine.until_timeout_ms(at(100)), 200);
    engine.set_publish_every(std::time::Duration::from_secs(3_600));
    assert_eq!(
        engine.until_timeout_ms(at(100)),
        cooperation_adapters::engine::MAX_STEP_MS - 100
    );
}

/// Every host gives the engine its publication interval one way, in whole milliseconds and at
/// least 1, whether when building it or later.
#[test]
fn a_publication_interval_is_given_one_way() {
    use std::time::Duration;
    for (every, ms) in [
        (Duration::from_millis(250), 250),
        (Duration::from_micros(1_500), 1),
        (Duration::ZERO, 1),
        (Duration::MAX, u64::MAX),
    ] {
        let options = Options::default().publishing_every(every);
        assert_eq!(options.publish_every_ms, ms, "{every:?}");
        let mut engine = engine();
        engine.set_publish_every(every);
        assert_eq!(engine.options().publish_every_ms, ms, "{every:?}");
    }
}

/// Every host builds its engine from a settings file the same way: the built-in settings for
/// none, and a file that cannot be read refused, named, before any engine exists.
#[test]
fn every_host_builds_its_engine_from_settings_one_way() {
    use cooperation_adapters::engine::EngineError;
    let built = Engine::from_settings(None, Options::default()).expect("the built-in settings");
    let expected = Engine::new(
        cooperation_adapters::settings::load(None)
            .expect("the built-in settings")
            .config,
        Options::default(),
    )
    .expect("a configuration");
    assert_eq!(built, expected);
    let missing = std::path::Path::new("/nonexistent/cooperation.param.yaml");
    let Err(EngineError::Settings(message)) =
        Engine::from_settings(Some(missing), Options::default())
    else {
        panic!("a missing settings file is refused as such");
    };
    assert!(
        message.starts_with("/nonexistent/cooperation.param.yaml: "),
        "{message}"
    );
}

/// `[COOP-ENGINE-TIME.1]` for a planner in the same process (`Engine::call_at`): the core is told
/// the call's time before the call, in the same step, so a report made after its scene's time to
/// live passed finds the scene retired, and the call says which scenes aged out first.
#[test]
fn coop_engine_time_1_a_call_in_process_is_made_at_its_own_time() {
    let mut engine = engine();
    let update = |host: &mut cooperation_adapters::Host, n: u128| {
        let report = rtc::StatusReport::new(id(n), true, cooperation::Phase::Waiting, 1.0, 2.0);
        host.interface("intersection")?
            .update_cooperate_status(&report)
            .map(drop)
    };
    let (first, change, ticked) = engine.call_at(at(10), |host| update(host, 1));
    assert!(first.is_ok(), "{first:?}");
    assert!(change.publish, "a new scene is shown");
    assert!(ticked.is_some_and(|t| t.retired.is_empty()), "time passed");
    let revision = engine.revision();

    // Past the first scene's time to live: it ages out before the second report is made.
    let (second, change, ticked) = engine.call_at(at(11 + TTL_MS), |host| update(host, 2));
    assert!(second.is_ok(), "{second:?}");
    assert_eq!(ticked.map(|t| t.retired), Some(vec![id(1)]));
    assert_eq!(
        change.revision,
        Some(revision + 1),
        "one step, one revision"
    );
    let late = engine.call_at(at(11 + TTL_MS), |host| update(host, 1)).0;
    assert!(late.is_err(), "a retired scene is never registered again");

    // No time passing and a refused call: no change.
    let (refused, change, ticked) =
        engine.call_at(at(11 + TTL_MS), |host| host.interface("no such").map(drop));
    assert!(refused.is_err());
    assert!(ticked.is_none());
    assert_eq!(change.revision, None);
}

/// What a sync asked that was refused and is worth a line in the host's log comes back with
/// the reply, for the host to log: the whole sync over `max_batch`, a scene over its interface's
/// quota; an accepted sync and a scene refused for another reason (a report of an unknown
/// state) have none.
#[test]
fn a_sync_answers_what_its_host_should_log() {
    let mut engine = Engine::new(
        cooperation_adapters::settings::load(None)
            .expect("the built-in settings")
            .config,
        Options {
            scene_quota: 1,
            ..Options::default()
        },
    )
    .expect("a configuration");
    let accepted = engine.handle(report(1, true), at(0));
    assert!(
        accepted.reply.success() && accepted.refused.is_empty(),
        "{accepted:?}"
    );

    let over_quota = engine.handle(report(2, true), at(1));
    assert!(!over_quota.reply.success(), "{over_quota:?}");
    assert_eq!(over_quota.refused.len(), 1, "{over_quota:?}");
    assert!(
        over_quota.refused[0].starts_with("a scene refused: "),
        "{over_quota:?}"
    );

    let Request::Sync(mut sync) = report(1, true) else {
        unreachable!("a sync")
    };
    let max_batch = engine.state().limits().max_batch;
    sync.removed = vec![id(9).into(); max_batch];
    let too_long = engine.handle(Request::Sync(sync.clone()), at(2));
    assert!(!too_long.reply.success(), "{too_long:?}");
    assert_eq!(too_long.refused.len(), 1, "{too_long:?}");
    assert!(
        too_long.refused[0].starts_with("a sync refused: ")
            && too_long.refused[0].contains("max_batch"),
        "{too_long:?}"
    );

    sync.removed.clear();
    sync.statuses[0].state.r#type = 99;
    let unknown_state = engine.handle(Request::Sync(sync), at(3));
    assert!(!unknown_state.reply.success(), "{unknown_state:?}");
    assert!(unknown_state.refused.is_empty(), "{unknown_state:?}");
}

proptest::proptest! {
    /// A host may skip telling the engine a reading in the millisecond it was last told
    /// (`Shared::told_in`, read without the lock) only because doing so would change nothing:
    /// over readings that repeat, creep by less than a millisecond, step and go back, with
    /// reports and commands between them, `told_in` says yes exactly when the engine's last
    /// reading is in that millisecond, and then `advance` leaves the engine as it was.
    #[test]
    fn a_reading_in_the_millisecond_last_told_changes_nothing(
        calls in proptest::collection::vec((0_u8..4, -3_i64..40), 1..60),
    ) {
        let mut config = cooperation_adapters::settings::load(None)
            .expect("the built-in settings")
            .config;
        config.limits.ttl_ms = 5;
        let engine = Engine::new(config, Options::default()).expect("a configuration");
        let shared = cooperation_adapters::Shared::new(engine);
        for (kind, step) in calls {
            // Steps of a quarter millisecond, from a reading that is no whole millisecond.
            let now = Now::new(7_100_000 + step * 250_000, Time::new(1_000, 0));
            let told = shared.told_in(now);
            let (before, last_ms) = shared.read(|engine| (engine.clone(), engine.read_ms()));
            proptest::prop_assert_eq!(told, last_ms == Some(now.reading_ns.div_euclid(1_000_000)));
            let n = u128::try_from(step.rem_euclid(3)).expect("small") + 1;
            match kind {
                0 => {
                    let after = shared.update(|engine| {
                        let answer = engine.advance(now);
                        (answer, engine.clone())
                    });
                    if told {
                        proptest::prop_assert_eq!(after.0.0, Default::default());
                        proptest::prop_assert!(after.0.1.is_none());
                        proptest::prop_assert_eq!(&after.1, &before);
                    }
                }
                1 => drop(shared.update(|engine| engine.handle(report(n, step % 2 == 0), now))),
                2 => drop(shared.update(|engine| engine.handle(command(n, OperatorDecision::Activate), now))),
                _ => drop(shared.update(|engine| engine.handle_timeout(now))),
            }
        }
    }
}
