//! Geometry: payload carried for the factor outputs that no rule reads.
//!
//! Floating-point values compare and hash by their bit patterns, so that the state that holds
//! them stays `Eq + Hash`: `0.0` and `-0.0` differ, and a NaN equals the same NaN.

use core::cmp::Ordering;
use core::hash::{Hash, Hasher};

#[cfg(feature = "serde")]
mod exact;

/// A pose in the map frame: a position and an orientation quaternion (`geometry_msgs/Pose`).
///
/// With the `serde` feature its coordinates are written as [`Distance`] says, exactly for
/// every bit pattern (`"NaN:0x"` and 16 hexadecimal digits for a NaN).
///
/// The default pose is [`Pose::IDENTITY`]: at the origin, facing along `x`, with the unit
/// quaternion `w = 1` (an all-zero quaternion is no rotation at all).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Pose {
    /// `x`, `y`, `z` in metres.
    #[cfg_attr(feature = "serde", serde(with = "exact::array"))]
    pub position: [f64; 3],
    /// `x`, `y`, `z`, `w`.
    #[cfg_attr(feature = "serde", serde(with = "exact::array"))]
    pub orientation: [f64; 4],
}

impl Pose {
    /// At the origin, with the identity orientation (`x = y = z = 0`, `w = 1`).
    pub const IDENTITY: Self = Self {
        position: [0.0; 3],
        orientation: [0.0, 0.0, 0.0, 1.0],
    };

    fn bits(&self) -> [u64; 7] {
        let [x, y, z] = self.position;
        let [qx, qy, qz, qw] = self.orientation;
        [x, y, z, qx, qy, qz, qw].map(f64::to_bits)
    }
}

impl Default for Pose {
    /// [`Pose::IDENTITY`].
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl PartialEq for Pose {
    fn eq(&self, other: &Self) -> bool {
        // Every bit compared at once, without a call to `memcmp`: scenes are compared in every
        // step a model checker takes.
        let (a, b) = (self.bits(), other.bits());
        a.iter().zip(b).fold(0, |differ, (a, b)| differ | (a ^ b)) == 0
    }
}

impl Eq for Pose {}

impl Hash for Pose {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.bits().hash(state);
    }
}

impl PartialOrd for Pose {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Pose {
    /// Component by component in IEEE 754 total order: consistent with equality.
    fn cmp(&self, other: &Self) -> Ordering {
        let pairs = self
            .position
            .iter()
            .chain(&self.orientation)
            .zip(other.position.iter().chain(&other.orientation));
        pairs
            .map(|(a, b)| a.total_cmp(b))
            .find(|o| o.is_ne())
            .unwrap_or(Ordering::Equal)
    }
}

/// A distance along the path in metres (`float32` on the wire). Compares by bit pattern.
///
/// With the `serde` feature, a finite distance is a number and a non-finite one a string
/// (`"inf"`, `"-inf"`, `"NaN:0x7fc00000"`: the NaN's bits), so that every distance is read
/// back exactly; a number beyond the range of `f32` is refused.
#[derive(Clone, Copy, Debug, Default)]
pub struct Distance(pub f32);

#[cfg(feature = "serde")]
impl serde::Serialize for Distance {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serde::Serialize::serialize(&exact::Exact(self.0), serializer)
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Distance {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        <exact::Exact<f32> as serde::Deserialize>::deserialize(deserializer).map(|e| Self(e.0))
    }
}

impl PartialEq for Distance {
    fn eq(&self, other: &Self) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}

impl Eq for Distance {}

impl Hash for Distance {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.to_bits().hash(state);
    }
}

impl Distance {
    /// The factor lists' order of distances (`[COOP-OUT-ORDER.1]`), a total order; the same as
    /// `Ord`. Ascending, `-inf` first, `-0.0` before `0.0`, and every NaN, of either sign, after
    /// every number: positive NaNs, then negative ones, each in IEEE 754 total order. That is
    /// `f32::total_cmp` with the negative NaNs, which it puts first, moved to the end.
    #[must_use]
    pub fn total_cmp(&self, other: &Self) -> Ordering {
        self.order_key().cmp(&other.order_key())
    }

    /// The distance's place in [`total_cmp`](Self::total_cmp)'s order, as an unsigned number:
    /// one key for each bit pattern, so keys compare as the distances do.
    #[must_use]
    pub(crate) fn order_key(self) -> u32 {
        /// How many keys IEEE 754 total order gives the negative NaNs, ahead of `-inf`.
        const NEGATIVE_NANS: u32 = (1 << 23) - 1;
        let bits = self.0.to_bits();
        // IEEE 754 total order: `-NaN`, `-inf`, …, `-0.0`, `0.0`, …, `inf`, `NaN`.
        let total = if bits >> 31 == 1 {
            !bits
        } else {
            bits | (1 << 31)
        };
        // Turned so that `-inf` is 0 and the negative NaNs follow the positive ones at the top.
        total.wrapping_sub(NEGATIVE_NANS)
    }
}

impl PartialOrd for Distance {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Distance {
    /// [`Distance::total_cmp`] (`-0.0 < 0.0`, NaN of either sign last): consistent with
    /// equality.
    fn cmp(&self, other: &Self) -> Ordering {
        self.total_cmp(other)
    }
}

/// What a velocity factor is doing (AD API `VelocityFactor.status`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum VelocityStatus {
    /// Not known.
    #[default]
    Unknown,
    /// The vehicle is approaching the factor.
    Approaching,
    /// The vehicle has stopped because of the factor.
    Stopped,
}

/// What a steering factor is doing (AD API `SteeringFactor.status`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum SteeringStatus {
    /// Not known.
    #[default]
    Unknown,
    /// The vehicle is approaching the steering section.
    Approaching,
    /// The vehicle is in the steering section.
    Turning,
}

/// Which way a steering scene turns (AD API `SteeringFactor.direction`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Direction {
    /// Not known.
    #[default]
    Unknown,
    /// To the left.
    Left,
    /// To the right.
    Right,
    /// Straight on.
    Straight,
}

/// Whether a scene is reported as a velocity factor or as a steering factor.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum FactorKind {
    /// A scene that decides whether to stop or pass.
    Velocity,
    /// A scene that decides whether to change the path.
    Steering,
}

impl core::fmt::Display for FactorKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::Velocity => "velocity",
            Self::Steering => "steering",
        })
    }
}

/// A scene's geometry, by kind. The kind is fixed at registration (spec `[COOP-OWN-KIND.1]`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub enum Geometry {
    /// A velocity scene: where it is and how far ahead.
    Velocity {
        /// Where the vehicle would stop or slow down.
        pose: Pose,
        /// How far ahead that is.
        distance: Distance,
        /// What the vehicle is doing about it.
        status: VelocityStatus,
    },
    /// A steering scene: where its section starts and ends.
    Steering {
        /// Start and end of the steering section.
        poses: [Pose; 2],
        /// Distances to the start and to the end.
        distances: [Distance; 2],
        /// Which way it turns.
        direction: Direction,
        /// What the vehicle is doing about it.
        status: SteeringStatus,
    },
}

impl Geometry {
    /// A velocity geometry at [`Pose::IDENTITY`] with the given distance.
    #[must_use]
    pub fn velocity(distance: f32) -> Self {
        Self::Velocity {
            pose: Pose::IDENTITY,
            distance: Distance(distance),
            status: VelocityStatus::Approaching,
        }
    }

    /// A steering geometry, both poses [`Pose::IDENTITY`], starting and ending at the given
    /// distances.
    #[must_use]
    pub fn steering(direction: Direction, start: f32, end: f32) -> Self {
        Self::Steering {
            poses: [Pose::IDENTITY; 2],
            distances: [Distance(start), Distance(end)],
            direction,
            status: SteeringStatus::Approaching,
        }
    }

    /// The kind of factor this geometry reports.
    #[must_use]
    pub const fn kind(&self) -> FactorKind {
        match self {
            Self::Velocity { .. } => FactorKind::Velocity,
            Self::Steering { .. } => FactorKind::Steering,
        }
    }

    /// The distance the factor lists are ordered by: to the stop, or to the section's start.
    #[must_use]
    pub const fn sort_distance(&self) -> Distance {
        match self {
            Self::Velocity { distance, .. } => *distance,
            Self::Steering {
                distances: [start, _],
                ..
            } => *start,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The keys at the seams of the order: `-inf` first, `inf` below every NaN, positive NaNs
    /// below negative ones, and each bit pattern its own key.
    #[test]
    fn order_keys_put_every_nan_last() {
        let key = |bits: u32| Distance(f32::from_bits(bits)).order_key();
        assert_eq!(Distance(f32::NEG_INFINITY).order_key(), 0);
        assert!(key(0x8000_0000) < key(0)); // -0.0 before 0.0
        assert!(Distance(f32::INFINITY).order_key() < key(0x7f80_0001)); // inf before NaN
        assert_eq!(key(0x7f80_0001), Distance(f32::INFINITY).order_key() + 1);
        assert!(key(0x7fff_ffff) < key(0xffff_ffff)); // positive NaNs before negative ones
        assert_eq!(key(0x7fff_ffff) + 1, key(0xffff_ffff));
        assert_eq!(key(0xff80_0001), u32::MAX);
        assert!(key(0xffc0_0000) < key(0xff80_0001));
    }

    #[test]
    fn floats_compare_by_bits() {
        assert_ne!(Distance(0.0), Distance(-0.0));
        assert_eq!(Distance(f32::NAN), Distance(f32::NAN));
        let mut pose = Pose::default();
        assert_eq!(pose, Pose::default());
        pose.position[0] = -0.0;
        assert_ne!(pose, Pose::default());
    }

    /// A pose nobody set faces along `x`: its quaternion is the unit one, so a factor published
    /// from it carries `w = 1`.
    #[test]
    fn the_default_pose_is_the_identity() {
        assert_eq!(Pose::default().orientation, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(Pose::default().position, [0.0; 3]);
        let Geometry::Steering { poses, .. } = Geometry::steering(Direction::Left, 1.0, 2.0) else {
            panic!("a steering geometry")
        };
        assert_eq!(poses, [Pose::IDENTITY; 2]);
    }
}
