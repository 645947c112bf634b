//! More checks of the RTC compatibility adapter (`tests/rtc.rs` holds the rest): parsing a
//! command with generators that make accepted commands common, and the external status array's
//! order at the values it is easy to get wrong.

use std::cell::Cell;

use super::Fixture;
use crate::common::*;
use cooperation::*;
use cooperation_adapters::rtc;
use proptest::prelude::*;
use proptest::test_runner::{Config as RunnerConfig, TestRunner};

/// A `command.type` byte: a defined constant half the time (upstream's `tier4_rtc_msgs/Command`:
/// DEACTIVATE 0, ACTIVATE 1), else the first undefined value or any byte.
fn command_type() -> impl Strategy<Value = u8> {
    prop_oneof![2 => 0..=1u8, 1 => Just(2u8), 1 => any::<u8>()]
}

/// A `module.type` byte: a defined constant half the time (upstream's `tier4_rtc_msgs/Module`:
/// NONE 0 to ROUNDABOUT 19), else the first undefined value or any byte.
fn module_type() -> impl Strategy<Value = u8> {
    prop_oneof![2 => 0..=19u8, 1 => Just(20u8), 1 => any::<u8>()]
}

fn any_command() -> impl Strategy<Value = rtc::CooperateCommand> {
    (any::<[u8; 16]>(), module_type(), command_type()).prop_map(|(uuid, module, command)| {
        rtc::CooperateCommand {
            uuid: rtc::Uuid { uuid },
            module: rtc::Module::new(module),
            command: rtc::Command::new(command),
        }
    })
}

/// Parsing a command never panics, accepts exactly the defined constants, and turns an
/// accepted one into the core command for its scene (ACTIVATE 1 is activate, DEACTIVATE 0
/// deactivate). Both outcomes must be common among the cases run: with both bytes drawn from
/// all of `u8`, about 86 % of runs of 256 cases never met an accepted command.
#[test]
fn command_parsing_accepts_exactly_the_constants() {
    const CASES: u32 = 512;
    let (accepted, refused) = (Cell::new(0u32), Cell::new(0u32));
    let mut runner = TestRunner::new(RunnerConfig {
        cases: CASES,
        failure_persistence: None,
        ..RunnerConfig::default()
    });
    let result = runner.run(&any_command(), |command| {
        let defined = command.command.r#type <= 1 && command.module.r#type <= 19;
        match command.parse() {
            Ok(parsed) => {
                prop_assert!(defined, "{:?} accepted", command);
                let decision = if command.command.r#type == 1 {
                    OperatorDecision::Activate
                } else {
                    OperatorDecision::Deactivate
                };
                prop_assert_eq!(parsed.id, SceneId::from(command.uuid));
                prop_assert_eq!(parsed.decision, decision);
                accepted.set(accepted.get() + 1);
            }
            Err(_) => {
                prop_assert!(!defined, "{:?} refused", command);
                refused.set(refused.get() + 1);
            }
        }
        Ok(())
    });
    result.unwrap_or_else(|failure| panic!("{failure}"));
    // About a quarter of the cases are accepted and three quarters refused; an eighth of the
    // cases is many standard deviations below either.
    let (accepted, refused) = (accepted.get(), refused.get());
    assert!(accepted >= CASES / 8, "only {accepted} accepted commands");
    assert!(refused >= CASES / 8, "only {refused} refused commands");
}

/// `[COOP-DEV-ORDER.1]` through the adapter: the external array lists the scenes in the order
/// `[COOP-OUT-ORDER.1]` states (checked with the oracle written from the spec's words), so
/// `-inf` comes first and a NaN of either sign last.
#[test]
fn the_external_array_puts_every_nan_last() {
    let mut fx = Fixture::new(false);
    let starts = [
        (1, f32::NAN),
        (2, -f32::NAN),
        (3, f32::NEG_INFINITY),
        (4, f32::INFINITY),
        (5, -0.0),
        (6, 0.0),
        (7, -3.0),
    ];
    for (n, start) in starts {
        rtc_register_at(&mut fx.rtc, &mut fx.state, "intersection", n, start);
    }
    let array = fx.rtc.cooperate_status_array(&fx.state, Time::new(3, 0));
    let order: Vec<SceneId> = array.statuses.iter().map(|s| s.uuid.into()).collect();
    assert_eq!(order, [3, 7, 5, 6, 4, 1, 2].map(id));
    assert!(array.statuses.windows(2).all(|w| listed_before(
        (Distance(w[0].start_distance), w[0].uuid.into()),
        (Distance(w[1].start_distance), w[1].uuid.into()),
    )));
}

/// An interface found once by name answers as the name does, is refused as the name is, and an
/// id found on an adapter with more bindings is refused by one with fewer.
#[test]
fn an_interface_found_once_answers_as_its_name() {
    let Fixture { mut rtc, mut state } = {
        let mut fixture = Fixture::new(false);
        fixture
            .report(
                super::LEFT,
                id(1),
                true,
                rtc::Lifecycle::WAITING_FOR_EXECUTION,
            )
            .expect("registers");
        fixture
    };
    assert_eq!(
        rtc.find("dynamic_obstacle_avoidance"),
        Err(rtc::RtcError::UnknownInterface {
            name: "dynamic_obstacle_avoidance".into()
        })
    );
    let left = rtc.find(super::LEFT).expect("bound");
    // A change through the id: auto mode off, so the scene waits for the operator.
    let reply = rtc
        .interface_at(&mut state, left)
        .expect("bound")
        .auto_mode(&rtc::AutoModeRequest { enable: false });
    assert!(reply.response.success, "{reply:?}");
    let by_name = rtc.view(&state, super::LEFT).expect("bound");
    let by_id = rtc.view_at(&state, left).expect("bound");
    assert!(by_id.is_registered(id(1)) && !by_id.is_activated(id(1)));
    assert!(!by_id.auto_mode_status().is_auto_mode);
    assert_eq!(
        by_id.cooperate_status_array(Time::new(3, 0)),
        by_name.cooperate_status_array(Time::new(3, 0))
    );
    // An id found on an adapter with one binding more: a place past this adapter's last.
    let mut more = rtc::Binding::standard();
    let last = more.len();
    more.push(rtc::Binding::new(
        "dynamic_obstacle_avoidance",
        rtc::ModuleType::None,
        Module::new(Behavior::Avoidance),
        rtc::Kind::Steering(Direction::Unknown),
    ));
    let extra = rtc::Rtc::new(more)
        .expect("distinct names")
        .find("dynamic_obstacle_avoidance")
        .expect("bound there");
    let before = state.clone();
    let error = rtc
        .interface_at(&mut state, extra)
        .map(|_| ())
        .expect_err("not an interface here");
    assert_eq!(
        error,
        rtc::RtcError::UnknownInterface {
            name: format!("#{last}")
        }
    );
    assert_eq!(state, before, "nothing changed");
}
