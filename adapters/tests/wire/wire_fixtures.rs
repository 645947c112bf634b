//! Fixtures shared by the wire tests: a configured state, scenes, and the JSON files.
#![allow(dead_code, unreachable_pub)]

use cooperation::*;
use cooperation_adapters::wire::{self, Service};

/// A whole AD API call from JSON to JSON, as a server makes it: the request read (or refused,
/// naming the field), answered from the state, and the response written.
pub trait CallJson {
    /// The response's JSON to the request's JSON.
    fn call_json(self, state: &mut State, json: &[u8]) -> Vec<u8>;
}

impl CallJson for Service {
    fn call_json(self, state: &mut State, json: &[u8]) -> Vec<u8> {
        let response = match self.read(json) {
            Ok(request) => request.answer(state).response,
            Err(malformed) => self.refusal(&malformed),
        };
        wire::to_json(&response)
    }
}

/// Lane change: optional by default.
pub const LANE_CHANGE: Module = Module::new(Behavior::LaneChange);
/// Avoidance (change): required by default.
pub const AVOIDANCE: Module = Module::with_sequence(Behavior::Avoidance, Sequence::Change);

/// The batch limit of [`state`].
pub const MAX_BATCH: usize = 4;

/// Scene A of the JSON files: `3f2a9c10-5b7e-4d21-9a0c-1e2f3a4b5c6d`, a lane change.
pub const A: SceneId = SceneId::from_u128(0x3f2a_9c10_5b7e_4d21_9a0c_1e2f_3a4b_5c6d);
/// Scene B of the JSON files: `8d4e2b71-0c3a-4f65-b817-29d0e6f4a3c2`, an avoidance.
pub const B: SceneId = SceneId::from_u128(0x8d4e_2b71_0c3a_4f65_b817_29d0_e6f4_a3c2);

/// Lane change optional, avoidance (change) required; at most [`MAX_BATCH`] per batch.
pub fn state() -> State {
    let mut config = Config::new([
        (LANE_CHANGE, Policy::Optional),
        (AVOIDANCE, Policy::Required),
    ]);
    config.limits.max_batch = MAX_BATCH;
    State::new(config).expect("valid configuration")
}

/// Registers a scene; the one place these tests build an owner's input.
pub fn register(
    state: &mut State,
    id: SceneId,
    module: Module,
    decision: Decision,
    geometry: Geometry,
) {
    let input = Input::Register {
        id,
        module,
        report: Report::new(decision, geometry),
    };
    state
        .apply(&input)
        .unwrap_or_else(|r| panic!("{input:?} rejected: {r}"));
}

/// Moves a live scene to `phase` by its owner's update, keeping its decision and geometry.
pub fn update(state: &mut State, id: SceneId, phase: Phase) {
    let scene = state.scene(id).expect("live").clone();
    let input = Input::Update {
        id,
        module: scene.module(),
        phase,
        report: Report::new(scene.module_decision(), *scene.geometry()),
    };
    state
        .apply(&input)
        .unwrap_or_else(|r| panic!("{input:?} rejected: {r}"));
}

/// [`state`] with scene A (lane change, module deactivates, a velocity scene 30 m ahead) and
/// scene B (avoidance/change, module activates, a steering section 12–40 m ahead, right).
pub fn with_scenes() -> State {
    let mut state = state();
    register(
        &mut state,
        A,
        LANE_CHANGE,
        Decision::Deactivate,
        Geometry::velocity(30.0),
    );
    register(
        &mut state,
        B,
        AVOIDANCE,
        Decision::Activate,
        Geometry::steering(Direction::Right, 12.0, 40.0),
    );
    state
}

/// The text of `adapters/tests/data/{name}`.
pub fn data(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// JSON text as a value, for comparisons that ignore layout.
pub fn json(text: &[u8]) -> serde_json::Value {
    serde_json::from_slice(text)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(text)))
}
