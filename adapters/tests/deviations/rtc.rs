//! Deviations met through the RTC compatibility adapter (`cooperation_adapters::rtc`).

use crate::common::*;
use cooperation::*;
use cooperation_adapters::rtc;

/// `[COOP-DEV-REGISTER-PHASE.1]`: a scene first reported running registers and runs; first
/// reported failed, it registers and retires as failed; first reported aborting or succeeded,
/// nothing registers and the error names the state.
#[test]
fn coop_dev_register_phase_1() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut lane_change = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    let transitions = lane_change
        .update_as_upstream(id(1), false, rtc::Lifecycle::RUNNING, 5.0, 40.0, false)
        .expect("registers running");
    let rules: Vec<Rule> = transitions.iter().map(|t| t.rule).collect();
    assert_eq!(rules, [Rule::RegisterNew, Rule::OwnerUpdate]);
    assert_eq!(
        lane_change.view().scene(id(1)).map(Scene::phase),
        Some(Phase::Running),
        "upstream would store it waiting"
    );
    let transitions = lane_change
        .update_as_upstream(id(2), true, rtc::Lifecycle::FAILED, 5.0, 40.0, false)
        .expect("registers and fails");
    assert_eq!(transitions.last().map(|t| t.rule), Some(Rule::OwnerFinish));
    assert_eq!(lane_change.view().is_terminated(id(2)), Some(true));
    for (n, rtc_state, phase) in [
        (3, rtc::Lifecycle::ABORTING, Phase::Aborting),
        (4, rtc::Lifecycle::SUCCEEDED, Phase::Succeeded),
    ] {
        let before = state.clone();
        let mut lane_change = rtc
            .interface(&mut state, "lane_change_left")
            .expect("bound");
        let error = lane_change
            .update_as_upstream(id(n), true, rtc_state, 5.0, 40.0, false)
            .expect_err("cannot start there");
        assert!(
            matches!(&error, rtc::RtcError::InitialPhase { id: at, phase: asked, .. } if *at == id(n) && *asked == phase),
            "{error:?}"
        );
        assert_eq!(
            error.to_string(),
            format!(
                "scene {} is not registered and cannot start {phase}: scene {} cannot go from waiting to {phase}",
                id(n),
                id(n)
            )
        );
        assert!(!lane_change.view().is_registered(id(n)));
        assert_eq!(state, before, "nothing registered");
    }
}

/// `[COOP-DEV-DUPLICATE.1]`: two commands for one scene in one request are refused together;
/// upstream would apply both, the last winning.
#[test]
fn coop_dev_duplicate_1() {
    let (mut rtc, mut state) = rtc_setup(true);
    let mut lane_change = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    lane_change
        .update_as_upstream(
            id(1),
            true,
            rtc::Lifecycle::WAITING_FOR_EXECUTION,
            5.0,
            40.0,
            false,
        )
        .expect("registers");
    let reply = lane_change.cooperate_commands(&rtc_commands(&[
        (id(1), rtc::Command::DEACTIVATE),
        (id(1), rtc::Command::ACTIVATE),
    ]));
    assert_eq!(
        reply.response.responses.len(),
        2,
        "one response per command"
    );
    assert!(reply.response.responses.iter().all(|r| !r.success));
    let rejection = reply.result.expect_err("refused").rejection().cloned();
    assert!(
        matches!(
            rejection,
            Some(Rejection::Commands {
                index: 1,
                failure: CommandFailure::DuplicateId,
                ..
            })
        ),
        "{rejection:?}"
    );
    assert!(
        !lane_change.view().is_activated(id(1)),
        "upstream: the last, ACTIVATE, wins"
    );
    assert_eq!(
        lane_change
            .view()
            .scene(id(1))
            .map(Scene::operator_decision),
        Some(OperatorDecision::Undecided)
    );
}

/// `[COOP-DEV-AUTO-MODE-KEY.1]`: switching auto mode on `lane_change_left` switches
/// `lane_change_right` too (one module, `lane-change`), and nothing else.
#[test]
fn coop_dev_auto_mode_key_1() {
    let (mut rtc, mut state) = rtc_setup(false);
    for (n, name) in [
        (1, "lane_change_left"),
        (2, "lane_change_right"),
        (3, "intersection"),
    ] {
        let mut interface = rtc.interface(&mut state, name).expect("bound");
        interface
            .update_as_upstream(
                id(n),
                true,
                rtc::Lifecycle::WAITING_FOR_EXECUTION,
                5.0,
                40.0,
                false,
            )
            .expect("registers");
        assert!(
            interface.view().is_activated(id(n)),
            "auto mode: follows safe"
        );
    }
    let reply = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound")
        .auto_mode(&rtc::AutoModeRequest { enable: false });
    assert!(reply.response.success);
    assert_eq!(
        state.policy(Module::new(Behavior::LaneChange)),
        Some(Policy::Required)
    );
    let right = rtc.view(&state, "lane_change_right").expect("bound");
    assert!(
        !right.auto_mode_status().is_auto_mode,
        "upstream: right keeps auto mode"
    );
    assert!(!right.is_activated(id(2)));
    assert_eq!(right.is_rtc_enabled(id(2)), Some(true));
    let intersection = rtc.view(&state, "intersection").expect("bound");
    assert!(intersection.auto_mode_status().is_auto_mode);
    assert!(intersection.is_activated(id(3)));
}

/// `[COOP-DEV-CONSTANTS.1]`: undefined constants are refused with the field named, and change
/// nothing.
#[test]
fn coop_dev_constants_1() {
    let (mut rtc, mut state) = rtc_setup(false);
    let mut lane_change = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    lane_change
        .update_as_upstream(id(1), true, rtc::Lifecycle::RUNNING, 5.0, 40.0, false)
        .expect("registers running");
    let before = state.clone();
    let mut lane_change = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    // Upstream accepts 7 from RUNNING and stores it. Here a status with an undefined state is
    // refused where it is read, before any report reaches the interface.
    let mut status = lane_change
        .view()
        .cooperate_status_array(Time::default())
        .statuses[0];
    status.state = rtc::Lifecycle::new(7);
    let field = status.report().expect_err("undefined state");
    assert_eq!(
        (field.field.to_string().as_str(), field.value),
        ("state.type", 7)
    );
    // Upstream stores an undefined command type as the command status.
    let reply = lane_change.cooperate_commands(&rtc_commands(&[(id(1), 2)]));
    assert!(!reply.response.responses[0].success);
    assert_eq!(
        reply.result.expect_err("undefined command").to_string(),
        "commands[0].command.type is 2, which is not DEACTIVATE (0) or ACTIVATE (1)"
    );
    let mut request = rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]);
    request.commands[0].module = rtc::Module::new(200);
    let reply = lane_change.cooperate_commands(&request);
    assert_eq!(
        reply.result.expect_err("undefined module").to_string(),
        "commands[0].module.type is 200, which is not a Module constant (0 to 19)"
    );
    assert_eq!(state, before, "nothing changed");
}

/// `[COOP-DEV-INTERFACE-NAME.1]`: a name without a binding is refused; binding it makes it an
/// interface.
#[test]
fn coop_dev_interface_name_1() {
    let (mut rtc, mut state) = rtc_setup(false);
    let error = rtc
        .interface(&mut state, "dynamic_obstacle_avoidance")
        .expect_err("not bound");
    assert_eq!(
        error,
        rtc::RtcError::UnknownInterface {
            name: "dynamic_obstacle_avoidance".into()
        }
    );
    assert_eq!(
        error.to_string(),
        "no RTC interface is bound to the name \"dynamic_obstacle_avoidance\""
    );
    let mut bindings = rtc::Binding::standard();
    bindings.push(rtc::Binding::new(
        "dynamic_obstacle_avoidance",
        rtc::ModuleType::None,
        Module::new(Behavior::Avoidance),
        rtc::Kind::Steering(Direction::Unknown),
    ));
    let mut rtc = rtc::Rtc::new(bindings).expect("distinct names");
    // Its module (`avoidance`, not a sequence the standard avoidances have) needs a policy.
    let error = rtc
        .interface(&mut state, "dynamic_obstacle_avoidance")
        .expect_err("no policy for its module");
    assert!(
        matches!(error, rtc::RtcError::Unconfigured { .. }),
        "{error:?}"
    );
    let mut state = State::new(Config::new(rtc.policies(false))).expect("valid");
    let mut interface = rtc
        .interface(&mut state, "dynamic_obstacle_avoidance")
        .expect("bound now");
    interface
        .update_as_upstream(
            id(1),
            true,
            rtc::Lifecycle::WAITING_FOR_EXECUTION,
            5.0,
            9.0,
            false,
        )
        .expect("registers");
    assert!(interface.view().is_activated(id(1)));
}

/// `[COOP-DEV-ROUTING.1]`: through the external API every command is answered, the virtual
/// traffic light's scenes can be commanded, and `AutoModeWithModule` reaches every interface
/// of the module type, external-request lane change included.
#[test]
fn coop_dev_routing_1() {
    let (mut rtc, mut state) = rtc_setup(true);
    rtc.interface(&mut state, "virtual_traffic_light")
        .expect("bound")
        .update_as_upstream(
            id(1),
            false,
            rtc::Lifecycle::WAITING_FOR_EXECUTION,
            30.0,
            30.0,
            false,
        )
        .expect("registers");
    // Its status carries TRAFFIC_LIGHT, as upstream.
    let array = rtc.cooperate_status_array(&state, Time::new(1, 0));
    assert_eq!(array.statuses[0].module.r#type, rtc::Module::TRAFFIC_LIGHT);
    // A command of module type NONE (upstream: no response) and one for the virtual traffic
    // light under TRAFFIC_LIGHT (upstream: routed to the traffic light, "not found").
    let mut request = rtc_commands(&[(id(1), rtc::Command::ACTIVATE)]);
    let reply = rtc.cooperate_commands(&mut state, &request);
    assert_eq!(reply.response.responses.len(), 1);
    assert!(reply.response.responses[0].success);
    request.commands[0].module = rtc::Module::new(rtc::Module::TRAFFIC_LIGHT);
    request.commands[0].command = rtc::Command::new(rtc::Command::DEACTIVATE);
    let reply = rtc.cooperate_commands(&mut state, &request);
    assert!(reply.response.responses[0].success);
    assert_eq!(
        state.scene(id(1)).map(Scene::operator_decision),
        Some(OperatorDecision::Deactivate)
    );
    // TRAFFIC_LIGHT reaches both traffic light interfaces' modules.
    let reply = rtc.auto_mode_with_module(
        &mut state,
        &rtc::AutoModeWithModuleRequest {
            module: rtc::Module::new(rtc::Module::TRAFFIC_LIGHT),
            enable: true,
        },
    );
    assert!(reply.response.success);
    for behavior in [Behavior::TrafficSignal, Behavior::VirtualTrafficLight] {
        assert_eq!(state.policy(Module::new(behavior)), Some(Policy::Optional));
    }
    // Upstream has no auto-mode route for external-request lane change.
    let reply = rtc.auto_mode_with_module(
        &mut state,
        &rtc::AutoModeWithModuleRequest {
            module: rtc::Module::new(rtc::Module::EXT_REQUEST_LANE_CHANGE_LEFT),
            enable: true,
        },
    );
    assert!(reply.response.success);
    assert_eq!(
        state.policy(Module::new(Behavior::LaneChange)),
        Some(Policy::Optional)
    );
    // A type no interface carries is an error, not silence.
    let before = state.clone();
    let reply = rtc.auto_mode_with_module(
        &mut state,
        &rtc::AutoModeWithModuleRequest {
            module: rtc::Module::new(rtc::Module::OCCLUSION_SPOT),
            enable: true,
        },
    );
    assert!(!reply.response.success);
    assert_eq!(
        reply.result.expect_err("no interface").to_string(),
        "no RTC interface reports module type OCCLUSION_SPOT (14)"
    );
    assert_eq!(state, before);
}
