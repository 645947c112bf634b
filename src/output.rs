//! Outputs: cooperation statuses and the factor lists that carry them.

use core::cmp::Ordering;

use crate::{
    Behavior, Decision, Detail, Direction, Distance, Geometry, OperatorDecision, Pose, Scene,
    SceneId, Sequence, State, SteeringStatus, VelocityStatus,
};

/// A live scene as an operator sees it (AD API `CooperationStatus`, `[COOP-OUT-STATUS.1]`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
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

/// A velocity scene as a factor (AD API `VelocityFactor`), or a factor of a module that does
/// not cooperate.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
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
    /// The owner's text for the operator.
    pub detail: Detail,
    /// The scene's cooperation status; `None` for a factor of a module that does not
    /// cooperate, which a planner publishes in the same stream (AD API: an empty
    /// `cooperation` list).
    pub cooperation: Option<CooperationStatus>,
}

/// A steering scene as a factor (AD API `SteeringFactor`), or a factor of a module that does
/// not cooperate.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
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
    /// The owner's text for the operator.
    pub detail: Detail,
    /// The scene's cooperation status; `None` for a factor of a module that does not
    /// cooperate, which a planner publishes in the same stream (AD API: an empty
    /// `cooperation` list).
    pub cooperation: Option<CooperationStatus>,
}

/// At equal distance (`[COOP-OUT-ORDER.1]`): scenes by identifier, then factors without a
/// cooperation status.
fn tie(a: Option<&CooperationStatus>, b: Option<&CooperationStatus>) -> Ordering {
    match (a, b) {
        (Some(a), Some(b)) => a.id.cmp(&b.id),
        (Some(_), None) => Ordering::Less,
        (None, Some(_)) => Ordering::Greater,
        (None, None) => Ordering::Equal,
    }
}

/// A factor given to [`State::velocity_factors_with`] or [`State::steering_factors_with`]
/// carries a cooperation status: only the core reports scenes, so that a scene is never
/// listed twice or with a status the core does not hold.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct CooperatingFactor {
    /// Its position among the factors given.
    pub index: usize,
    /// The scene its status names.
    pub id: SceneId,
}

impl core::fmt::Display for CooperatingFactor {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "factor {} carries the cooperation status of scene {}: only factors of modules \
             that do not cooperate may be added to the core's",
            self.index, self.id
        )
    }
}

impl std::error::Error for CooperatingFactor {}

/// The first factor of `others` with a cooperation status, as the error.
fn check_others<'a>(
    others: impl IntoIterator<Item = Option<&'a CooperationStatus>>,
) -> Result<(), CooperatingFactor> {
    match others
        .into_iter()
        .enumerate()
        .find_map(|(index, status)| status.map(|status| (index, status.id)))
    {
        Some((index, id)) => Err(CooperatingFactor { index, id }),
        None => Ok(()),
    }
}

impl VelocityFactor {
    /// The scene this factor reports, or `None` for a module that does not cooperate.
    #[must_use]
    pub fn scene(&self) -> Option<SceneId> {
        self.cooperation.map(|status| status.id)
    }

    /// `[COOP-OUT-ORDER.1]`: nearest first, then [`tie`].
    fn order(a: &Self, b: &Self) -> Ordering {
        a.distance
            .total_cmp(&b.distance)
            .then_with(|| tie(a.cooperation.as_ref(), b.cooperation.as_ref()))
    }

    /// The factor of the live scene `scene`, whose identifier is `id`, if it is a velocity
    /// scene.
    fn of(id: SceneId, scene: &Scene) -> Option<Self> {
        match *scene.geometry() {
            Geometry::Velocity {
                pose,
                distance,
                status,
            } => Some(Self {
                pose,
                distance,
                status,
                behavior: scene.module().behavior,
                sequence: scene.module().sequence,
                detail: scene.detail().clone(),
                cooperation: Some(CooperationStatus::of(id, scene)),
            }),
            Geometry::Steering { .. } => None,
        }
    }
}

impl SteeringFactor {
    /// The scene this factor reports, or `None` for a module that does not cooperate.
    #[must_use]
    pub fn scene(&self) -> Option<SceneId> {
        self.cooperation.map(|status| status.id)
    }

    /// `[COOP-OUT-ORDER.1]`: nearest start first, then [`tie`].
    fn order(a: &Self, b: &Self) -> Ordering {
        let [a_start, _] = a.distances;
        let [b_start, _] = b.distances;
        a_start
            .total_cmp(&b_start)
            .then_with(|| tie(a.cooperation.as_ref(), b.cooperation.as_ref()))
    }

    /// The factor of the live scene `scene`, whose identifier is `id`, if it is a steering
    /// scene.
    fn of(id: SceneId, scene: &Scene) -> Option<Self> {
        match *scene.geometry() {
            Geometry::Steering {
                poses,
                distances,
                direction,
                status,
            } => Some(Self {
                poses,
                distances,
                direction,
                status,
                behavior: scene.module().behavior,
                sequence: scene.module().sequence,
                detail: scene.detail().clone(),
                cooperation: Some(CooperationStatus::of(id, scene)),
            }),
            Geometry::Velocity { .. } => None,
        }
    }
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
        out.extend(
            self.scenes_in_any_order()
                .filter_map(|(id, scene)| VelocityFactor::of(id, scene)),
        );
        out.sort_unstable_by(VelocityFactor::order);
    }

    /// Replaces `out`'s contents with the steering factors of the live steering scenes, nearest
    /// start first (`[COOP-OUT-ORDER.1]`). Allocates only if `out` has too little capacity.
    pub fn steering_factors_into(&self, out: &mut Vec<SteeringFactor>) {
        out.clear();
        out.extend(
            self.scenes_in_any_order()
                .filter_map(|(id, scene)| SteeringFactor::of(id, scene)),
        );
        out.sort_unstable_by(SteeringFactor::order);
    }

    /// Replaces `out`'s contents with the velocity factors of the live velocity scenes and
    /// `others`, the planner's factors of modules that do not cooperate, in one list ordered
    /// as [`velocity_factors_into`](Self::velocity_factors_into) orders it: nearest first; at
    /// equal distance, scenes by identifier and then `others` in the order given.
    ///
    /// # Errors
    /// [`CooperatingFactor`] for the first of `others` with a cooperation status; `out` is
    /// then left as it was.
    pub fn velocity_factors_with(
        &self,
        others: &[VelocityFactor],
        out: &mut Vec<VelocityFactor>,
    ) -> Result<(), CooperatingFactor> {
        check_others(others.iter().map(|f| f.cooperation.as_ref()))?;
        self.velocity_factors_into(out);
        out.extend_from_slice(others);
        out.sort_by(VelocityFactor::order);
        Ok(())
    }

    /// Replaces `out`'s contents with the steering factors of the live steering scenes and
    /// `others`, the planner's factors of modules that do not cooperate, in one list ordered
    /// as [`steering_factors_into`](Self::steering_factors_into) orders it: nearest start
    /// first; at equal distance, scenes by identifier and then `others` in the order given.
    ///
    /// # Errors
    /// [`CooperatingFactor`] for the first of `others` with a cooperation status; `out` is
    /// then left as it was.
    pub fn steering_factors_with(
        &self,
        others: &[SteeringFactor],
        out: &mut Vec<SteeringFactor>,
    ) -> Result<(), CooperatingFactor> {
        check_others(others.iter().map(|f| f.cooperation.as_ref()))?;
        self.steering_factors_into(out);
        out.extend_from_slice(others);
        out.sort_by(SteeringFactor::order);
        Ok(())
    }

    /// Fills `lists` with both factor lists, ordered as [`velocity_factors_into`] and
    /// [`steering_factors_into`] order them (`[COOP-OUT-ORDER.1]`).
    ///
    /// The form for a planning cycle: it sorts small keys kept in `lists` and then writes each
    /// factor once in its place, where the two functions above sort the factors themselves.
    /// Allocates only if a buffer of `lists` has too little capacity, so a planner that keeps
    /// one `FactorLists` from cycle to cycle allocates nothing once it has grown.
    ///
    /// [`velocity_factors_into`]: Self::velocity_factors_into
    /// [`steering_factors_into`]: Self::steering_factors_into
    pub fn factors_into(&self, lists: &mut FactorLists) {
        let FactorLists {
            velocity,
            steering,
            keys,
        } = lists;
        if u32::try_from(self.scene_count()).is_err() {
            // Positions do not fit in a key: sort the factors themselves.
            self.velocity_factors_into(velocity);
            self.steering_factors_into(steering);
            return;
        }
        velocity.clear();
        steering.clear();
        // [COOP-OUT-ORDER.1] Velocity scenes, nearest first; ties by identifier.
        self.sort_keys(keys, |scene| match scene.geometry() {
            Geometry::Velocity { distance, .. } => Some(*distance),
            Geometry::Steering { .. } => None,
        });
        velocity.extend(
            keys.iter()
                .filter_map(|&key| self.keyed_scene(key))
                .filter_map(|(id, scene)| VelocityFactor::of(id, scene)),
        );
        // [COOP-OUT-ORDER.1] Steering scenes, nearest start first; ties by identifier.
        self.sort_keys(keys, |scene| match scene.geometry() {
            Geometry::Steering {
                distances: [start, _],
                ..
            } => Some(*start),
            Geometry::Velocity { .. } => None,
        });
        steering.extend(
            keys.iter()
                .filter_map(|&key| self.keyed_scene(key))
                .filter_map(|(id, scene)| SteeringFactor::of(id, scene)),
        );
    }

    /// Fills `keys` with one key for each live scene `distance` gives a distance for, sorted
    /// as `[COOP-OUT-ORDER.1]` orders the scenes. A key holds, from the most significant bits
    /// down: the distance's place in that order ([`Distance::order_key`]), the identifier's
    /// high 64 bits, the scene's position in the table. Sorting the keys therefore sorts by
    /// distance and then by identifier, except where two identifiers share their high half
    /// (almost never for random UUIDs): such runs are re-sorted by the whole identifier.
    ///
    /// Positions must fit in 32 bits; [`factors_into`](Self::factors_into) checks that first.
    fn sort_keys(&self, keys: &mut Vec<u128>, distance: impl Fn(&Scene) -> Option<Distance>) {
        keys.clear();
        for (position, (id, scene)) in self.scenes_in_any_order().enumerate() {
            let (Some(distance), Ok(position)) = (distance(scene), u32::try_from(position)) else {
                continue;
            };
            let high = id.to_u128() >> 64;
            keys.push(
                (u128::from(distance.order_key()) << 96) | (high << 32) | u128::from(position),
            );
        }
        keys.sort_unstable();
        let tie = |key: u128| key >> 32;
        if keys.windows(2).all(|pair| match pair {
            [a, b] => tie(*a) != tie(*b),
            _ => true,
        }) {
            return;
        }
        let mut start = 0;
        while start < keys.len() {
            let run_key = keys.get(start).copied().map(tie);
            let len = keys
                .iter()
                .skip(start)
                .take_while(|&&key| Some(tie(key)) == run_key)
                .count();
            if len > 1 {
                if let Some(run) = keys.get_mut(start..start + len) {
                    run.sort_unstable_by_key(|&key| self.keyed_scene(key).map(|(id, _)| id));
                }
            }
            start += len.max(1);
        }
    }

    /// The scene a key of [`sort_keys`](Self::sort_keys) names.
    fn keyed_scene(&self, key: u128) -> Option<(SceneId, &Scene)> {
        self.scene_at((key & u128::from(u32::MAX)) as usize)
    }
}

/// Caller-owned buffers for both factor lists, filled by [`State::factors_into`] and reused
/// cycle after cycle.
#[derive(Clone, Default, Debug)]
pub struct FactorLists {
    /// The velocity factors, nearest first (`[COOP-OUT-ORDER.1]`).
    pub velocity: Vec<VelocityFactor>,
    /// The steering factors, nearest start first (`[COOP-OUT-ORDER.1]`).
    pub steering: Vec<SteeringFactor>,
    /// Sort keys, kept only so that their memory is reused.
    keys: Vec<u128>,
}
