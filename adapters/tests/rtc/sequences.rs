//! Interfaces bound to several sequences: an avoidance's shift out (`avoidance/change`) and its
//! return (`avoidance/return`) through one interface, each under its own policy.

use super::*;
use cooperation_adapters::wire;

const AVOID: &str = "static_obstacle_avoidance_left";
const CHANGE: Module = Module::with_sequence(Behavior::Avoidance, Sequence::Change);
const RETURN: Module = Module::with_sequence(Behavior::Avoidance, Sequence::Return);

impl Fixture {
    /// A status report from interface `name` stating `sequence` (distances 10 and 60, not
    /// requested): the rules the core fired.
    fn report_in(
        &mut self,
        name: &str,
        id: SceneId,
        sequence: Sequence,
        safe: bool,
        rtc_state: u8,
    ) -> Result<Vec<Rule>, rtc::RtcError> {
        let mut interface = self.rtc.interface(&mut self.state, name).expect("bound");
        let transitions =
            interface.update_as_upstream_in(id, sequence, safe, rtc_state, 10.0, 60.0, false)?;
        Ok(transitions.into_iter().map(|t| t.rule).collect())
    }

    /// A report that must be refused, and change neither the adapter nor the core.
    fn refused(
        &mut self,
        name: &str,
        id: SceneId,
        sequence: Option<Sequence>,
        rtc_state: u8,
    ) -> rtc::RtcError {
        let before = (self.rtc.clone(), self.state.clone());
        let result = match sequence {
            Some(sequence) => self.report_in(name, id, sequence, true, rtc_state),
            None => self.report(name, id, true, rtc_state),
        };
        let error = result.expect_err("refused");
        assert_eq!((&self.rtc, &self.state), (&before.0, &before.1), "{error}");
        error
    }

    /// The module of live scene `id`.
    fn module_of(&self, id: SceneId) -> Option<Module> {
        self.state.scene(id).map(Scene::module)
    }
}

/// `[COOP-DEV-SEQUENCE.1]`: one avoidance interface, a shift out and a return under different
/// policies. Upstream has one auto-mode flag for both; here each follows its own module's
/// policy, the AD API sees each in its sequence, and the interface's auto mode is on only while
/// both are optional.
#[test]
fn coop_dev_sequence_1() {
    let mut fx = Fixture::new(false);
    // An operator requires approval for returns only, through the AD API.
    let request = [PolicySetting {
        module: RETURN,
        policy: Policy::Required,
    }]
    .into_iter()
    .collect();
    let answer = wire::set_policies(&mut fx.state, &request);
    assert!(answer.response.status.success);
    fx.report_in(
        AVOID,
        id(1),
        Sequence::Change,
        true,
        rtc::Lifecycle::RUNNING,
    )
    .expect("registers the shift out");
    fx.report_in(
        AVOID,
        id(2),
        Sequence::Return,
        true,
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    )
    .expect("registers the return");
    let view = fx.rtc.view(&fx.state, AVOID).expect("bound");
    assert!(view.is_activated(id(1)), "optional: follows safe");
    assert!(
        !view.is_activated(id(2)),
        "required: waits for the operator"
    );
    assert_eq!(view.is_rtc_enabled(id(1)), Some(false));
    assert_eq!(view.is_rtc_enabled(id(2)), Some(true));
    assert!(
        !view.auto_mode_status().is_auto_mode,
        "upstream: one flag, here on only while both sequences are optional"
    );
    let mut factors = Vec::new();
    fx.state.steering_factors_into(&mut factors);
    let modules: Vec<(Behavior, Sequence)> =
        factors.iter().map(|f| (f.behavior, f.sequence)).collect();
    assert_eq!(
        modules,
        [
            (Behavior::Avoidance, Sequence::Change),
            (Behavior::Avoidance, Sequence::Return)
        ]
    );
    // A return reported as a shift out is not moved: the core's rule for another module.
    let error = fx.refused(
        AVOID,
        id(2),
        Some(Sequence::Change),
        rtc::Lifecycle::RUNNING,
    );
    assert_eq!(
        error.rejection().map(Rejection::rule),
        Some(Rule::OwnerModule)
    );
}

/// Both kinds of scene register through one interface, are published on its one topic with its
/// module type, and belong to their own modules.
#[test]
fn change_and_return_scenes_register_through_one_interface() {
    let mut fx = Fixture::new(false);
    assert_eq!(
        fx.report_in(
            AVOID,
            id(1),
            Sequence::Change,
            true,
            rtc::Lifecycle::WAITING_FOR_EXECUTION
        ),
        Ok(vec![Rule::RegisterNew])
    );
    assert_eq!(
        fx.report_in(
            AVOID,
            id(2),
            Sequence::Return,
            false,
            rtc::Lifecycle::RUNNING
        ),
        Ok(vec![Rule::RegisterNew, Rule::OwnerUpdate])
    );
    assert_eq!(fx.module_of(id(1)), Some(CHANGE));
    assert_eq!(fx.module_of(id(2)), Some(RETURN));
    let view = fx.rtc.view(&fx.state, AVOID).expect("bound");
    assert!(view.is_registered(id(1)) && view.is_registered(id(2)));
    let array = view.cooperate_status_array(Time::new(1, 0));
    let listed: Vec<(SceneId, u8)> = array
        .statuses
        .iter()
        .map(|s| (s.uuid.into(), s.module.r#type))
        .collect();
    assert_eq!(
        listed,
        [
            (id(1), rtc::Module::AVOIDANCE_LEFT),
            (id(2), rtc::Module::AVOIDANCE_LEFT)
        ]
    );
    // Later reports may leave the sequence out: the scene keeps its own.
    assert_eq!(
        fx.report(AVOID, id(2), true, rtc::Lifecycle::RUNNING),
        Ok(vec![Rule::OwnerUpdate])
    );
    assert_eq!(fx.module_of(id(2)), Some(RETURN));
    // Or state it again.
    assert_eq!(
        fx.report_in(
            AVOID,
            id(1),
            Sequence::Change,
            true,
            rtc::Lifecycle::RUNNING
        ),
        Ok(vec![Rule::OwnerUpdate])
    );
    // A scene registered through the right-hand interface is its own, whatever its module.
    let right = "static_obstacle_avoidance_right";
    fx.report_in(
        right,
        id(3),
        Sequence::Return,
        true,
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let error = fx.refused(
        AVOID,
        id(3),
        Some(Sequence::Return),
        rtc::Lifecycle::RUNNING,
    );
    assert!(
        matches!(error, rtc::RtcError::ForeignScene { .. }),
        "{error:?}"
    );
}

/// Each module's policy applies to its scenes only: the statuses' `auto_mode`, the queries and
/// the merged decision follow the scene's module, set through the AD API or the core.
#[test]
fn each_sequence_follows_its_own_policy() {
    let (mut rtc, _) = rtc_setup(false);
    let config = Config::new([(CHANGE, Policy::Required), (RETURN, Policy::Optional)]);
    let mut state = State::new(config).expect("valid");
    let mut interface = rtc.interface(&mut state, AVOID).expect("bound");
    for (n, sequence) in [(1, Sequence::Change), (2, Sequence::Return)] {
        interface
            .update_as_upstream_in(
                id(n),
                sequence,
                true,
                rtc::Lifecycle::WAITING_FOR_EXECUTION,
                5.0,
                25.0,
                false,
            )
            .expect("registers");
    }
    let view = interface.view();
    assert!(!view.is_activated(id(1)));
    assert!(view.is_activated(id(2)));
    let auto: Vec<bool> = view
        .cooperate_status_array(Time::default())
        .statuses
        .iter()
        .map(|s| s.auto_mode)
        .collect();
    assert_eq!(auto, [false, true]);
    // The AD API's set_policies for the shift out reaches it, and not the return.
    let request: wire::SetCooperationPoliciesRequest = serde_json::from_str(
        r#"{"policies": [{"behavior": "avoidance", "sequence": "change", "policy": 1}]}"#,
    )
    .expect("reads");
    assert!(
        wire::set_policies(&mut state, &request)
            .response
            .status
            .success
    );
    let view = rtc.view(&state, AVOID).expect("bound");
    assert!(view.is_activated(id(1)) && view.is_activated(id(2)));
    assert!(view.auto_mode_status().is_auto_mode, "both optional now");
}

/// A sequence the interface is not bound to is refused, for a new scene and a live one, and
/// changes nothing; an interface bound to one sequence takes it stated or not.
#[test]
fn a_sequence_the_interface_is_not_bound_to_is_refused() {
    let mut fx = Fixture::new(false);
    let error = fx.refused(LEFT, id(1), Some(Sequence::Return), rtc::Lifecycle::RUNNING);
    assert_eq!(
        error,
        rtc::RtcError::UnboundSequence {
            name: LEFT.into(),
            module: Module::with_sequence(Behavior::LaneChange, Sequence::Return),
            bound: vec![Module::new(Behavior::LaneChange)],
        }
    );
    assert_eq!(
        error.to_string(),
        "RTC interface \"lane_change_left\" has no scenes of lane-change/return, only of lane-change"
    );
    fx.report_in(
        AVOID,
        id(2),
        Sequence::Change,
        true,
        rtc::Lifecycle::RUNNING,
    )
    .expect("registers");
    let error = fx.refused(AVOID, id(2), Some(Sequence::Empty), rtc::Lifecycle::RUNNING);
    assert_eq!(
        error.to_string(),
        "RTC interface \"static_obstacle_avoidance_left\" has no scenes of avoidance, only of \
         avoidance/change or avoidance/return"
    );
    // The lane change's one sequence, stated or not.
    assert_eq!(
        fx.report_in(LEFT, id(3), Sequence::Empty, true, rtc::Lifecycle::RUNNING),
        Ok(vec![Rule::RegisterNew, Rule::OwnerUpdate])
    );
    assert_eq!(
        fx.report(LEFT, id(3), true, rtc::Lifecycle::RUNNING),
        Ok(vec![Rule::OwnerUpdate])
    );
    assert_eq!(fx.module_of(id(3)), Some(Module::new(Behavior::LaneChange)));
}

/// A new scene reported without a sequence through an interface bound to two is refused, with
/// nothing registered; the state is checked first, as for any report.
#[test]
fn a_new_scene_must_state_its_sequence_where_two_are_bound() {
    let mut fx = Fixture::new(false);
    let error = fx.refused(AVOID, id(1), None, rtc::Lifecycle::WAITING_FOR_EXECUTION);
    assert_eq!(
        error,
        rtc::RtcError::SequenceUnstated {
            id: id(1),
            name: AVOID.into(),
            bound: vec![CHANGE, RETURN],
        }
    );
    assert_eq!(
        error.to_string(),
        format!(
            "scene {} is not registered, and RTC interface \"static_obstacle_avoidance_left\" \
             has scenes of avoidance/change or avoidance/return: state its sequence",
            id(1)
        )
    );
    let error = fx.refused(AVOID, id(1), None, 7);
    assert!(matches!(error, rtc::RtcError::Field(_)), "{error:?}");
    assert!(!fx
        .rtc
        .view(&fx.state, AVOID)
        .expect("bound")
        .is_registered(id(1)));
}

/// Reporting a scene in another sequence than it registered with is the core's rule for a live
/// identifier named with another module (`WrongModule`), the same rejection the core gives a
/// `Register` of it; nothing changes. A removed scene's identifier is retired in any sequence.
#[test]
fn a_scene_keeps_its_sequence() {
    let mut fx = Fixture::new(false);
    fx.report_in(
        AVOID,
        id(1),
        Sequence::Change,
        true,
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let error = fx.refused(
        AVOID,
        id(1),
        Some(Sequence::Return),
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    );
    let wrong = Rejection::WrongModule {
        id: id(1),
        owner: CHANGE,
        named: RETURN,
    };
    assert_eq!(error, rtc::RtcError::Core(wrong.clone()));
    // The core's own answer to registering it again in the return.
    let mut core = fx.state.clone();
    assert_eq!(
        core.apply(&register(id(1), RETURN, Decision::Activate)),
        Err(wrong)
    );
    assert_eq!(core, fx.state);
    // Removed, the identifier never comes back, in its sequence or another.
    fx.rtc
        .interface(&mut fx.state, AVOID)
        .expect("bound")
        .remove_cooperate_status(id(1))
        .expect("removes");
    for sequence in [Sequence::Change, Sequence::Return] {
        let error = fx.refused(AVOID, id(1), Some(sequence), rtc::Lifecycle::RUNNING);
        assert_eq!(
            error.rejection().map(Rejection::rule),
            Some(Rule::RegisterRetired)
        );
    }
    assert_eq!(
        fx.state.retirement(id(1)).map(|r| r.module),
        Some(CHANGE),
        "retired as the shift out"
    );
}

/// Removal and clear name each scene's own module.
#[test]
fn remove_and_clear_reach_both_sequences() {
    let mut fx = Fixture::new(false);
    for (n, sequence) in [
        (1, Sequence::Return),
        (2, Sequence::Change),
        (3, Sequence::Return),
    ] {
        fx.report_in(AVOID, id(n), sequence, true, rtc::Lifecycle::RUNNING)
            .expect("registers");
    }
    let mut interface = fx.rtc.interface(&mut fx.state, AVOID).expect("bound");
    assert_eq!(
        interface.remove_cooperate_status(id(1)).map(|t| t.rule),
        Ok(Rule::OwnerRemove)
    );
    assert_eq!(interface.clear_cooperate_status(), Ok(vec![id(2), id(3)]));
    let retired: Vec<Option<Module>> = (1..=3)
        .map(|n| fx.state.retirement(id(n)).map(|r| r.module))
        .collect();
    assert_eq!(retired, [Some(RETURN), Some(CHANGE), Some(RETURN)]);
}

/// `enable_rtc` configures both modules; the interface's switch and the external one set both;
/// the interface's status is on only while both are optional, and the other avoidance interface
/// shares them.
#[test]
fn auto_mode_covers_both_sequences() {
    for enable_rtc in [false, true] {
        let policies = Rtc::standard().policies(enable_rtc);
        let expected = rtc::policy_for_auto_mode(!enable_rtc);
        assert_eq!(policies.get(&CHANGE), Some(&expected));
        assert_eq!(policies.get(&RETURN), Some(&expected));
        assert_eq!(policies.get(&Module::new(Behavior::Avoidance)), None);
    }
    let mut fx = Fixture::new(false);
    fx.auto_mode(AVOID, false);
    assert_eq!(fx.state.policy(CHANGE), Some(Policy::Required));
    assert_eq!(fx.state.policy(RETURN), Some(Policy::Required));
    let right = "static_obstacle_avoidance_right";
    for name in [AVOID, right] {
        let view = fx.rtc.view(&fx.state, name).expect("bound");
        assert!(!view.auto_mode_status().is_auto_mode, "{name}");
    }
    // Only the shift out optional: neither interface is in auto mode.
    let request = [PolicySetting {
        module: CHANGE,
        policy: Policy::Optional,
    }]
    .into_iter()
    .collect();
    assert!(
        wire::set_policies(&mut fx.state, &request)
            .response
            .status
            .success
    );
    let modes = fx.rtc.auto_mode_status_array(&fx.state, Time::default());
    let avoidance: Vec<bool> = modes
        .statuses
        .iter()
        .filter(|s| {
            [rtc::Module::AVOIDANCE_LEFT, rtc::Module::AVOIDANCE_RIGHT].contains(&s.module.r#type)
        })
        .map(|s| s.is_auto_mode)
        .collect();
    assert_eq!(avoidance, [false, false]);
    // The external switch for AVOIDANCE_RIGHT sets both modules, so both interfaces.
    let reply = fx.rtc.auto_mode_with_module(
        &mut fx.state,
        &rtc::AutoModeWithModuleRequest {
            module: rtc::Module::new(rtc::Module::AVOIDANCE_RIGHT),
            enable: true,
        },
    );
    assert!(reply.response.success, "{reply:?}");
    assert_eq!(fx.state.policy(RETURN), Some(Policy::Optional));
    for name in [AVOID, right] {
        let view = fx.rtc.view(&fx.state, name).expect("bound");
        assert!(view.auto_mode_status().is_auto_mode, "{name}");
    }
    // A core configured with one of the two cannot serve the interface.
    let mut state = State::new(Config::new([(CHANGE, Policy::Optional)])).expect("valid");
    let error = fx
        .rtc
        .interface(&mut state, AVOID)
        .expect_err("unconfigured");
    assert_eq!(
        error,
        rtc::RtcError::Unconfigured {
            name: AVOID.into(),
            module: RETURN
        }
    );
}

/// On the RTC wire nothing changes: a return's status is a `tier4_rtc_msgs` status like any,
/// with the interface's module type. On the AD API wire each scene's factor carries its
/// sequence. A binding's serde form names its behaviour and sequences, and reads back.
#[test]
fn the_wire_forms() {
    let mut fx = Fixture::new(false);
    fx.report_in(
        AVOID,
        id(1),
        Sequence::Change,
        true,
        rtc::Lifecycle::RUNNING,
    )
    .expect("registers");
    fx.report_in(
        AVOID,
        id(2),
        Sequence::Return,
        true,
        rtc::Lifecycle::WAITING_FOR_EXECUTION,
    )
    .expect("registers");
    let array = fx
        .rtc
        .view(&fx.state, AVOID)
        .expect("bound")
        .cooperate_status_array(Time::new(1, 0));
    for status in &array.statuses {
        let json = serde_json::to_value(status).expect("serializes");
        // The message's fields, and no other (the map lists them in name order).
        let keys: Vec<&str> = json
            .as_object()
            .expect("object")
            .keys()
            .map(String::as_str)
            .collect();
        assert_eq!(
            keys,
            [
                "auto_mode",
                "command_status",
                "finish_distance",
                "module",
                "requested",
                "safe",
                "stamp",
                "start_distance",
                "state",
                "uuid"
            ]
        );
        assert_eq!(json["module"], serde_json::json!({"type": 3}));
    }
    let factors: serde_json::Value = serde_json::from_slice(&wire::to_json(
        &wire::steering_factors(&fx.state, Time::default()),
    ))
    .expect("JSON");
    let sequences: Vec<(&str, &str)> = factors["factors"]
        .as_array()
        .expect("list")
        .iter()
        .map(|f| {
            (
                f["behavior"].as_str().expect("string"),
                f["sequence"].as_str().expect("string"),
            )
        })
        .collect();
    assert_eq!(
        sequences,
        [("avoidance", "change"), ("avoidance", "return")]
    );

    let binding = fx
        .rtc
        .bindings()
        .iter()
        .find(|b| b.name == AVOID)
        .expect("bound");
    let json = serde_json::to_value(binding).expect("serializes");
    assert_eq!(
        json["sequences"],
        serde_json::to_value([Sequence::Change, Sequence::Return]).expect("serializes")
    );
    assert_eq!(
        json["behavior"],
        serde_json::to_value(Behavior::Avoidance).expect("serializes")
    );
    let back: rtc::Binding = serde_json::from_value(json.clone()).expect("reads");
    assert_eq!(&back, binding);
    // A binding without a sequence reads, but makes no adapter.
    let mut none = json;
    none["sequences"] = serde_json::json!([]);
    let none: rtc::Binding = serde_json::from_value(none).expect("reads");
    assert_eq!(
        Rtc::new([none]),
        Err(rtc::RtcError::NoSequence { name: AVOID.into() })
    );
}
