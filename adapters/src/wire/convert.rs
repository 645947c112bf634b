//! Conversions between the messages and the core's types.
//!
//! Into the core, a conversion parses: it either returns a core value, which cannot be
//! malformed, or a [`Malformed`] naming the first faulty field in field order. Out of the core,
//! a conversion always succeeds.

use cooperation::{
    Behavior, Command, Decision, Detail, Direction, Distance, Module, OperatorDecision, Policy,
    PolicySetting, SceneId, Sequence, SteeringStatus, VelocityStatus,
};

use super::{
    CooperationCommand, CooperationDecision, CooperationPolicy, CooperationStatus, FieldPath,
    Malformed, Point, Pose, Quaternion, SetCooperationCommandsRequest,
    SetCooperationPoliciesRequest, SteeringFactor, SteeringFactorArray, VelocityFactor,
    VelocityFactorArray, FRAME_ID,
};

/// What an operator decision field takes.
const OPERATOR_DECISIONS: &str = "DEACTIVATE, ACTIVATE, AUTONOMOUS or UNDECIDED";
/// What a module decision field takes.
const MODULE_DECISIONS: &str = "DEACTIVATE or ACTIVATE (a module decision)";

// -------------------------------------------------------------------------------------------
// Decisions and policies
// -------------------------------------------------------------------------------------------

/// A decision number that a field does not take, as the fault it is.
fn unaccepted_decision(decision: CooperationDecision, expected: &'static str) -> Malformed {
    let path = FieldPath::field("decision");
    let value = decision.decision.into();
    match decision.constant_name() {
        Some(constant) => Malformed::UnacceptedConstant {
            path,
            constant,
            value,
            expected,
        },
        None => Malformed::UndefinedConstant {
            path,
            constants: "CooperationDecision",
            value,
        },
    }
}

impl TryFrom<CooperationDecision> for OperatorDecision {
    type Error = Malformed;

    /// `DEACTIVATE`, `ACTIVATE`, `AUTONOMOUS` or `UNDECIDED` ("none"); a fault at `decision`
    /// otherwise.
    fn try_from(decision: CooperationDecision) -> Result<Self, Malformed> {
        decision
            .meaning()
            .ok_or_else(|| unaccepted_decision(decision, OPERATOR_DECISIONS))
    }
}

impl TryFrom<CooperationDecision> for Decision {
    type Error = Malformed;

    /// `DEACTIVATE` or `ACTIVATE`; a fault at `decision` otherwise.
    fn try_from(decision: CooperationDecision) -> Result<Self, Malformed> {
        match decision.meaning() {
            Some(OperatorDecision::Deactivate) => Ok(Self::Deactivate),
            Some(OperatorDecision::Activate) => Ok(Self::Activate),
            _ => Err(unaccepted_decision(decision, MODULE_DECISIONS)),
        }
    }
}

impl From<Decision> for CooperationDecision {
    fn from(decision: Decision) -> Self {
        Self::of(match decision {
            Decision::Deactivate => OperatorDecision::Deactivate,
            Decision::Activate => OperatorDecision::Activate,
        })
    }
}

/// A module from its behaviour and sequence strings.
fn module(behavior: &str, sequence: &str) -> Result<Module, Malformed> {
    let parsed_behavior =
        behavior
            .parse::<Behavior>()
            .map_err(|error| Malformed::InvalidBehavior {
                path: FieldPath::field("behavior"),
                given: error.given,
                problem: error.problem,
            })?;
    let parsed_sequence =
        sequence
            .parse::<Sequence>()
            .map_err(|error| Malformed::InvalidSequence {
                path: FieldPath::field("sequence"),
                given: error.given,
                problem: error.problem,
            })?;
    Ok(Module::with_sequence(parsed_behavior, parsed_sequence))
}

impl TryFrom<&CooperationCommand> for Command {
    type Error = Malformed;

    fn try_from(command: &CooperationCommand) -> Result<Self, Malformed> {
        Ok(Self {
            id: SceneId::from(command.uuid),
            decision: OperatorDecision::try_from(command.cooperator)
                .map_err(|e| e.in_field("cooperator"))?,
        })
    }
}

impl From<Command> for CooperationCommand {
    fn from(command: Command) -> Self {
        Self {
            uuid: command.id.into(),
            cooperator: command.decision.into(),
        }
    }
}

impl TryFrom<&CooperationPolicy> for PolicySetting {
    type Error = Malformed;

    fn try_from(setting: &CooperationPolicy) -> Result<Self, Malformed> {
        let module = module(&setting.behavior, &setting.sequence)?;
        let policy = match setting.policy {
            CooperationPolicy::OPTIONAL => Policy::Optional,
            CooperationPolicy::REQUIRED => Policy::Required,
            value => {
                return Err(Malformed::UndefinedConstant {
                    path: FieldPath::field("policy"),
                    constants: "CooperationPolicy",
                    value: value.into(),
                })
            }
        };
        Ok(Self { module, policy })
    }
}

impl From<PolicySetting> for CooperationPolicy {
    fn from(setting: PolicySetting) -> Self {
        Self {
            behavior: setting.module.behavior.as_str().to_owned(),
            sequence: setting.module.sequence.as_str().to_owned(),
            policy: match setting.policy {
                Policy::Optional => Self::OPTIONAL,
                Policy::Required => Self::REQUIRED,
            },
        }
    }
}

impl TryFrom<&CooperationStatus> for cooperation::CooperationStatus {
    type Error = Malformed;

    fn try_from(status: &CooperationStatus) -> Result<Self, Malformed> {
        Ok(Self {
            id: SceneId::from(status.uuid),
            module_decision: Decision::try_from(status.autonomous)
                .map_err(|e| e.in_field("autonomous"))?,
            operator_decision: OperatorDecision::try_from(status.cooperator)
                .map_err(|e| e.in_field("cooperator"))?,
            cancellable: status.cancellable,
        })
    }
}

impl From<cooperation::CooperationStatus> for CooperationStatus {
    fn from(status: cooperation::CooperationStatus) -> Self {
        Self {
            uuid: status.id.into(),
            autonomous: status.module_decision.into(),
            cooperator: status.operator_decision.into(),
            cancellable: status.cancellable,
        }
    }
}

/// Each entry converted, a fault prefixed with its position.
fn each<'a, T: 'a, U>(
    items: &'a [T],
    convert: impl Fn(&'a T) -> Result<U, Malformed>,
) -> Result<Vec<U>, Malformed> {
    items
        .iter()
        .enumerate()
        .map(|(index, item)| convert(item).map_err(|e| e.at_index(index)))
        .collect()
}

impl SetCooperationCommandsRequest {
    /// The commands as the core takes them, in request order; the first fault is named by
    /// its path from the request, e.g. `commands[2].cooperator.decision`.
    ///
    /// # Errors
    /// The first [`Malformed`] command. Batch rules (duplicates, the batch limit, unknown
    /// scenes) are the core's, checked when the commands are applied.
    pub fn to_commands(&self) -> Result<Vec<Command>, Malformed> {
        each(&self.commands, Command::try_from).map_err(|e| e.in_field("commands"))
    }
}

impl FromIterator<Command> for SetCooperationCommandsRequest {
    fn from_iter<I: IntoIterator<Item = Command>>(commands: I) -> Self {
        Self {
            commands: commands.into_iter().map(Into::into).collect(),
        }
    }
}

impl SetCooperationPoliciesRequest {
    /// The policy settings as the core takes them, in request order; the first fault is named
    /// by its path from the request, e.g. `policies[0].behavior`.
    ///
    /// # Errors
    /// The first [`Malformed`] setting. Batch rules (a module twice, a module without a
    /// policy, the batch limit) are the core's, checked when the settings are applied.
    pub fn to_policies(&self) -> Result<Vec<PolicySetting>, Malformed> {
        each(&self.policies, PolicySetting::try_from).map_err(|e| e.in_field("policies"))
    }
}

impl FromIterator<PolicySetting> for SetCooperationPoliciesRequest {
    fn from_iter<I: IntoIterator<Item = PolicySetting>>(policies: I) -> Self {
        Self {
            policies: policies.into_iter().map(Into::into).collect(),
        }
    }
}

// -------------------------------------------------------------------------------------------
// Factors
// -------------------------------------------------------------------------------------------

impl From<Pose> for cooperation::Pose {
    fn from(pose: Pose) -> Self {
        let Point { x, y, z } = pose.position;
        let Quaternion {
            x: qx,
            y: qy,
            z: qz,
            w: qw,
        } = pose.orientation;
        Self {
            position: [x, y, z],
            orientation: [qx, qy, qz, qw],
        }
    }
}

impl From<cooperation::Pose> for Pose {
    fn from(pose: cooperation::Pose) -> Self {
        let [x, y, z] = pose.position;
        let [qx, qy, qz, qw] = pose.orientation;
        Self {
            position: Point { x, y, z },
            orientation: Quaternion {
                x: qx,
                y: qy,
                z: qz,
                w: qw,
            },
        }
    }
}

/// The one cooperation status a factor of the core carries.
/// A factor's cooperation status: none for a module that does not cooperate, one for a
/// scene, never more.
fn cooperation(
    list: &[CooperationStatus],
) -> Result<Option<cooperation::CooperationStatus>, Malformed> {
    match list {
        [] => Ok(None),
        [status] => cooperation::CooperationStatus::try_from(status)
            .map(Some)
            .map_err(|e| e.at_index(0).in_field("cooperation")),
        _ => Err(Malformed::TooManyCooperation {
            path: FieldPath::field("cooperation"),
            len: list.len(),
        }),
    }
}

/// A constant of a factor's `u16` field, or the fault at `field`.
fn constant<T>(
    value: u16,
    field: &str,
    constants: &'static str,
    parse: impl Fn(u16) -> Option<T>,
) -> Result<T, Malformed> {
    parse(value).ok_or_else(|| Malformed::UndefinedConstant {
        path: FieldPath::field(field),
        constants,
        value,
    })
}

const fn velocity_status(value: u16) -> Option<VelocityStatus> {
    match value {
        VelocityFactor::UNKNOWN => Some(VelocityStatus::Unknown),
        VelocityFactor::APPROACHING => Some(VelocityStatus::Approaching),
        VelocityFactor::STOPPED => Some(VelocityStatus::Stopped),
        _ => None,
    }
}

const fn velocity_status_constant(status: VelocityStatus) -> u16 {
    match status {
        VelocityStatus::Unknown => VelocityFactor::UNKNOWN,
        VelocityStatus::Approaching => VelocityFactor::APPROACHING,
        VelocityStatus::Stopped => VelocityFactor::STOPPED,
    }
}

const fn steering_status(value: u16) -> Option<SteeringStatus> {
    match value {
        SteeringFactor::UNKNOWN => Some(SteeringStatus::Unknown),
        SteeringFactor::APPROACHING => Some(SteeringStatus::Approaching),
        SteeringFactor::TURNING => Some(SteeringStatus::Turning),
        _ => None,
    }
}

const fn steering_status_constant(status: SteeringStatus) -> u16 {
    match status {
        SteeringStatus::Unknown => SteeringFactor::UNKNOWN,
        SteeringStatus::Approaching => SteeringFactor::APPROACHING,
        SteeringStatus::Turning => SteeringFactor::TURNING,
    }
}

const fn direction(value: u16) -> Option<Direction> {
    match value {
        SteeringFactor::UNKNOWN => Some(Direction::Unknown),
        SteeringFactor::LEFT => Some(Direction::Left),
        SteeringFactor::RIGHT => Some(Direction::Right),
        SteeringFactor::STRAIGHT => Some(Direction::Straight),
        _ => None,
    }
}

const fn direction_constant(direction: Direction) -> u16 {
    match direction {
        Direction::Unknown => SteeringFactor::UNKNOWN,
        Direction::Left => SteeringFactor::LEFT,
        Direction::Right => SteeringFactor::RIGHT,
        Direction::Straight => SteeringFactor::STRAIGHT,
    }
}

impl TryFrom<&VelocityFactor> for cooperation::VelocityFactor {
    type Error = Malformed;

    /// The factor of a cooperating scene, or of a module that does not cooperate (an empty
    /// `cooperation` list), `detail` included. Distances are taken as they are, NaN included:
    /// the core orders them totally.
    fn try_from(factor: &VelocityFactor) -> Result<Self, Malformed> {
        let status = constant(
            factor.status,
            "status",
            "VelocityFactor status",
            velocity_status,
        )?;
        let module = module(&factor.behavior, &factor.sequence)?;
        Ok(Self {
            pose: factor.pose.into(),
            distance: Distance(factor.distance),
            status,
            behavior: module.behavior,
            sequence: module.sequence,
            detail: Detail::new(&factor.detail),
            cooperation: cooperation(&factor.cooperation)?,
        })
    }
}

impl From<cooperation::VelocityFactor> for VelocityFactor {
    fn from(factor: cooperation::VelocityFactor) -> Self {
        Self {
            pose: factor.pose.into(),
            distance: factor.distance.0,
            status: velocity_status_constant(factor.status),
            behavior: factor.behavior.as_str().to_owned(),
            sequence: factor.sequence.as_str().to_owned(),
            detail: factor.detail.as_str().to_owned(),
            cooperation: factor.cooperation.map(Into::into).into_iter().collect(),
        }
    }
}

impl TryFrom<&SteeringFactor> for cooperation::SteeringFactor {
    type Error = Malformed;

    /// The factor of a cooperating scene, or of a module that does not cooperate (an empty
    /// `cooperation` list), `detail` included. Distances are taken as they are, NaN included:
    /// the core orders them totally.
    fn try_from(factor: &SteeringFactor) -> Result<Self, Malformed> {
        let direction = constant(
            factor.direction,
            "direction",
            "SteeringFactor direction",
            direction,
        )?;
        let status = constant(
            factor.status,
            "status",
            "SteeringFactor status",
            steering_status,
        )?;
        let module = module(&factor.behavior, &factor.sequence)?;
        Ok(Self {
            poses: factor.pose.map(Into::into),
            distances: factor.distance.map(Distance),
            direction,
            status,
            behavior: module.behavior,
            sequence: module.sequence,
            detail: Detail::new(&factor.detail),
            cooperation: cooperation(&factor.cooperation)?,
        })
    }
}

impl From<cooperation::SteeringFactor> for SteeringFactor {
    fn from(factor: cooperation::SteeringFactor) -> Self {
        Self {
            pose: factor.poses.map(Into::into),
            distance: factor.distances.map(|d| d.0),
            direction: direction_constant(factor.direction),
            status: steering_status_constant(factor.status),
            behavior: factor.behavior.as_str().to_owned(),
            sequence: factor.sequence.as_str().to_owned(),
            detail: factor.detail.as_str().to_owned(),
            cooperation: factor.cooperation.map(Into::into).into_iter().collect(),
        }
    }
}

/// The frame check every factor array shares.
fn map_frame(frame_id: &str) -> Result<(), Malformed> {
    if frame_id == FRAME_ID {
        Ok(())
    } else {
        Err(Malformed::Frame {
            path: FieldPath::field("frame_id"),
            given: frame_id.to_owned(),
        }
        .in_field("header"))
    }
}

impl VelocityFactorArray {
    /// The factors as the core reports them, for a consumer of the stream (for example, to
    /// compare a recording with the core). The header's frame must be `map`.
    ///
    /// # Errors
    /// The first [`Malformed`] field, named from the array, e.g. `factors[1].cooperation`.
    pub fn to_factors(&self) -> Result<Vec<cooperation::VelocityFactor>, Malformed> {
        map_frame(&self.header.frame_id)?;
        each(&self.factors, cooperation::VelocityFactor::try_from)
            .map_err(|e| e.in_field("factors"))
    }
}

impl SteeringFactorArray {
    /// The factors as the core reports them, for a consumer of the stream. The header's frame
    /// must be `map`.
    ///
    /// # Errors
    /// The first [`Malformed`] field, named from the array, e.g. `factors[1].status`.
    pub fn to_factors(&self) -> Result<Vec<cooperation::SteeringFactor>, Malformed> {
        map_frame(&self.header.frame_id)?;
        each(&self.factors, cooperation::SteeringFactor::try_from)
            .map_err(|e| e.in_field("factors"))
    }
}
