//! User-extension behaviours and sequences on the wire: configured, set and read like the
//! built-in ones; refused by the core when no configuration names them; refused as malformed
//! when the name breaks the documented length or character set.

use proptest::prelude::*;

use super::*;

/// `valet-parking/approach`: an extension behaviour with an extension sequence.
fn valet() -> Module {
    Module::with_sequence(
        "valet-parking".parse().expect("a valid name"),
        "approach".parse().expect("a valid name"),
    )
}

/// `approach-assist`: an extension behaviour whose name sorts before `lane-change` (and every
/// built-in name but `adaptive-cruise`).
fn assist() -> Module {
    Module::new("approach-assist".parse().expect("a valid name"))
}

/// Valet parking and approach assist optional, lane change required, with one valet scene
/// 20 m ahead.
fn with_valet_scene() -> (State, SceneId) {
    let mut state = State::new(Config::new([
        (valet(), Policy::Optional),
        (LANE_CHANGE, Policy::Required),
        (assist(), Policy::Optional),
    ]))
    .expect("valid");
    let id = SceneId::from_u128(7);
    register(
        &mut state,
        id,
        valet(),
        Decision::Deactivate,
        Geometry::velocity(20.0),
    );
    (state, id)
}

#[test]
fn an_extension_module_has_its_policy_set_and_read_through_the_services() {
    let (mut state, _) = with_valet_scene();
    let listed = json(&Service::GetPolicies.call_json(&mut state, b"{}"));
    assert_eq!(
        listed["policies"],
        serde_json::json!([
            {"behavior": "approach-assist", "sequence": "", "policy": wire::CooperationPolicy::OPTIONAL},
            {"behavior": "lane-change", "sequence": "", "policy": wire::CooperationPolicy::REQUIRED},
            {"behavior": "valet-parking", "sequence": "approach", "policy": wire::CooperationPolicy::OPTIONAL},
        ]),
        "[COOP-POL-GET.2]: by behaviour string, then sequence string, built-in or not"
    );
    let request = format!(
        r#"{{"policies": [{{"behavior": "valet-parking", "sequence": "approach", "policy": {}}}]}}"#,
        wire::CooperationPolicy::REQUIRED
    );
    let response = json(&Service::SetPolicies.call_json(&mut state, request.as_bytes()));
    assert_eq!(response["status"]["success"], true, "{response}");
    assert_eq!(state.policy(valet()), Some(Policy::Required));
}

#[test]
fn an_extension_scene_is_published_under_its_names_and_commanded_by_its_id() {
    let (mut state, id) = with_valet_scene();
    let stream = wire::velocity_factors(&state, Time::default());
    let value = json(&wire::to_json(&stream));
    assert_eq!(value["factors"][0]["behavior"], "valet-parking");
    assert_eq!(value["factors"][0]["sequence"], "approach");
    let read = stream.to_factors().expect("reads back");
    assert_eq!(read[0].behavior.as_str(), "valet-parking");
    assert_eq!(read[0].sequence, valet().sequence);

    let request = format!(
        r#"{{"commands": [{{"uuid": {{"uuid": {}}}, "cooperator": {{"decision": {}}}}}]}}"#,
        list(id),
        wire::CooperationDecision::ACTIVATE
    );
    let response = json(&Service::SetCommands.call_json(&mut state, request.as_bytes()));
    assert_eq!(response["status"]["success"], true, "{response}");
    assert_eq!(
        state.scene(id).expect("live").operator_decision(),
        OperatorDecision::Activate
    );
}

#[test]
fn an_extension_no_configuration_names_is_refused_by_the_cores_rule() {
    let (mut state, _) = with_valet_scene();
    // `valet-parking` with the empty sequence is another module than the configured one.
    let request = r#"{"policies": [{"behavior": "valet-parking", "sequence": "", "policy": 1}]}"#;
    core_rejects(
        &mut state,
        Service::SetPolicies,
        request,
        Rule::PolicyUnknown,
    );
    // A well-formed typo is an extension no configuration names: its scene is refused too.
    let typo = Module::new("valet-prking".parse().expect("a valid name"));
    let register = Input::Register {
        id: SceneId::from_u128(8),
        module: typo,
        report: Report::new(Decision::Activate, Geometry::velocity(1.0)),
    };
    let rejection = state.clone().apply(&register).expect_err("refused");
    assert_eq!(rejection.rule(), Rule::RegisterModule);
}

/// A valid extension name: a letter, then letters, digits and `-`, at most 24 bytes.
fn extension_name() -> impl Strategy<Value = String> {
    "[a-z][a-z0-9-]{0,23}"
}

proptest! {
    #[test]
    fn every_valid_extension_name_round_trips_and_is_published_as_given(
        behavior in extension_name(),
        sequence in extension_name(),
    ) {
        let module = Module::with_sequence(
            behavior.parse().expect("valid"),
            sequence.parse().expect("valid"),
        );
        prop_assert_eq!(module.behavior.as_str(), behavior.as_str());
        prop_assert_eq!(module.sequence.as_str(), sequence.as_str());
        let mut state = State::new(Config::new([(module, Policy::Optional)])).expect("valid");
        register(&mut state, SceneId::from_u128(1), module, Decision::Activate, Geometry::velocity(5.0));
        let stream = wire::velocity_factors(&state, Time::default());
        prop_assert_eq!(&stream.factors[0].behavior, &behavior);
        prop_assert_eq!(&stream.factors[0].sequence, &sequence);
        let read = stream.to_factors().expect("reads back");
        prop_assert_eq!((read[0].behavior, read[0].sequence), (module.behavior, module.sequence));
    }

    #[test]
    fn a_name_beyond_the_length_or_character_set_is_malformed(
        name in "[a-z][a-z0-9-]{24,40}|[A-Z_./ ][a-z]{0,8}|[a-z]{1,8}[A-Z_./ ]",
    ) {
        let request = format!(r#"{{"policies": [{{"behavior": {name:?}, "sequence": "", "policy": 1}}]}}"#);
        prop_assert!(
            matches!(policy_fault(&request), Malformed::InvalidBehavior { .. }),
            "{}", name
        );
    }
}
