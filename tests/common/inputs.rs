//! Input generators for the property tests: random inputs over a small universe of identifiers
//! and modules (the fixtures' configuration), and a crowd of identifiers for large tables.

use cooperation::*;
use proptest::prelude::*;

use super::{AVOIDANCE, INTERSECTION, LANE_CHANGE};

/// The identifiers the inputs name: 1 to `IDS`.
pub const IDS: u128 = 6;

pub fn any_id() -> impl Strategy<Value = SceneId> {
    (1..=IDS).prop_map(SceneId::from_u128)
}

pub fn any_module() -> impl Strategy<Value = Module> {
    prop_oneof![Just(LANE_CHANGE), Just(AVOIDANCE), Just(INTERSECTION)]
}

pub fn any_decision() -> impl Strategy<Value = Decision> {
    prop_oneof![Just(Decision::Deactivate), Just(Decision::Activate)]
}

pub fn any_operator() -> impl Strategy<Value = OperatorDecision> {
    proptest::sample::select(OperatorDecision::ALL.to_vec())
}

/// Any phase, running and aborting twice as often as the others: a scene reaches aborting
/// only through running, and commands for an aborting scene are a rule of their own.
pub fn any_phase() -> impl Strategy<Value = Phase> {
    prop_oneof![
        1 => Just(Phase::Waiting),
        2 => Just(Phase::Running),
        2 => Just(Phase::Aborting),
        1 => Just(Phase::Succeeded),
        1 => Just(Phase::Failed),
    ]
}

pub fn any_geometry() -> impl Strategy<Value = Geometry> {
    prop_oneof![
        (-10.0f32..100.0).prop_map(Geometry::velocity),
        (-10.0f32..100.0).prop_map(|start| Geometry::steering(Direction::Left, start, start + 5.0)),
    ]
}

/// What an owner input names: mostly an identifier with the module and kind its owner uses
/// (odd: lane change, velocity; even: avoidance, steering), so that updates often reach a live
/// scene and walk it through its lifecycle; a quarter of the time any module and any kind.
pub fn any_owner() -> impl Strategy<Value = (SceneId, Module, Geometry)> {
    prop_oneof![
        3 => (1..=IDS, -10.0f32..100.0).prop_map(|(n, at)| if n % 2 == 1 {
            (SceneId::from_u128(n), LANE_CHANGE, Geometry::velocity(at))
        } else {
            (SceneId::from_u128(n), AVOIDANCE, Geometry::steering(Direction::Left, at, at + 5.0))
        }),
        1 => (any_id(), any_module(), any_geometry()),
    ]
}

/// An owner's text for the operator: mostly none, sometimes a fixed one, sometimes any.
pub fn any_detail() -> impl Strategy<Value = Detail> {
    prop_oneof![
        2 => Just(Detail::EMPTY),
        1 => Just(Detail::new("waiting for the pedestrian")),
        1 => "\\PC{0,16}".prop_map(|text| Detail::new(&text)),
    ]
}

/// A distance for a factor of a module that does not cooperate: often one a scene has too
/// (the tests' owners report 5 and 10 m), or a signed zero, an infinity or a NaN.
pub fn any_other_distance() -> impl Strategy<Value = Distance> {
    prop_oneof![
        2 => (-10.0f32..100.0).prop_map(Distance),
        2 => proptest::sample::select(vec![5.0f32, 10.0, 0.0, -0.0, f32::INFINITY, f32::NAN, -f32::NAN])
            .prop_map(Distance),
    ]
}

pub fn any_input() -> impl Strategy<Value = Input> {
    prop_oneof![
        3 => (any_owner(), any_decision(), any::<bool>(), any_detail())
            .prop_map(|((id, module, geometry), decision, requested, detail)| Input::Register { id, module, report: Report { decision, requested, geometry, detail } }),
        4 => (any_owner(), any_phase(), any_decision(), any::<bool>(), any_detail())
            .prop_map(|((id, module, geometry), phase, decision, requested, detail)| Input::Update { id, module, phase, report: Report { decision, requested, geometry, detail } }),
        1 => any_owner().prop_map(|(id, module, _)| Input::Remove { id, module }),
        3 => proptest::collection::vec((any_id(), any_operator()).prop_map(|(id, decision)| Command { id, decision }), 0..6)
            .prop_map(|commands| Input::SetCommands { commands }),
        // One command alone, as an operator panel sends it: a batch fails for its first
        // failing command, so a rule such as a command for a scene that is not cancellable
        // is rare in batches of random identifiers.
        2 => (any_id(), any_operator())
            .prop_map(|(id, decision)| Input::SetCommands { commands: vec![Command { id, decision }] }),
        2 => proptest::collection::vec(
                (any_module(), proptest::sample::select(Policy::ALL.to_vec()))
                    .prop_map(|(module, policy)| PolicySetting { module, policy }),
                0..7,
            )
            .prop_map(|policies| Input::SetPolicies { policies }),
        2 => (0..=60u64).prop_map(|elapsed_ms| Input::Tick { elapsed_ms }),
    ]
}

/// Distances that tie often, and the values whose order is easy to get wrong.
pub fn any_crowd_distance() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => (-8i8..8).prop_map(|half_metres| f32::from(half_metres) / 2.0),
        1 => proptest::sample::select(vec![
            0.0,
            -0.0,
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7f80_0001),
            f32::from_bits(0xffff_ffff),
            f32::INFINITY,
            f32::NEG_INFINITY,
        ]),
    ]
}

/// Owner inputs and ticks over 40 identifiers, so that tables grow past their small form and
/// shrink back.
pub fn any_crowd_input() -> impl Strategy<Value = Input> {
    // Half the identifiers spread over all bits; the other half share their high 64 bits in
    // threes, which the factor lists' sort keys cannot tell apart.
    let id = (1..=40u128).prop_map(|n| {
        SceneId::from_u128(if n % 2 == 0 {
            n.wrapping_mul(0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c835)
        } else {
            ((n % 3) << 64) | (n * 0x9e37_79b9)
        })
    });
    let geometry = prop_oneof![
        any_crowd_distance().prop_map(Geometry::velocity),
        any_crowd_distance().prop_map(|start| Geometry::steering(Direction::Right, start, 1.0)),
    ];
    prop_oneof![
        6 => (id.clone(), any_module(), any_decision(), geometry.clone())
            .prop_map(|(id, module, decision, geometry)| Input::Register { id, module, report: Report::new(decision, geometry) }),
        4 => (id.clone(), any_module(), any_decision(), geometry)
            .prop_map(|(id, module, decision, geometry)| Input::Update { id, module, phase: Phase::Running, report: Report::new(decision, geometry) }),
        1 => (id, any_module()).prop_map(|(id, module)| Input::Remove { id, module }),
        1 => (0..=20u64).prop_map(|elapsed_ms| Input::Tick { elapsed_ms }),
    ]
}
