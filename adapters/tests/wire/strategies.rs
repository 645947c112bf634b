//! Strategies: the messages as anything may send them, and the core's values.

use cooperation::*;
use cooperation_adapters::wire;
use cooperation_adapters::Time;
use proptest::prelude::*;
use proptest::sample::select;

// -------------------------------------------------------------------------------------------
// Strategies: messages as anything may send them
// -------------------------------------------------------------------------------------------

/// Every finite `f64`, signed zeros and subnormals included: what JSON can carry.
pub(crate) fn finite_f64() -> impl Strategy<Value = f64> {
    use proptest::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
}

pub(crate) fn finite_f32() -> impl Strategy<Value = f32> {
    use proptest::num::f32::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
    POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
}

/// Behaviour and sequence strings: the known ones, near misses, and anything.
pub(crate) fn name() -> impl Strategy<Value = String> {
    prop_oneof![
        select(Behavior::ALL.to_vec()).prop_map(|behavior| behavior.as_str().to_owned()),
        select(Sequence::ALL.to_vec()).prop_map(|sequence| sequence.as_str().to_owned()),
        // User extensions, valid or too long.
        Just("valet-parking".to_owned()),
        "[a-z][a-z0-9-]{0,33}",
        "\\PC{0,12}",
    ]
}

pub(crate) fn time() -> impl Strategy<Value = Time> {
    (any::<i32>(), 0..1_000_000_000u32).prop_map(|(sec, nanosec)| Time { sec, nanosec })
}

pub(crate) fn header() -> impl Strategy<Value = wire::Header> {
    (time(), prop_oneof![Just("map".to_owned()), "\\PC{0,8}"])
        .prop_map(|(stamp, frame_id)| wire::Header { stamp, frame_id })
}

pub(crate) fn point() -> impl Strategy<Value = wire::Point> {
    (finite_f64(), finite_f64(), finite_f64()).prop_map(|(x, y, z)| wire::Point { x, y, z })
}

pub(crate) fn quaternion() -> impl Strategy<Value = wire::Quaternion> {
    (finite_f64(), finite_f64(), finite_f64(), finite_f64())
        .prop_map(|(x, y, z, w)| wire::Quaternion { x, y, z, w })
}

pub(crate) fn pose() -> impl Strategy<Value = wire::Pose> {
    (point(), quaternion()).prop_map(|(position, orientation)| wire::Pose {
        position,
        orientation,
    })
}

/// Any 16 bytes (a UUID of another length does not read: `malformed.rs`).
pub(crate) fn uuid() -> impl Strategy<Value = wire::Uuid> {
    prop::array::uniform16(any::<u8>()).prop_map(|uuid| wire::Uuid { uuid })
}

/// Mostly defined constants, sometimes any number.
pub(crate) fn decision() -> impl Strategy<Value = wire::CooperationDecision> {
    prop_oneof![4 => 0..=4u8, 1 => any::<u8>()]
        .prop_map(|decision| wire::CooperationDecision { decision })
}

pub(crate) fn constant16() -> impl Strategy<Value = u16> {
    prop_oneof![4 => 0..=3u16, 1 => any::<u16>()]
}

pub(crate) fn status() -> impl Strategy<Value = wire::CooperationStatus> {
    (uuid(), decision(), decision(), any::<bool>()).prop_map(
        |(uuid, autonomous, cooperator, cancellable)| wire::CooperationStatus {
            uuid,
            autonomous,
            cooperator,
            cancellable,
        },
    )
}

pub(crate) fn command() -> impl Strategy<Value = wire::CooperationCommand> {
    (uuid(), decision())
        .prop_map(|(uuid, cooperator)| wire::CooperationCommand { uuid, cooperator })
}

pub(crate) fn policy() -> impl Strategy<Value = wire::CooperationPolicy> {
    (name(), name(), prop_oneof![4 => 0..=2u8, 1 => any::<u8>()]).prop_map(
        |(behavior, sequence, policy)| wire::CooperationPolicy {
            behavior,
            sequence,
            policy,
        },
    )
}

pub(crate) fn cooperation() -> impl Strategy<Value = Vec<wire::CooperationStatus>> {
    prop_oneof![4 => prop::collection::vec(status(), 1..=1), 1 => prop::collection::vec(status(), 0..3)]
}

pub(crate) fn velocity_factor() -> impl Strategy<Value = wire::VelocityFactor> {
    (
        pose(),
        finite_f32(),
        constant16(),
        name(),
        name(),
        "\\PC{0,8}",
        cooperation(),
    )
        .prop_map(
            |(pose, distance, status, behavior, sequence, detail, cooperation)| {
                wire::VelocityFactor {
                    pose,
                    distance,
                    status,
                    behavior,
                    sequence,
                    detail,
                    cooperation,
                }
            },
        )
}

pub(crate) fn steering_factor() -> impl Strategy<Value = wire::SteeringFactor> {
    (
        [pose(), pose()],
        [finite_f32(), finite_f32()],
        constant16(),
        constant16(),
        name(),
        name(),
        "\\PC{0,8}",
        cooperation(),
    )
        .prop_map(
            |(pose, distance, direction, status, behavior, sequence, detail, cooperation)| {
                wire::SteeringFactor {
                    pose,
                    distance,
                    direction,
                    status,
                    behavior,
                    sequence,
                    detail,
                    cooperation,
                }
            },
        )
}

pub(crate) fn velocity_array() -> impl Strategy<Value = wire::VelocityFactorArray> {
    (header(), prop::collection::vec(velocity_factor(), 0..4))
        .prop_map(|(header, factors)| wire::VelocityFactorArray { header, factors })
}

pub(crate) fn steering_array() -> impl Strategy<Value = wire::SteeringFactorArray> {
    (header(), prop::collection::vec(steering_factor(), 0..4))
        .prop_map(|(header, factors)| wire::SteeringFactorArray { header, factors })
}

pub(crate) fn response_status() -> impl Strategy<Value = wire::ResponseStatus> {
    (
        any::<bool>(),
        prop_oneof![
            Just(0u16),
            50_000..=50_004u16,
            60_000..=60_001u16,
            any::<u16>()
        ],
        "\\PC{0,16}",
    )
        .prop_map(|(success, code, message)| wire::ResponseStatus {
            success,
            code,
            message,
        })
}

pub(crate) fn commands_request() -> impl Strategy<Value = wire::SetCooperationCommandsRequest> {
    prop::collection::vec(command(), 0..6)
        .prop_map(|commands| wire::SetCooperationCommandsRequest { commands })
}

pub(crate) fn policies_request() -> impl Strategy<Value = wire::SetCooperationPoliciesRequest> {
    prop::collection::vec(policy(), 0..6)
        .prop_map(|policies| wire::SetCooperationPoliciesRequest { policies })
}

// -------------------------------------------------------------------------------------------
// Strategies: core values
// -------------------------------------------------------------------------------------------

pub(crate) fn scene_id() -> impl Strategy<Value = SceneId> {
    any::<u128>().prop_map(SceneId::from_u128)
}

/// Any `f64` bit pattern: the core holds NaNs and infinities too.
pub(crate) fn any_f64() -> impl Strategy<Value = f64> {
    any::<u64>().prop_map(f64::from_bits)
}

pub(crate) fn any_distance() -> impl Strategy<Value = Distance> {
    any::<u32>().prop_map(|bits| Distance(f32::from_bits(bits)))
}

pub(crate) fn core_pose() -> impl Strategy<Value = Pose> {
    (
        [any_f64(), any_f64(), any_f64()],
        [any_f64(), any_f64(), any_f64(), any_f64()],
    )
        .prop_map(|(position, orientation)| Pose {
            position,
            orientation,
        })
}

pub(crate) fn core_status() -> impl Strategy<Value = CooperationStatus> {
    (
        scene_id(),
        select(Decision::ALL.to_vec()),
        select(OperatorDecision::ALL.to_vec()),
        any::<bool>(),
    )
        .prop_map(
            |(id, module_decision, operator_decision, cancellable)| CooperationStatus {
                id,
                module_decision,
                operator_decision,
                cancellable,
            },
        )
}

pub(crate) fn module() -> impl Strategy<Value = Module> {
    (
        select(Behavior::ALL.to_vec()),
        select(Sequence::ALL.to_vec()),
    )
        .prop_map(|(behavior, sequence)| Module { behavior, sequence })
}

pub(crate) fn core_velocity_factor() -> impl Strategy<Value = VelocityFactor> {
    let status = prop_oneof![
        Just(VelocityStatus::Unknown),
        Just(VelocityStatus::Approaching),
        Just(VelocityStatus::Stopped)
    ];
    (
        core_pose(),
        any_distance(),
        status,
        module(),
        detail(),
        // Sometimes a factor of a module that does not cooperate.
        prop::option::weighted(0.8, core_status()),
    )
        .prop_map(
            |(pose, distance, status, module, detail, cooperation)| VelocityFactor {
                pose,
                distance,
                status,
                behavior: module.behavior,
                sequence: module.sequence,
                detail,
                cooperation,
            },
        )
}

/// A factor's detail: none, or any text (any characters, control ones included).
pub(crate) fn detail() -> impl Strategy<Value = Detail> {
    prop_oneof![
        Just(Detail::EMPTY),
        ".{0,24}".prop_map(|text| Detail::new(&text))
    ]
}

pub(crate) fn core_steering_factor() -> impl Strategy<Value = SteeringFactor> {
    let direction = prop_oneof![
        Just(Direction::Unknown),
        Just(Direction::Left),
        Just(Direction::Right),
        Just(Direction::Straight)
    ];
    let status = prop_oneof![
        Just(SteeringStatus::Unknown),
        Just(SteeringStatus::Approaching),
        Just(SteeringStatus::Turning)
    ];
    (
        [core_pose(), core_pose()],
        [any_distance(), any_distance()],
        direction,
        status,
        module(),
        (detail(), prop::option::weighted(0.8, core_status())),
    )
        .prop_map(
            |(poses, distances, direction, status, module, (detail, cooperation))| SteeringFactor {
                poses,
                distances,
                direction,
                status,
                behavior: module.behavior,
                sequence: module.sequence,
                detail,
                cooperation,
            },
        )
}
