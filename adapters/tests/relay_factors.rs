//! `[COOP-RELAY-FACTORS.1]`: the stack's factors with the scenes' statuses
//! (`cooperation_adapters::relay::factors`), case by case and as properties of any input.

use cooperation::Distance;
use cooperation_adapters::relay::factors::{self, MATCH_M};
use cooperation_adapters::wire::{
    CooperationStatus, SteeringFactor, SteeringFactorArray, VelocityFactor, VelocityFactorArray,
};
use cooperation_adapters::Uuid;
use proptest::prelude::*;

fn status(n: u8) -> CooperationStatus {
    CooperationStatus {
        uuid: Uuid { uuid: [n; 16] },
        cancellable: true,
        ..CooperationStatus::default()
    }
}

/// A stack factor (no status) or, with `scene`, the factor the core builds for a scene.
fn velocity(behavior: &str, distance: f32, scene: Option<u8>) -> VelocityFactor {
    VelocityFactor {
        behavior: behavior.to_owned(),
        distance,
        detail: if scene.is_some() { "scene" } else { "stack" }.to_owned(),
        cooperation: scene.map(status).into_iter().collect(),
        ..VelocityFactor::default()
    }
}

fn steering(direction: u16, start: f32, scene: Option<u8>) -> SteeringFactor {
    SteeringFactor {
        behavior: "lane-change".to_owned(),
        direction,
        distance: [start, start + 50.0],
        detail: if scene.is_some() { "scene" } else { "stack" }.to_owned(),
        cooperation: scene.map(status).into_iter().collect(),
        ..SteeringFactor::default()
    }
}

fn velocity_array(factors: Vec<VelocityFactor>) -> VelocityFactorArray {
    VelocityFactorArray {
        factors,
        ..VelocityFactorArray::default()
    }
}

#[test]
fn coop_relay_factors_1() {
    // The stack's intersection stop 0.4 m from the scene's: one factor, the stack's, with the
    // scene's status; the crosswalk passes as it came; the nearest first.
    let stack = velocity_array(vec![
        velocity("intersection", 30.4, None),
        velocity("crosswalk", 12.0, None),
    ]);
    let scenes = velocity_array(vec![velocity("intersection", 30.0, Some(1))]);
    let merged = factors::velocity(Some(&stack), &scenes);
    assert_eq!(
        merged.factors,
        vec![velocity("crosswalk", 12.0, None), {
            let mut matched = velocity("intersection", 30.4, None);
            matched.cooperation = vec![status(1)];
            matched
        }]
    );
}

#[test]
fn coop_relay_factors_1_a_scene_matching_no_factor_is_the_core_s() {
    // Another behaviour, too far, or no stack at all: the scene's own factor.
    let scenes = velocity_array(vec![velocity("intersection", 30.0, Some(1))]);
    for stack in [
        Some(velocity_array(vec![velocity("crosswalk", 30.0, None)])),
        Some(velocity_array(vec![velocity(
            "intersection",
            30.0 + MATCH_M + 0.01,
            None,
        )])),
        None,
    ] {
        let merged = factors::velocity(stack.as_ref(), &scenes);
        let own: Vec<_> = merged
            .factors
            .iter()
            .filter(|f| !f.cooperation.is_empty())
            .collect();
        assert_eq!(own, vec![&velocity("intersection", 30.0, Some(1))]);
        assert_eq!(
            merged.factors.len(),
            stack.map_or(0, |s| s.factors.len()) + 1
        );
    }
}

#[test]
fn coop_relay_factors_1_nearest_pairs_first_and_one_scene_per_factor() {
    // Two scenes 10.0 and 10.6 m ahead, one stack factor at 10.5: the nearer scene (10.6)
    // takes it, the other is published as its own.
    let stack = velocity_array(vec![velocity("intersection", 10.5, None)]);
    let scenes = velocity_array(vec![
        velocity("intersection", 10.0, Some(1)),
        velocity("intersection", 10.6, Some(2)),
    ]);
    let merged = factors::velocity(Some(&stack), &scenes);
    assert_eq!(merged.factors.len(), 2);
    assert_eq!(merged.factors[0], velocity("intersection", 10.0, Some(1)));
    assert_eq!(merged.factors[1].detail, "stack");
    assert_eq!(merged.factors[1].cooperation, vec![status(2)]);
}

#[test]
fn coop_relay_factors_1_steering_matches_within_one_direction() {
    let stack = SteeringFactorArray {
        factors: vec![
            steering(SteeringFactor::RIGHT, 40.0, None),
            steering(SteeringFactor::LEFT, 40.2, None),
        ],
        ..SteeringFactorArray::default()
    };
    let scenes = SteeringFactorArray {
        factors: vec![steering(SteeringFactor::LEFT, 40.0, Some(3))],
        ..SteeringFactorArray::default()
    };
    let merged = factors::steering(Some(&stack), &scenes);
    assert_eq!(merged.factors.len(), 2);
    let left = &merged.factors[1];
    assert_eq!(
        (left.direction, left.detail.as_str()),
        (SteeringFactor::LEFT, "stack")
    );
    assert_eq!(left.cooperation, vec![status(3)]);
    assert!(merged.factors[0].cooperation.is_empty());
}

#[test]
fn coop_relay_factors_1_a_stack_factor_with_a_status_is_left_as_it_is() {
    let mut cooperating = velocity("intersection", 30.0, None);
    cooperating.cooperation = vec![status(9)];
    let stack = velocity_array(vec![cooperating.clone()]);
    let scenes = velocity_array(vec![velocity("intersection", 30.0, Some(1))]);
    let merged = factors::velocity(Some(&stack), &scenes);
    assert_eq!(
        merged.factors,
        vec![cooperating, velocity("intersection", 30.0, Some(1))]
    );
}

fn any_velocity(scene: Option<u8>) -> impl Strategy<Value = VelocityFactor> {
    (
        prop::sample::select(vec!["intersection", "crosswalk", "traffic-signal"]),
        prop_oneof![
            (0u8..40).prop_map(|d| f32::from(d) * 0.5),
            Just(f32::NAN),
            Just(f32::INFINITY),
            Just(-0.0f32),
        ],
        any::<bool>(),
    )
        .prop_map(move |(behavior, distance, cooperating)| {
            let mut factor = velocity(behavior, distance, scene);
            if scene.is_none() && cooperating {
                factor.cooperation = vec![status(200)];
            }
            factor
        })
}

fn same_bits(a: &VelocityFactor, b: &VelocityFactor) -> bool {
    a.behavior == b.behavior && a.distance.to_bits() == b.distance.to_bits() && a.detail == b.detail
}

proptest! {
    /// Whatever the stack sends: each of its factors comes out once, changed at most in its
    /// status (given only if it had none, from a scene of its behaviour within 1 m); each
    /// scene's status comes out once; the order is the core's order of distances.
    #[test]
    fn coop_relay_factors_1_nothing_lost_nothing_doubled(
        stack in prop::collection::vec(any_velocity(None), 0..6),
        scenes in prop::collection::vec(any_velocity(Some(0)), 0..5),
    ) {
        let scenes: Vec<VelocityFactor> = scenes
            .into_iter()
            .enumerate()
            .map(|(i, mut f)| { f.cooperation = vec![status(u8::try_from(i).unwrap())]; f })
            .collect();
        let merged = factors::velocity(
            Some(&velocity_array(stack.clone())),
            &velocity_array(scenes.clone()),
        ).factors;
        let from_stack: Vec<&VelocityFactor> =
            merged.iter().filter(|f| f.detail == "stack").collect();
        prop_assert_eq!(from_stack.len(), stack.len());
        for factor in &stack {
            let out = from_stack.iter().filter(|f| same_bits(f, factor)).count();
            let inn = stack.iter().filter(|f| same_bits(f, factor)).count();
            prop_assert_eq!(out, inn);
        }
        for factor in &from_stack {
            if let Some(given) = factor.cooperation.first().filter(|s| s.uuid.uuid[0] != 200) {
                let scene = &scenes[usize::from(given.uuid.uuid[0])];
                prop_assert_eq!(&scene.behavior, &factor.behavior);
                prop_assert!((scene.distance - factor.distance).abs() <= MATCH_M);
            }
        }
        for (i, _) in scenes.iter().enumerate() {
            let shown = merged
                .iter()
                .filter(|f| f.cooperation.first() == Some(&status(u8::try_from(i).unwrap())))
                .count();
            prop_assert_eq!(shown, 1);
        }
        prop_assert!(merged
            .windows(2)
            .all(|w| Distance(w[0].distance).total_cmp(&Distance(w[1].distance)).is_le()));
    }
}
