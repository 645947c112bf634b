//! Mixed factor streams: factors of modules that do not cooperate beside the scenes', and each
//! factor's `detail`, in both directions.

use super::*;

/// A factor of a module that does not cooperate, `at` metres ahead.
fn other(at: f32, detail: &str) -> VelocityFactor {
    VelocityFactor {
        pose: Pose::IDENTITY,
        distance: Distance(at),
        status: VelocityStatus::Approaching,
        behavior: Behavior::RunOut,
        sequence: Sequence::Empty,
        detail: Detail::new(detail),
        cooperation: None,
    }
}

/// A state with one velocity scene 30 m ahead whose owner says why it waits.
fn one_scene() -> (State, SceneId) {
    let mut state = State::new(Config::new([(LANE_CHANGE, Policy::Required)])).expect("valid");
    let id = SceneId::from_u128(1);
    let report = Report::new(Decision::Activate, Geometry::velocity(30.0))
        .with_detail(Detail::new("gap behind the truck"));
    state
        .apply(&Input::Register {
            id,
            module: LANE_CHANGE,
            report,
        })
        .expect("registers");
    (state, id)
}

#[test]
fn a_planner_publishes_its_other_factors_in_the_same_stream_by_distance() {
    let (state, id) = one_scene();
    let others = [
        other(45.0, "pedestrian may enter"),
        other(10.0, ""),
        other(30.0, "tie"),
    ];
    let stamp = Time::default();
    let stream = wire::velocity_factors_with(&state, stamp, &others).expect("none cooperates");
    let distances: Vec<f32> = stream.factors.iter().map(|f| f.distance).collect();
    assert_eq!(distances, [10.0, 30.0, 30.0, 45.0]);
    // At 30 m the scene comes first, then the other factor at the same distance.
    assert_eq!(stream.factors[1].cooperation.len(), 1);
    assert_eq!(stream.factors[1].detail, "gap behind the truck");
    assert!(stream.factors[2].cooperation.is_empty());
    assert_eq!(stream.factors[2].detail, "tie");
    assert_eq!(stream.factors[3].behavior, wire::PlanningBehavior::RUN_OUT);
    assert_eq!(stream.factors[3].detail, "pedestrian may enter");
    // As JSON: an empty `cooperation` list.
    let value = json(&wire::to_json(&stream));
    assert_eq!(value["factors"][0]["cooperation"], serde_json::json!([]));
    assert_eq!(value["factors"][1]["cooperation"][0]["cancellable"], true);

    // Read back, every factor is there: the scene's with its status and detail, the others
    // without a status.
    let read = stream.to_factors().expect("a mixed stream reads");
    assert_eq!(read.len(), 4);
    assert_eq!(read[1].scene(), Some(id));
    assert_eq!(read[1].detail.as_str(), "gap behind the truck");
    assert_eq!(read[3], others[0]);
    let mut expected = Vec::new();
    state
        .velocity_factors_with(&others, &mut expected)
        .expect("none cooperates");
    assert_eq!(read, expected);
}

#[test]
fn a_stream_read_from_json_may_mix_factors() {
    let text = br#"{"header": {"stamp": {"sec": 1, "nanosec": 2}, "frame_id": "map"},
        "factors": [
          {"pose": {"position": {"x": 0, "y": 0, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}},
           "distance": 12.5, "status": 1, "behavior": "crosswalk", "sequence": "",
           "detail": "someone is crossing", "cooperation": []},
          {"pose": {"position": {"x": 0, "y": 0, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}},
           "distance": 20.0, "status": 1, "behavior": "intersection", "sequence": "", "detail": "",
           "cooperation": [{"uuid": {"uuid": "AAECAwQFBgcICQoLDA0ODw=="}, "autonomous": {"decision": 2},
                            "cooperator": {"decision": 4}, "cancellable": true}]}
        ]}"#;
    let stream: wire::VelocityFactorArray = wire::from_json(text).expect("reads");
    let factors = stream.to_factors().expect("converts");
    assert_eq!(factors[0].cooperation, None);
    assert_eq!(factors[0].detail.as_str(), "someone is crossing");
    assert_eq!(factors[0].behavior, Behavior::Crosswalk);
    assert_eq!(
        factors[1].scene(),
        Some(SceneId::from_u128(
            0x0001_0203_0405_0607_0809_0a0b_0c0d_0e0f
        ))
    );
}

#[test]
fn a_factor_with_a_status_is_not_an_other_factor() {
    let (state, id) = one_scene();
    let mut scenes = Vec::new();
    state.velocity_factors_into(&mut scenes);
    let mut others = vec![other(5.0, ""), scenes[0].clone()];
    let mut out = vec![other(1.0, "kept")];
    let error = state
        .velocity_factors_with(&others, &mut out)
        .expect_err("a scene's factor is the core's to report");
    assert_eq!(error, CooperatingFactor { index: 1, id });
    assert_eq!(
        error.to_string(),
        format!(
            "factor 1 carries the cooperation status of scene {id}: only factors of modules \
             that do not cooperate may be added to the core's"
        )
    );
    assert_eq!(out, [other(1.0, "kept")], "left as it was");
    assert!(wire::velocity_factors_with(&state, Time::default(), &others).is_err());
    // Steering streams take other factors the same way.
    others.clear();
    let steering_other = SteeringFactor {
        poses: [Pose::IDENTITY; 2],
        distances: [Distance(3.0), Distance(9.0)],
        direction: Direction::Left,
        status: SteeringStatus::Approaching,
        behavior: Behavior::GoalPlanner,
        sequence: Sequence::Empty,
        detail: Detail::new("pull over"),
        cooperation: None,
    };
    let stream = wire::steering_factors_with(&state, Time::default(), &[steering_other])
        .expect("none cooperates");
    assert_eq!(stream.factors.len(), 1);
    assert!(stream.factors[0].cooperation.is_empty());
    assert_eq!(stream.factors[0].detail, "pull over");
}
