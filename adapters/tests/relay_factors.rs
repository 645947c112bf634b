//! `[COOP-RELAY-FACTORS.1]`: the stack's factors with the scenes' statuses
//! (`cooperation_adapters::relay::factors`), case by case and as properties of any input.

use cooperation::Distance;
use cooperation_adapters::engine::{Now, Publication};
use cooperation_adapters::relay::factors::{self, Stream, MATCH_M};
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

/// The clock reading `ms` milliseconds.
fn at(ms: i64) -> Now {
    Now::new(ms * 1_000_000, cooperation_adapters::Time::default())
}

/// The engine's publication of revision `revision`, with one scene's velocity factor.
fn scenes(revision: u64) -> Publication {
    Publication {
        revision,
        velocity: velocity_array(vec![velocity("intersection", 30.0, Some(1))]),
        ..Publication::default()
    }
}

/// The stream publishes when a side changed, and only then; nothing before the engine's first
/// publication; the engine's revision on each.
#[test]
fn coop_relay_factors_1_published_whenever_either_side_changes() {
    let mut stream = Stream::default();
    stream.take_velocity(
        velocity_array(vec![velocity("crosswalk", 12.0, None)]),
        at(0),
    );
    assert_eq!(
        stream.poll(at(0)),
        None,
        "nothing before the engine's first"
    );
    stream.take_scenes(scenes(3));
    let first = stream.poll(at(1)).expect("the engine published");
    assert_eq!(first.revision, 3);
    assert_eq!(first.velocity.factors.len(), 2, "{first:?}");
    assert_eq!(stream.poll(at(2)), None, "nothing changed");
    stream.take_velocity(
        velocity_array(vec![velocity("intersection", 30.2, None)]),
        at(5),
    );
    let matched = stream.poll(at(5)).expect("the stack's came");
    assert_eq!(matched.revision, 3);
    assert_eq!(matched.velocity.factors.len(), 1, "{matched:?}");
    assert_eq!(matched.velocity.factors[0].detail, "stack");
    assert_eq!(matched.velocity.factors[0].cooperation, vec![status(1)]);
    stream.take_scenes(scenes(4));
    assert_eq!(stream.poll(at(6)).expect("the engine's").revision, 4);
    assert_eq!(stream.poll(at(7)), None);
}

/// An array the last publication used is dropped once older than the time to live, in a
/// publication of its own; the stream says when that is due.
#[test]
fn coop_relay_factors_1_a_stale_stack_array_is_dropped_when_it_lapses() {
    let ttl = i64::try_from(factors::INPUT_TTL_MS).expect("small");
    let mut stream = Stream::default();
    assert_eq!(stream.until_stale_ms(at(0)), u64::MAX, "nothing used");
    stream.take_scenes(scenes(1));
    stream.take_velocity(
        velocity_array(vec![velocity("crosswalk", 12.0, None)]),
        at(0),
    );
    stream.take_steering(
        SteeringFactorArray {
            factors: vec![steering(1, 20.0, None)],
            ..SteeringFactorArray::default()
        },
        at(400),
    );
    let both = stream.poll(at(400)).expect("due");
    assert_eq!(both.velocity.factors.len(), 2);
    assert_eq!(both.steering.factors.len(), 1);
    assert_eq!(
        stream.until_stale_ms(at(400)),
        factors::INPUT_TTL_MS - 400 + 1
    );
    assert_eq!(
        stream.poll(at(ttl)),
        None,
        "still fresh at the time to live"
    );
    let lapsed = stream.poll(at(ttl + 1)).expect("the velocity array lapsed");
    assert_eq!(
        lapsed.velocity.factors.len(),
        1,
        "only the scene's: {lapsed:?}"
    );
    assert_eq!(
        lapsed.steering.factors.len(),
        1,
        "the steering array is fresh"
    );
    assert_eq!(stream.poll(at(ttl + 2)), None, "dropped once");
    assert_eq!(
        stream.until_stale_ms(at(ttl + 2)),
        factors::INPUT_TTL_MS - 602 + 1
    );
    let lapsed = stream
        .poll(at(ttl + 401))
        .expect("the steering array lapsed");
    assert!(lapsed.steering.factors.is_empty());
    assert_eq!(stream.until_stale_ms(at(ttl + 401)), u64::MAX);
    assert_eq!(stream.poll(at(5 * ttl)), None);
}

/// An array already stale when first polled is not used, and so never lapses; a clock that
/// went back takes nothing as stale.
#[test]
fn coop_relay_factors_1_a_stale_array_is_not_used_and_a_clock_going_back_ages_nothing() {
    let ttl = i64::try_from(factors::INPUT_TTL_MS).expect("small");
    let mut stream = Stream::default();
    stream.take_scenes(scenes(1));
    stream.take_velocity(
        velocity_array(vec![velocity("crosswalk", 12.0, None)]),
        at(0),
    );
    let published = stream.poll(at(ttl + 1)).expect("due");
    assert_eq!(published.velocity.factors.len(), 1, "the scene's only");
    assert_eq!(stream.until_stale_ms(at(ttl + 1)), u64::MAX);
    assert_eq!(stream.poll(at(ttl + 2)), None);
    stream.take_velocity(
        velocity_array(vec![velocity("crosswalk", 12.0, None)]),
        at(10_000),
    );
    let back = stream.poll(at(0)).expect("due");
    assert_eq!(back.velocity.factors.len(), 2, "fresh: {back:?}");
    assert_eq!(stream.until_stale_ms(at(0)), factors::INPUT_TTL_MS + 1);
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
