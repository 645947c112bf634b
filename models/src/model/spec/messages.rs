//! What the AD API's factor messages must carry for a state, stated from the specification
//! (§6.5, `[COOP-OUT-STATUS.1]`, `[COOP-OUT-ORDER.1]`) and the AD API's message definitions
//! (`autoware_adapi_v1_msgs`: `CooperationDecision`, `VelocityFactor`, `SteeringFactor`), never
//! by calling the adapters' conversions: the engine model compares the messages the engine
//! writes with these, field by field and in order.

use core::cmp::Ordering;

use cooperation::{
    Decision, Direction, Geometry, OperatorDecision, Phase, SceneId, State, SteeringStatus,
    VelocityStatus,
};

/// `CooperationDecision`'s constants.
pub mod decision {
    /// `DEACTIVATE`.
    pub const DEACTIVATE: u8 = 1;
    /// `ACTIVATE`.
    pub const ACTIVATE: u8 = 2;
    /// `AUTONOMOUS`.
    pub const AUTONOMOUS: u8 = 3;
    /// `UNDECIDED`.
    pub const UNDECIDED: u8 = 4;
}

/// `[COOP-OUT-ORDER.1]`'s order of distances, from its text: ascending, every NaN, of either
/// sign, last (NaNs in the order of their bits, positive ones first).
#[must_use]
pub fn distance_order(a: f32, b: f32) -> Ordering {
    match (a.is_nan(), b.is_nan()) {
        (false, false) => a.total_cmp(&b),
        (true, false) => Ordering::Greater,
        (false, true) => Ordering::Less,
        (true, true) => (a.to_bits() >> 31)
            .cmp(&(b.to_bits() >> 31))
            .then(a.total_cmp(&b)),
    }
}

/// One factor as the streams must carry it, the fields the spec's mapping decides: the
/// identifier's bytes, the distances' bits (one for a velocity factor, start and end for a
/// steering one), the direction and status constants, behaviour, sequence, detail, and the
/// cooperation status (module decision, operator decision, cancellable).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Factor {
    /// The scene's identifier.
    pub uuid: Vec<u8>,
    /// The distances' bit patterns.
    pub distances: Vec<u32>,
    /// `SteeringFactor.direction` (0 for a velocity factor).
    pub direction: u16,
    /// `status`.
    pub status: u16,
    /// `behavior`.
    pub behavior: String,
    /// `sequence`.
    pub sequence: String,
    /// `detail`.
    pub detail: String,
    /// `cooperation[0].autonomous.decision`.
    pub autonomous: u8,
    /// `cooperation[0].cooperator.decision`.
    pub cooperator: u8,
    /// `cooperation[0].cancellable`.
    pub cancellable: bool,
}

const fn module_constant(decision: Decision) -> u8 {
    match decision {
        Decision::Deactivate => decision::DEACTIVATE,
        Decision::Activate => decision::ACTIVATE,
    }
}

const fn operator_constant(decision: OperatorDecision) -> u8 {
    match decision {
        OperatorDecision::Deactivate => decision::DEACTIVATE,
        OperatorDecision::Activate => decision::ACTIVATE,
        OperatorDecision::Autonomous => decision::AUTONOMOUS,
        OperatorDecision::Undecided => decision::UNDECIDED,
    }
}

/// `SteeringFactor`'s direction constants: `LEFT = 1, RIGHT = 2, STRAIGHT = 3`.
const fn direction_constant(direction: Direction) -> u16 {
    match direction {
        Direction::Unknown => 0,
        Direction::Left => 1,
        Direction::Right => 2,
        Direction::Straight => 3,
    }
}

/// `VelocityFactor`'s status constants: `APPROACHING = 1, STOPPED = 2`.
const fn velocity_status(status: VelocityStatus) -> u16 {
    match status {
        VelocityStatus::Unknown => 0,
        VelocityStatus::Approaching => 1,
        VelocityStatus::Stopped => 2,
    }
}

/// `SteeringFactor`'s status constants: `APPROACHING = 1, TURNING = 3`.
const fn steering_status(status: SteeringStatus) -> u16 {
    match status {
        SteeringStatus::Unknown => 0,
        SteeringStatus::Approaching => 1,
        SteeringStatus::Turning => 3,
    }
}

/// The factors of `state`'s live scenes of one kind (velocity, or steering), in
/// `[COOP-OUT-ORDER.1]`'s order: by the (start) distance, then by identifier.
#[must_use]
pub fn factors(state: &State, steering: bool) -> Vec<Factor> {
    let mut listed: Vec<(f32, SceneId, Factor)> = state
        .scenes()
        .filter_map(|(id, scene)| {
            let (distances, direction, status) = match *scene.geometry() {
                Geometry::Velocity {
                    distance, status, ..
                } if !steering => (vec![distance.0], 0, velocity_status(status)),
                Geometry::Steering {
                    distances,
                    direction,
                    status,
                    ..
                } if steering => (
                    distances.iter().map(|d| d.0).collect(),
                    direction_constant(direction),
                    steering_status(status),
                ),
                _ => return None,
            };
            let module = scene.module();
            let factor = Factor {
                uuid: id.to_bytes().to_vec(),
                distances: distances.iter().map(|d| d.to_bits()).collect(),
                direction,
                status,
                behavior: module.behavior.as_str().to_owned(),
                sequence: module.sequence.as_str().to_owned(),
                detail: scene.detail().as_str().to_owned(),
                autonomous: module_constant(scene.module_decision()),
                cooperator: operator_constant(scene.operator_decision()),
                // `[COOP-CANCELLABLE.1]`: waiting or running.
                cancellable: matches!(scene.phase(), Phase::Waiting | Phase::Running),
            };
            Some((distances.first().copied().unwrap_or(f32::NAN), id, factor))
        })
        .collect();
    listed.sort_by(|a, b| distance_order(a.0, b.0).then(a.1.cmp(&b.1)));
    listed.into_iter().map(|(_, _, factor)| factor).collect()
}
