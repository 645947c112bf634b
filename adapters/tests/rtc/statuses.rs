//! The published statuses, and the bindings and routes behind them.

use super::*;

// ---------------------------------------------------------------------------------------------
// Statuses
// ---------------------------------------------------------------------------------------------

/// §6.29: each status is stamped with its owner's last report: the array's stamp less the
/// scene's age.
#[test]
fn statuses_are_stamped_with_the_last_report() {
    let mut fx = Fixture::new(false);
    fx.report(LEFT, id(1), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    fx.rtc.tick(&mut fx.state, 1_500).expect("ticks");
    fx.report(LEFT, id(2), true, rtc::Lifecycle::WAITING_FOR_EXECUTION)
        .expect("registers");
    fx.rtc.tick(&mut fx.state, 250).expect("ticks");
    let array = fx
        .rtc
        .view(&fx.state, LEFT)
        .expect("bound")
        .cooperate_status_array(Time::new(10, 100_000_000));
    let stamps: Vec<Time> = array.statuses.iter().map(|s| s.stamp).collect();
    assert_eq!(
        stamps,
        [Time::new(8, 350_000_000), Time::new(9, 850_000_000)]
    );
    assert_eq!(Time::new(0, 0).before_ms(1), Time::new(-1, 999_000_000));
    assert_eq!(
        Time::new(i32::MIN, 0).before_ms(u64::MAX),
        Time::new(i32::MIN, 0)
    );
}

/// §6.31: the external API's array holds every interface's scenes, nearest start first; a
/// velocity scene reports its one distance as start and finish.
#[test]
fn the_external_array_is_ordered_by_start_distance() {
    let mut fx = Fixture::new(false);
    for (n, name, start) in [
        (1, LEFT, 50.0),
        (2, "intersection", 20.0),
        (3, "static_obstacle_avoidance_right", -3.0),
        (4, "crosswalk", f32::NAN),
    ] {
        rtc_register_at(&mut fx.rtc, &mut fx.state, name, n, start);
    }
    let array = fx.rtc.cooperate_status_array(&fx.state, Time::new(3, 0));
    let order: Vec<SceneId> = array.statuses.iter().map(|s| s.uuid.into()).collect();
    assert_eq!(order, [id(3), id(2), id(1), id(4)], "NaN last");
    let intersection = array.statuses[1];
    assert_eq!(intersection.module.r#type, rtc::Module::INTERSECTION);
    assert_eq!(
        (intersection.start_distance, intersection.finish_distance),
        (20.0, 20.0)
    );
    let modes = fx.rtc.auto_mode_status_array(&fx.state, Time::new(3, 0));
    assert_eq!(modes.statuses.len(), fx.rtc.bindings().len());
    assert!(modes.statuses.iter().all(|s| s.is_auto_mode));
}

/// The same scenes are the AD API's factors: a steering interface's scene is a steering
/// factor of its core module, turning its way.
#[test]
fn rtc_scenes_are_ad_api_factors() {
    let mut fx = Fixture::new(false);
    fx.report(
        "lane_change_right",
        id(1),
        true,
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    fx.report(
        "traffic_light",
        id(2),
        false,
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let mut steering = Vec::new();
    fx.state.steering_factors_into(&mut steering);
    assert_eq!(steering.len(), 1);
    assert_eq!(steering[0].behavior, Behavior::LaneChange);
    assert_eq!(steering[0].direction, Direction::Right);
    assert_eq!(steering[0].distances, [Distance(10.0), Distance(60.0)]);
    let mut velocity = Vec::new();
    fx.state.velocity_factors_into(&mut velocity);
    assert_eq!(velocity.len(), 1);
    assert_eq!(velocity[0].behavior, Behavior::TrafficSignal);
    assert_eq!(
        velocity[0].cooperation.map(|status| status.module_decision),
        Some(Decision::Deactivate)
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
            .update_as_upstream(
                id(n),
                true,
                rtc::Lifecycle::WAITING_FOR_EXECUTION,
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
