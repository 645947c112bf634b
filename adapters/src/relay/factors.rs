//! One factor stream (`[COOP-RELAY-FACTORS.1]`): the stack's own planning factors (Autoware's
//! `default_adapi`, whose outputs are remapped to [`VELOCITY_INPUT`] and [`STEERING_INPUT`]),
//! each matched to the RTC scene it is about, if any, and given that scene's cooperation status.
//!
//! A factor carries no scene identifier, so a scene's factor as the engine builds it (its
//! behaviour, direction and distances) is matched to the stack factor of the same behaviour (for
//! steering, the same direction) whose distance (for steering, the start distance) is nearest,
//! within [`MATCH_M`]; the nearest pairs are matched first, each factor to at most one scene.
//! A stack factor that carries a cooperation status already is left as it is. A scene matched
//! to none is published as the engine builds it. The factors come out nearest first, in the
//! order of distances of the core's factor lists (`[COOP-OUT-ORDER.1]`).
//!
//! ```
//! use cooperation_adapters::relay::factors;
//! use cooperation_adapters::wire::{CooperationStatus, VelocityFactor, VelocityFactorArray};
//!
//! let factor = |behavior: &str, distance| VelocityFactor {
//!     behavior: behavior.to_owned(),
//!     distance,
//!     ..VelocityFactor::default()
//! };
//! // default_adapi's: a crosswalk and an intersection stop.
//! let stack = VelocityFactorArray {
//!     factors: vec![factor("crosswalk", 12.0), factor("intersection", 30.4)],
//!     ..VelocityFactorArray::default()
//! };
//! // The engine's: the intersection's RTC scene, 30 m ahead.
//! let scene = VelocityFactor {
//!     cooperation: vec![CooperationStatus::default()],
//!     ..factor("intersection", 30.0)
//! };
//! let scenes = VelocityFactorArray { factors: vec![scene], ..VelocityFactorArray::default() };
//!
//! let merged = factors::velocity(Some(&stack), &scenes);
//! assert_eq!(merged.factors.len(), 2);
//! assert!(merged.factors[0].cooperation.is_empty()); // the crosswalk, as it came
//! assert_eq!(merged.factors[1].distance, 30.4); // the stack's factor …
//! assert_eq!(merged.factors[1].cooperation.len(), 1); // … with the scene's status
//! ```

use cooperation::Distance;

use crate::engine::{Now, Publication};
use crate::wire::{CooperationStatus, SteeringFactorArray, VelocityFactorArray};

/// The topic the stack's velocity factors are remapped to.
pub const VELOCITY_INPUT: &str = "/cooperation/input/velocity_factors";

/// The topic the stack's steering factors are remapped to.
pub const STEERING_INPUT: &str = "/cooperation/input/steering_factors";

/// How far apart, in metres, a stack factor's distance and a scene's may be for the two to be
/// matched.
pub const MATCH_M: f32 = 1.0;

/// How long a stack array is used after it came, in milliseconds: past it, the stack is taken
/// to have stopped publishing, and only the scenes' factors are published.
pub const INPUT_TTL_MS: u64 = 1_000;

/// What matching needs of a factor.
trait Factor: Clone {
    /// Behaviour and, for steering, direction: factors match only within one group.
    fn group(&self) -> (&str, u16);
    /// The distance that orders factors and matches them.
    fn distance(&self) -> f32;
    fn cooperation(&self) -> &Vec<CooperationStatus>;
    fn cooperation_mut(&mut self) -> &mut Vec<CooperationStatus>;
}

impl Factor for crate::wire::VelocityFactor {
    fn group(&self) -> (&str, u16) {
        (&self.behavior, 0)
    }
    fn distance(&self) -> f32 {
        self.distance
    }
    fn cooperation(&self) -> &Vec<CooperationStatus> {
        &self.cooperation
    }
    fn cooperation_mut(&mut self) -> &mut Vec<CooperationStatus> {
        &mut self.cooperation
    }
}

impl Factor for crate::wire::SteeringFactor {
    fn group(&self) -> (&str, u16) {
        (&self.behavior, self.direction)
    }
    fn distance(&self) -> f32 {
        self.distance[0]
    }
    fn cooperation(&self) -> &Vec<CooperationStatus> {
        &self.cooperation
    }
    fn cooperation_mut(&mut self) -> &mut Vec<CooperationStatus> {
        &mut self.cooperation
    }
}

/// `stack`'s factors, each given the cooperation status of the scene of `scenes` matched to it,
/// then the scenes matched to none; nearest first (`[COOP-OUT-ORDER.1]`'s order of distances).
fn merge<F: Factor>(stack: &[F], scenes: &[F]) -> Vec<F> {
    let mut pairs: Vec<(f32, usize, usize)> = Vec::new();
    for (s, scene) in scenes.iter().enumerate() {
        for (f, factor) in stack.iter().enumerate() {
            let gap = (factor.distance() - scene.distance()).abs();
            if factor.group() == scene.group() && factor.cooperation().is_empty() && gap <= MATCH_M
            {
                pairs.push((gap, s, f));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
    let mut merged: Vec<F> = stack.to_vec();
    let mut scene_matched = vec![false; scenes.len()];
    let mut factor_matched = vec![false; stack.len()];
    for (_, s, f) in pairs {
        let (Some(scene), Some(factor), Some(scene_done), Some(factor_done)) = (
            scenes.get(s),
            merged.get_mut(f),
            scene_matched.get_mut(s),
            factor_matched.get_mut(f),
        ) else {
            continue;
        };
        if *scene_done || *factor_done {
            continue;
        }
        factor.cooperation_mut().clone_from(scene.cooperation());
        *scene_done = true;
        *factor_done = true;
    }
    merged.extend(
        scenes
            .iter()
            .zip(&scene_matched)
            .filter(|(_, &matched)| !matched)
            .map(|(scene, _)| scene.clone()),
    );
    // Stable: equal distances keep the stack's order, then the scenes'.
    merged.sort_by(|a, b| Distance(a.distance()).total_cmp(&Distance(b.distance())));
    merged
}

/// The velocity factors to publish (`[COOP-RELAY-FACTORS.1]`): `stack`'s (if any) merged with
/// the scenes' (the engine's publication), under the scenes' header.
#[must_use]
pub fn velocity(
    stack: Option<&VelocityFactorArray>,
    scenes: &VelocityFactorArray,
) -> VelocityFactorArray {
    VelocityFactorArray {
        header: scenes.header.clone(),
        factors: merge(stack.map_or(&[][..], |s| &s.factors), &scenes.factors),
    }
}

/// The steering factors to publish (`[COOP-RELAY-FACTORS.1]`): `stack`'s (if any) merged with
/// the scenes' (the engine's publication), under the scenes' header.
#[must_use]
pub fn steering(
    stack: Option<&SteeringFactorArray>,
    scenes: &SteeringFactorArray,
) -> SteeringFactorArray {
    SteeringFactorArray {
        header: scenes.header.clone(),
        factors: merge(stack.map_or(&[][..], |s| &s.factors), &scenes.factors),
    }
}

/// The one factor stream as a host publishes it (`[COOP-RELAY-FACTORS.1]`): the stack's newest
/// arrays, each with the reading it came at, and the engine's newest publication. It says what
/// to publish and when: whenever either side changed, and when an array the last publication
/// used grows older than [`INPUT_TTL_MS`]. The host reads the topics and the clock, and writes
/// what [`poll`](Self::poll) gives.
///
/// ```
/// use cooperation_adapters::engine::{Now, Publication};
/// use cooperation_adapters::relay::factors::{Stream, INPUT_TTL_MS};
/// use cooperation_adapters::wire::{VelocityFactor, VelocityFactorArray};
/// use cooperation_adapters::Time;
///
/// let at = |ms: i64| Now::new(ms * 1_000_000, Time::default());
/// let mut stream = Stream::default();
/// stream.take_scenes(Publication::default());
/// let stack = VelocityFactorArray {
///     factors: vec![VelocityFactor { behavior: "crosswalk".into(), ..Default::default() }],
///     ..Default::default()
/// };
/// stream.take_velocity(stack, at(0));
/// assert_eq!(stream.poll(at(0)).expect("due").velocity.factors.len(), 1);
/// assert!(stream.poll(at(10)).is_none(), "nothing changed");
/// // The stack stopped publishing: past the time to live, its factor goes.
/// assert_eq!(stream.until_stale_ms(at(10)), INPUT_TTL_MS - 10 + 1);
/// let lapsed = stream.poll(at(1_000 + 1)).expect("due");
/// assert!(lapsed.velocity.factors.is_empty());
/// ```
#[derive(Clone, Debug, Default)]
pub struct Stream {
    /// The stack's newest velocity array, and the reading it came at (ns).
    velocity: Option<(VelocityFactorArray, i64)>,
    /// The stack's newest steering array, and the reading it came at (ns).
    steering: Option<(SteeringFactorArray, i64)>,
    /// The engine's newest publication.
    scenes: Option<Publication>,
    /// A side changed since the last publication.
    changed: bool,
    /// Whether the last publication used the stack's velocity and steering arrays.
    used: (bool, bool),
}

/// [`INPUT_TTL_MS`] in nanoseconds.
const INPUT_TTL_NS: i64 = 1_000_000 * INPUT_TTL_MS as i64;

/// How old, in nanoseconds, something that came at `came` is `now` (none for a clock that went
/// back).
fn age_ns(came: i64, now: Now) -> i64 {
    now.reading_ns.saturating_sub(came).max(0)
}

/// The array of `input`, if it is not older than [`INPUT_TTL_MS`].
fn fresh<T>(input: Option<&(T, i64)>, now: Now) -> Option<&T> {
    input
        .filter(|(_, came)| age_ns(*came, now) <= INPUT_TTL_NS)
        .map(|(array, _)| array)
}

impl Stream {
    /// The stack's newest velocity array came, `now`.
    pub fn take_velocity(&mut self, array: VelocityFactorArray, now: Now) {
        self.velocity = Some((array, now.reading_ns));
        self.changed = true;
    }

    /// The stack's newest steering array came, `now`.
    pub fn take_steering(&mut self, array: SteeringFactorArray, now: Now) {
        self.steering = Some((array, now.reading_ns));
        self.changed = true;
    }

    /// The engine published (`Engine::poll_publication`): the scenes' factors and statuses.
    pub fn take_scenes(&mut self, publication: Publication) {
        self.scenes = Some(publication);
        self.changed = true;
    }

    /// What to publish `now`, if anything: the stack's fresh arrays merged with the scenes'
    /// ([`velocity`], [`steering`]), under the engine's revision, when a side changed or an
    /// array the last publication used went stale. Nothing before the engine's first
    /// publication.
    pub fn poll(&mut self, now: Now) -> Option<Publication> {
        let scenes = self.scenes.as_ref()?;
        let velocity = fresh(self.velocity.as_ref(), now);
        let steering = fresh(self.steering.as_ref(), now);
        let lapsed = (self.used.0 && velocity.is_none()) || (self.used.1 && steering.is_none());
        if !(self.changed || lapsed) {
            return None;
        }
        let publication = Publication {
            revision: scenes.revision,
            velocity: self::velocity(velocity, &scenes.velocity),
            steering: self::steering(steering, &scenes.steering),
            scenes: scenes.scenes.clone(),
        };
        self.used = (velocity.is_some(), steering.is_some());
        self.changed = false;
        Some(publication)
    }

    /// How long from `now` until an array the last publication used goes stale, in
    /// milliseconds: the time left of [`INPUT_TTL_MS`] rounded up, and one more (an array is
    /// stale once older than that). The longest a host may wait before it polls again;
    /// `u64::MAX` if the last publication used none.
    #[must_use]
    pub fn until_stale_ms(&self, now: Now) -> u64 {
        let until = |input: Option<i64>| {
            input.map_or(u64::MAX, |came| {
                let left = INPUT_TTL_NS.saturating_sub(age_ns(came, now)).max(0);
                u64::try_from(left).unwrap_or(0).div_ceil(1_000_000) + 1
            })
        };
        let velocity = self.velocity.as_ref().filter(|_| self.used.0);
        let steering = self.steering.as_ref().filter(|_| self.used.1);
        until(velocity.map(|(_, came)| *came)).min(until(steering.map(|(_, came)| *came)))
    }
}
