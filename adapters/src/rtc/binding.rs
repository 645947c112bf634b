//! Bindings: which core modules, and which kind of factor, an RTC interface name stands for.

use std::collections::BTreeSet;

use cooperation::{
    Behavior, Direction, Distance, Geometry, Module, Pose, Sequence, SteeringStatus, VelocityStatus,
};

use super::ModuleType;

/// How an interface's scenes are reported in the AD API: as velocity factors (stop or pass) or
/// as steering factors turning one way (change the path or keep it).
#[derive(
    Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, serde::Serialize, serde::Deserialize,
)]
pub enum Kind {
    /// A velocity scene: the start distance is the distance to the stop.
    Velocity,
    /// A steering scene turning this way: the start and finish distances bound its section.
    Steering(Direction),
}

/// One RTC interface: its name (the last element of its topics and services), the module type
/// its statuses carry, the core modules its scenes may belong to (a behaviour and one or more
/// of its sequences), and their kind.
///
/// Most interfaces have one module. An interface whose scenes are parts of one behaviour that
/// the AD API keys apart binds several sequences: `static_obstacle_avoidance_left` binds
/// `avoidance/change` (the shift out) and `avoidance/return` (the shift back), and its owner
/// states each scene's sequence when it registers it (`[COOP-DEV-SEQUENCE.1]`). A scene's
/// module never changes.
///
/// Several interfaces may share a core module (`lane_change_left` and `lane_change_right` are
/// both `lane-change`); they then share its policy (`[COOP-DEV-AUTO-MODE-KEY.1]`) but not their
/// scenes.
#[derive(
    Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, serde::Serialize, serde::Deserialize,
)]
#[serde(deny_unknown_fields)]
pub struct Binding {
    /// The interface name, for example `lane_change_left`.
    pub name: String,
    /// The module type its statuses and auto-mode status carry.
    pub module_type: ModuleType,
    /// The behaviour its scenes belong to.
    pub behavior: Behavior,
    /// The sequences its scenes may have: each is one core module, `behavior` with it. At least
    /// one ([`Rtc::new`](super::Rtc::new) refuses a binding with none, `RtcError::NoSequence`).
    pub sequences: BTreeSet<Sequence>,
    /// How its scenes are reported.
    pub kind: Kind,
}

impl Binding {
    /// A binding of one module: every scene of the interface belongs to `module`.
    pub fn new(
        name: impl Into<String>,
        module_type: ModuleType,
        module: Module,
        kind: Kind,
    ) -> Self {
        Self {
            name: name.into(),
            module_type,
            behavior: module.behavior,
            sequences: BTreeSet::from([module.sequence]),
            kind,
        }
    }

    /// The same binding, its scenes having any of `sequences` (in place of the ones it had), for
    /// example `[Sequence::Change, Sequence::Return]` for an avoidance.
    #[must_use]
    pub fn with_sequences(mut self, sequences: impl IntoIterator<Item = Sequence>) -> Self {
        self.sequences = sequences.into_iter().collect();
        self
    }

    /// The core modules its scenes may belong to, in module order.
    pub fn modules(&self) -> impl Iterator<Item = Module> + '_ {
        self.sequences
            .iter()
            .map(|sequence| Module::with_sequence(self.behavior, *sequence))
    }

    /// The core module of its scenes of `sequence`, if it binds that sequence.
    #[must_use]
    pub fn module(&self, sequence: Sequence) -> Option<Module> {
        self.sequences
            .contains(&sequence)
            .then_some(Module::with_sequence(self.behavior, sequence))
    }

    /// Its one module, if it binds exactly one sequence: the module of a new scene whose owner
    /// states no sequence.
    #[must_use]
    pub fn only_module(&self) -> Option<Module> {
        match (self.sequences.first(), self.sequences.len()) {
            (Some(sequence), 1) => Some(Module::with_sequence(self.behavior, *sequence)),
            _ => None,
        }
    }

    /// The bindings of every interface name the planners use, with the behaviour names of the
    /// AD API's planning factors:
    ///
    /// | Interface | Module type | Behaviour | Sequences | Kind |
    /// |---|---|---|---|---|
    /// | `lane_change_left`, `_right` | `LANE_CHANGE_LEFT`, `_RIGHT` | `lane-change` | empty | steering left, right |
    /// | `external_request_lane_change_left`, `_right` | `EXT_REQUEST_LANE_CHANGE_LEFT`, `_RIGHT` | `lane-change` | empty | steering left, right |
    /// | `avoidance_by_lane_change_left`, `_right` | `AVOIDANCE_BY_LC_LEFT`, `_RIGHT` | `lane-change` | empty | steering left, right |
    /// | `static_obstacle_avoidance_left`, `_right` | `AVOIDANCE_LEFT`, `_RIGHT` | `avoidance` | `change`, `return` | steering left, right |
    /// | `goal_planner` | `GOAL_PLANNER` | `goal-planner` | empty | steering, direction unknown |
    /// | `start_planner` | `START_PLANNER` | `start-planner` | empty | steering, direction unknown |
    /// | `intersection`, `intersection_occlusion` | `INTERSECTION`, `INTERSECTION_OCCLUSION` | `intersection` | empty | velocity |
    /// | `crosswalk` | `CROSSWALK` | `crosswalk` | empty | velocity |
    /// | `blind_spot` | `BLIND_SPOT` | `rear-check` | empty | velocity |
    /// | `traffic_light` | `TRAFFIC_LIGHT` | `traffic-signal` | empty | velocity |
    /// | `virtual_traffic_light` | `TRAFFIC_LIGHT` | `virtual-traffic-light` | empty | velocity |
    /// | `detection_area` | `DETECTION_AREA` | `user-defined-attention-area` | empty | velocity |
    /// | `no_stopping_area` | `NO_STOPPING_AREA` | `no-stopping-area` | empty | velocity |
    /// | `roundabout` | `ROUNDABOUT` | `roundabout` | empty | velocity |
    ///
    /// An RTC status cannot say whether an avoidance shifts out or returns, but the module that
    /// owns the interface knows it for each scene (one per shift line), so the avoidance
    /// interfaces bind both sequences and their owner states each scene's
    /// (`StatusReport::in_sequence`, `[COOP-DEV-SEQUENCE.1]`); `avoidance/change` and
    /// `avoidance/return` then have policies of their own. `occlusion_spot` has no AD API
    /// behaviour and `stop_line` no RTC scenes; bind them yourself if you need them.
    #[must_use]
    pub fn standard() -> Vec<Self> {
        use Behavior as B;
        use Direction::{Left, Right, Unknown};
        use Kind::{Steering, Velocity};
        use ModuleType as T;
        let rows = [
            (
                "lane_change_left",
                T::LaneChangeLeft,
                B::LaneChange,
                Steering(Left),
            ),
            (
                "lane_change_right",
                T::LaneChangeRight,
                B::LaneChange,
                Steering(Right),
            ),
            (
                "external_request_lane_change_left",
                T::ExtRequestLaneChangeLeft,
                B::LaneChange,
                Steering(Left),
            ),
            (
                "external_request_lane_change_right",
                T::ExtRequestLaneChangeRight,
                B::LaneChange,
                Steering(Right),
            ),
            (
                "avoidance_by_lane_change_left",
                T::AvoidanceByLcLeft,
                B::LaneChange,
                Steering(Left),
            ),
            (
                "avoidance_by_lane_change_right",
                T::AvoidanceByLcRight,
                B::LaneChange,
                Steering(Right),
            ),
            (
                "static_obstacle_avoidance_left",
                T::AvoidanceLeft,
                B::Avoidance,
                Steering(Left),
            ),
            (
                "static_obstacle_avoidance_right",
                T::AvoidanceRight,
                B::Avoidance,
                Steering(Right),
            ),
            (
                "goal_planner",
                T::GoalPlanner,
                B::GoalPlanner,
                Steering(Unknown),
            ),
            (
                "start_planner",
                T::StartPlanner,
                B::StartPlanner,
                Steering(Unknown),
            ),
            ("intersection", T::Intersection, B::Intersection, Velocity),
            (
                "intersection_occlusion",
                T::IntersectionOcclusion,
                B::Intersection,
                Velocity,
            ),
            ("crosswalk", T::Crosswalk, B::Crosswalk, Velocity),
            ("blind_spot", T::BlindSpot, B::RearCheck, Velocity),
            ("traffic_light", T::TrafficLight, B::TrafficSignal, Velocity),
            (
                "virtual_traffic_light",
                T::TrafficLight,
                B::VirtualTrafficLight,
                Velocity,
            ),
            (
                "detection_area",
                T::DetectionArea,
                B::UserDefinedAttentionArea,
                Velocity,
            ),
            (
                "no_stopping_area",
                T::NoStoppingArea,
                B::NoStoppingArea,
                Velocity,
            ),
            ("roundabout", T::Roundabout, B::Roundabout, Velocity),
        ];
        rows.into_iter()
            .map(|(name, module_type, behavior, kind)| {
                let binding = Self::new(name, module_type, Module::new(behavior), kind);
                // [COOP-DEV-SEQUENCE.1]
                if behavior == B::Avoidance {
                    binding.with_sequences([Sequence::Change, Sequence::Return])
                } else {
                    binding
                }
            })
            .collect()
    }

    /// The core geometry for a status's distances: identity poses (RTC has none), status unknown
    /// (RTC does not say whether the vehicle has stopped or is turning).
    pub(crate) fn geometry(&self, start_distance: f32, finish_distance: f32) -> Geometry {
        match self.kind {
            Kind::Velocity => Geometry::Velocity {
                pose: Pose::IDENTITY,
                distance: Distance(start_distance),
                status: VelocityStatus::Unknown,
            },
            Kind::Steering(direction) => Geometry::Steering {
                poses: [Pose::IDENTITY; 2],
                distances: [Distance(start_distance), Distance(finish_distance)],
                direction,
                status: SteeringStatus::Unknown,
            },
        }
    }
}

/// A geometry's start and finish distances; a velocity scene has one distance, reported as both.
pub(crate) const fn distances(geometry: &Geometry) -> (f32, f32) {
    match geometry {
        Geometry::Velocity { distance, .. } => (distance.0, distance.0),
        Geometry::Steering {
            distances: [start, finish],
            ..
        } => (start.0, finish.0),
    }
}
