//! Outputs: cooperation statuses, the factor lists that carry them, and the AD API calls'
//! responses.

use crate::{
    Behavior, Command, CommandOutcome, Decision, Direction, Distance, Geometry, Input,
    OperatorDecision, PolicySetting, Pose, Rejection, Scene, SceneId, Sequence, State,
    SteeringStatus, Transition, VelocityStatus,
};

/// A live scene as an operator sees it (AD API `CooperationStatus`, `[COOP-OUT-STATUS.1]`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CooperationStatus {
    /// The scene. AD API `uuid`.
    pub id: SceneId,
    /// The module decision. AD API `autonomous`.
    pub module_decision: Decision,
    /// The operator decision. AD API `cooperator`.
    pub operator_decision: OperatorDecision,
    /// Whether a command would be accepted now. AD API `cancellable`.
    pub cancellable: bool,
}

impl CooperationStatus {
    /// The status of the live scene `scene`, whose identifier is `id`.
    const fn of(id: SceneId, scene: &Scene) -> Self {
        Self {
            id,
            module_decision: scene.module_decision(),
            operator_decision: scene.operator_decision(),
            cancellable: scene.is_cancellable(),
        }
    }
}

/// A velocity scene as a factor (AD API `VelocityFactor`).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct VelocityFactor {
    /// Where the vehicle would stop or slow down.
    pub pose: Pose,
    /// How far ahead that is.
    pub distance: Distance,
    /// What the vehicle is doing about it.
    pub status: VelocityStatus,
    /// The module's behaviour.
    pub behavior: Behavior,
    /// The module's sequence.
    pub sequence: Sequence,
    /// The scene's cooperation status.
    pub cooperation: CooperationStatus,
}

/// A steering scene as a factor (AD API `SteeringFactor`).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SteeringFactor {
    /// Start and end of the steering section.
    pub poses: [Pose; 2],
    /// Distances to the start and to the end.
    pub distances: [Distance; 2],
    /// Which way it turns.
    pub direction: Direction,
    /// What the vehicle is doing about it.
    pub status: SteeringStatus,
    /// The module's behaviour.
    pub behavior: Behavior,
    /// The module's sequence.
    pub sequence: Sequence,
    /// The scene's cooperation status.
    pub cooperation: CooperationStatus,
}

impl State {
    /// The cooperation status of a live scene (`[COOP-OUT-STATUS.1]`).
    #[must_use]
    pub fn status(&self, id: SceneId) -> Option<CooperationStatus> {
        self.scene(id).map(|scene| CooperationStatus::of(id, scene))
    }

    /// Replaces `out`'s contents with every live scene's status, in identifier order.
    /// Allocates only if `out` has too little capacity.
    pub fn statuses_into(&self, out: &mut Vec<CooperationStatus>) {
        out.clear();
        out.extend(
            self.scenes()
                .map(|(id, scene)| CooperationStatus::of(id, scene)),
        );
    }

    /// Replaces `out`'s contents with the velocity factors of the live velocity scenes, nearest
    /// first (`[COOP-OUT-ORDER.1]`). Allocates only if `out` has too little capacity.
    pub fn velocity_factors_into(&self, out: &mut Vec<VelocityFactor>) {
        out.clear();
        for (id, scene) in self.scenes() {
            if let Geometry::Velocity {
                pose,
                distance,
                status,
            } = scene.geometry()
            {
                out.push(VelocityFactor {
                    pose: *pose,
                    distance: *distance,
                    status: *status,
                    behavior: scene.module().behavior,
                    sequence: scene.module().sequence,
                    cooperation: CooperationStatus::of(id, scene),
                });
            }
        }
        out.sort_unstable_by(|a, b| {
            a.distance
                .total_cmp(&b.distance)
                .then(a.cooperation.id.cmp(&b.cooperation.id))
        });
    }

    /// Replaces `out`'s contents with the steering factors of the live steering scenes, nearest
    /// start first (`[COOP-OUT-ORDER.1]`). Allocates only if `out` has too little capacity.
    pub fn steering_factors_into(&self, out: &mut Vec<SteeringFactor>) {
        out.clear();
        for (id, scene) in self.scenes() {
            if let Geometry::Steering {
                poses,
                distances,
                direction,
                status,
            } = scene.geometry()
            {
                out.push(SteeringFactor {
                    poses: *poses,
                    distances: *distances,
                    direction: *direction,
                    status: *status,
                    behavior: scene.module().behavior,
                    sequence: scene.module().sequence,
                    cooperation: CooperationStatus::of(id, scene),
                });
            }
        }
        out.sort_unstable_by(|a, b| {
            let [a_start, _] = a.distances;
            let [b_start, _] = b.distances;
            a_start
                .total_cmp(&b_start)
                .then(a.cooperation.id.cmp(&b.cooperation.id))
        });
    }

    /// The AD API `set_commands` call (`[COOP-API-SET-COMMANDS.1]`): applies the batch, all or
    /// nothing, and answers with the status and every command's outcome.
    pub fn set_commands(&mut self, commands: Vec<Command>) -> CommandsResponse {
        let len = commands.len();
        let result = self.apply(&Input::SetCommands { commands });
        let outcomes = match &result {
            Ok(_) => vec![CommandOutcome::Applied; len],
            Err(Rejection::Commands { outcomes, .. }) => outcomes.clone(),
            Err(_) => vec![CommandOutcome::Withheld; len],
        };
        CommandsResponse {
            status: ResponseStatus::for_batch(len, &result),
            outcomes,
        }
    }

    /// The AD API `set_policies` call (`[COOP-API-SET-POLICIES.1]`): applies the batch, all or
    /// nothing.
    pub fn set_policies(&mut self, policies: Vec<PolicySetting>) -> ResponseStatus {
        let len = policies.len();
        let result = self.apply(&Input::SetPolicies { policies });
        ResponseStatus::for_batch(len, &result)
    }

    /// The AD API `get_policies` call (`[COOP-POL-GET.1]`): every module's current policy.
    #[must_use]
    pub fn get_policies(&self) -> (ResponseStatus, Vec<PolicySetting>) {
        (ResponseStatus::success(), self.policies().collect())
    }
}

/// The answer to `set_commands`: the AD API status plus one outcome per command, in order.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct CommandsResponse {
    /// The AD API response status.
    pub status: ResponseStatus,
    /// What happened to each command.
    pub outcomes: Vec<CommandOutcome>,
}

/// The AD API `ResponseStatus`: success, a code and a message (`[COOP-API-STATUS.1]`).
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ResponseStatus {
    /// Whether the call did what was asked.
    pub success: bool,
    /// `0` on plain success; otherwise one of the constants below.
    pub code: u16,
    /// Empty on plain success; otherwise what went wrong or what to know.
    pub message: String,
}

impl ResponseStatus {
    /// An error of no more specific kind.
    pub const UNKNOWN: u16 = 50_000;
    /// The service is not ready.
    pub const SERVICE_UNREADY: u16 = 50_001;
    /// The service timed out.
    pub const SERVICE_TIMEOUT: u16 = 50_002;
    /// A transform failed.
    pub const TRANSFORM_ERROR: u16 = 50_003;
    /// The request's parameters were refused: every rejection of a call.
    pub const PARAMETER_ERROR: u16 = 50_004;
    /// Warning: the call is deprecated.
    pub const DEPRECATED: u16 = 60_000;
    /// Warning: the call succeeded but changed nothing (an empty batch).
    pub const NO_EFFECT: u16 = 60_001;

    /// Plain success: `success = true`, `code = 0`, empty message.
    #[must_use]
    pub const fn success() -> Self {
        Self {
            success: true,
            code: 0,
            message: String::new(),
        }
    }

    /// The status of a batch call of `len` entries with this result: a rejection is a
    /// `PARAMETER_ERROR` carrying its explanation; an accepted empty batch is a success with
    /// the `NO_EFFECT` warning.
    #[must_use]
    pub fn for_batch(len: usize, result: &Result<Transition, Rejection>) -> Self {
        match result {
            Err(rejection) => Self {
                success: false,
                code: Self::PARAMETER_ERROR,
                message: rejection.to_string(),
            },
            Ok(_) if len == 0 => Self {
                success: true,
                code: Self::NO_EFFECT,
                message: "the batch is empty".into(),
            },
            Ok(_) => Self::success(),
        }
    }
}
