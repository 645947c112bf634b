//! The engine model's state: the engine, the clock, and the history the properties read; and
//! what the streams carry of a core, short of stamps and ages.

use std::hash::{Hash, Hasher};

use cooperation::{SceneId, State};
use cooperation_adapters::engine::{self, Engine, Now};
use cooperation_adapters::{cdr, wire, Time};
use stateright::Representative;

/// A state of the engine model.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EngineStep {
    /// The engine.
    pub engine: Engine,
    /// The clock's reading, in milliseconds.
    pub clock_ms: u64,
    /// When each identifier's scene was last reported, accepted, until it was removed (history
    /// annotation).
    pub reported_ms: Vec<Option<u64>>,
    /// The latest reading the core should have been told of, by the rule's own count (history
    /// annotation): every call but a publication poll tells the core its reading.
    pub read_ms: u64,
    /// The core's time by the rule's own count: each step from [`read_ms`](Self::read_ms) counts
    /// at most the step limit (`[COOP-ENGINE-STEP.1]`; history annotation).
    pub core_ms: u64,
    /// [`reported_ms`](Self::reported_ms) in the core's time ([`core_ms`](Self::core_ms)).
    pub reported_core_ms: Vec<Option<u64>>,
    /// What the last publication carried ([`content`]); `None` before the first.
    pub published: Option<Vec<u8>>,
    /// The clock's reading at the last publication (history annotation); `None` before the
    /// first. Hashed only where the clock can go back: on a clock that moves forward, the
    /// engine's time left until the next publication, which is hashed, tells as much of it
    /// as the properties read.
    pub published_at_ms: Option<u64>,
    /// The clock has gone back ([`EngineBounds::rewinds`](super::EngineBounds::rewinds)).
    pub went_back: bool,
    /// The clock can go back ([`EngineBounds::rewinds`](super::EngineBounds::rewinds); the same in every state of a run).
    pub rewinds: bool,
    /// Sticky flags of broken step properties ([`broken`](super::broken)).
    pub broken: u8,
}

impl Hash for EngineStep {
    /// Everything but the engine's revision counter, which only labels publications and grows
    /// with every change: two states that differ in it alone behave alike.
    fn hash<H: Hasher>(&self, state: &mut H) {
        let engine = &self.engine;
        engine.state().hash(state);
        // Each identifier's route: the model's retired capacity covers every identifier, so the
        // core forgets none and the routes are exactly these.
        for n in 1..=4u128 {
            let id = SceneId::from_u128(n);
            let owner = engine.host().rtc().owner(engine.state(), id);
            owner.map(|binding| binding.name.as_str()).hash(state);
        }
        engine.host().told_ms().hash(state);
        engine.told(Time::default()).reading_ns.hash(state);
        engine.until_publication_ms(self.now()).hash(state);
        engine.publication_due(self.now()).hash(state);
        // On a clock that only moves forward, the time left until the next periodic
        // publication at the reading now decides every later one. On a clock that can go back,
        // two last publications can leave the same time left now and differ once the clock
        // reads earlier than one of them: the reading itself is hashed, and whether a change
        // waits to be published.
        if let (true, Some(published_ms)) = (self.rewinds, engine.last_publication_ms()) {
            published_ms.hash(state);
            self.published_at_ms.hash(state);
            // Whether a change waits to be published, which no reading's time left tells
            // apart from an interval run out once the clock can go back: asked at the last
            // publication's own reading, the interval has not run.
            let at = now_at(u64::try_from(published_ms).unwrap_or(0));
            engine.publication_due(at).hash(state);
        }
        self.clock_ms.hash(state);
        self.reported_ms.hash(state);
        self.read_ms.hash(state);
        self.core_ms.hash(state);
        self.reported_core_ms.hash(state);
        self.published.hash(state);
        self.went_back.hash(state);
        self.broken.hash(state);
    }
}

impl Representative for EngineStep {
    /// No reduction.
    fn representative(&self) -> Self {
        self.clone()
    }
}

impl EngineStep {
    /// The clock's reading as the engine takes it.
    #[must_use]
    pub fn now(&self) -> Now {
        now_at(self.clock_ms)
    }
}

/// The reading of `ms`, its stamp that many milliseconds after the epoch.
#[must_use]
pub fn now_at(ms: u64) -> Now {
    let ns = i64::try_from(ms)
        .unwrap_or(i64::MAX)
        .saturating_mul(1_000_000);
    Now::new(
        ns,
        Time::new(
            i32::try_from(ms / 1000).unwrap_or(i32::MAX),
            u32::try_from((ms % 1000) * 1_000_000).unwrap_or(0),
        ),
    )
}

/// What the streams carry of `state`, short of stamps and ages: the two factor lists and the
/// scenes, in CDR, the encoding the DDS door writes messages in (each number as its bits:
/// cheaper to write than JSON, whose numbers are printed).
#[must_use]
pub fn content(state: &State) -> Vec<u8> {
    let stamp = Time::default();
    let mut scenes = engine::scenes::scene_array(state, stamp);
    for scene in &mut scenes.scenes {
        scene.age_ms = 0;
    }
    let mut bytes = cdr::to_vec(&wire::velocity_factors(state, stamp).factors).unwrap_or_default();
    bytes.extend(cdr::to_vec(&wire::steering_factors(state, stamp).factors).unwrap_or_default());
    bytes.extend(cdr::to_vec(&scenes.scenes).unwrap_or_default());
    bytes
}
