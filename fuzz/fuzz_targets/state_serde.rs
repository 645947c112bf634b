//! Hostile bytes as a `State` in its serde JSON form, then inputs applied to it. The bytes begin
//! with one JSON value, read as a `State`; what follows is a JSON array of inputs in their serde
//! form or, if it is not an array, bytes that each build an input over the state's own modules
//! and identifiers. Nothing may panic. A state that reads keeps its invariants, has limits that
//! `State::new` accepts, lost no entry of its lists (none was there twice), and writes JSON that
//! reads back to an equal state. Every input then leaves the invariants holding and a state that
//! reads back from its JSON; a rejected input leaves the state unchanged; and a copy laid out as
//! `TableLayout::Colliding` answers every input the same and stays equal.
#![no_main]

use cooperation::{
    Behavior, Command, Config, Decision, Detail, Direction, Geometry, Input, Module,
    OperatorDecision, Phase, Policy, PolicySetting, Report, SceneId, Sequence, State, TableLayout,
};
use libfuzzer_sys::fuzz_target;
use serde::de::IgnoredAny;
use serde::Deserialize;

/// The most inputs applied after the state is read.
const MAX_STEPS: usize = 64;

/// The serialized form's lists, entries unread: how many entries each was given.
#[derive(Deserialize)]
struct Lengths {
    #[allow(dead_code)]
    limits: IgnoredAny,
    policies: Vec<IgnoredAny>,
    scenes: Vec<IgnoredAny>,
    retired: Vec<IgnoredAny>,
    retired_order: Vec<IgnoredAny>,
}

fn lengths(json: &[u8]) -> Option<[usize; 4]> {
    let lists: Lengths = serde_json::from_slice(json).ok()?;
    Some([
        lists.policies.len(),
        lists.scenes.len(),
        lists.retired.len(),
        lists.retired_order.len(),
    ])
}

/// The state's JSON, checked to read back to the same state.
fn round_trip(state: &State) -> Vec<u8> {
    let Ok(json) = serde_json::to_vec(state) else {
        panic!("a state does not write")
    };
    match serde_json::from_slice::<State>(&json) {
        Ok(again) => assert_eq!(&again, state, "not a fixpoint"),
        Err(error) => panic!("written JSON does not read back: {error}"),
    }
    json
}

/// Bytes, one at a time.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn next(&mut self) -> Option<u8> {
        let (&byte, rest) = self.0.split_first()?;
        self.0 = rest;
        Some(byte)
    }
}

/// The item `byte` picks, or `None` from an empty list.
fn pick<T: Copy>(items: &[T], byte: u8) -> Option<T> {
    items.get(usize::from(byte) % items.len().max(1)).copied()
}

/// A scene identifier: mostly one the state knows (live or retired), else a small one.
fn id(state: &State, byte: u8) -> SceneId {
    let known: Vec<SceneId> = state
        .scenes()
        .map(|(id, _)| id)
        .chain(state.retired_oldest_first().map(|(id, _)| id))
        .collect();
    match pick(&known, byte) {
        Some(id) if byte < 0xc0 => id,
        _ => SceneId::from_u128(u128::from(byte & 0x0f)),
    }
}

/// A module: mostly one the state has a policy for, else any.
fn module(state: &State, byte: u8) -> Module {
    let configured: Vec<Module> = state.policies().map(|setting| setting.module).collect();
    match pick(&configured, byte >> 1) {
        Some(module) if byte & 1 == 0 => module,
        _ => Module::with_sequence(
            pick(&Behavior::ALL, byte >> 1).unwrap_or(Behavior::LaneChange),
            pick(&Sequence::ALL, byte).unwrap_or(Sequence::Empty),
        ),
    }
}

fn decision(byte: u8) -> Decision {
    pick(&Decision::ALL, byte).unwrap_or(Decision::Activate)
}

fn geometry(byte: u8) -> Geometry {
    let distance = f32::from(byte >> 2) - 8.0;
    if byte & 1 == 0 {
        Geometry::velocity(distance)
    } else {
        let directions = [
            Direction::Unknown,
            Direction::Left,
            Direction::Right,
            Direction::Straight,
        ];
        let direction = pick(&directions, byte >> 1).unwrap_or(Direction::Unknown);
        Geometry::steering(direction, distance, distance + 10.0)
    }
}

/// A detail from a byte: mostly none, else a text with characters JSON must escape.
fn detail(byte: u8) -> Detail {
    match byte % 4 {
        0 => Detail::new("waiting for the \"gap\"\n"),
        1 => Detail::new("é\u{1b}"),
        _ => Detail::EMPTY,
    }
}

/// The next input the bytes build, or `None` when they run out.
fn input(state: &State, bytes: &mut Bytes<'_>) -> Option<Input> {
    let op = bytes.next()?;
    let a = bytes.next()?;
    let b = bytes.next()?;
    Some(match op % 6 {
        0 => Input::Register {
            id: id(state, a),
            module: module(state, b),
            report: Report {
                decision: decision(op >> 3),
                requested: op & 0x80 != 0,
                geometry: geometry(bytes.next()?),
                detail: detail(a),
            },
        },
        1 => {
            let id = id(state, a);
            let module = match state.scene(id) {
                Some(scene) if b < 0xc0 => scene.module(),
                _ => module(state, b),
            };
            Input::Update {
                id,
                module,
                phase: pick(&Phase::ALL, op >> 3).unwrap_or(Phase::Running),
                report: Report {
                    decision: decision(op >> 6),
                    requested: op & 0x80 != 0,
                    geometry: geometry(bytes.next()?),
                    detail: detail(b),
                },
            }
        }
        2 => {
            let id = id(state, a);
            let module = match state.scene(id) {
                Some(scene) if b < 0xc0 => scene.module(),
                _ => module(state, b),
            };
            Input::Remove { id, module }
        }
        3 => {
            let mut commands = Vec::new();
            for _ in 0..a % 4 {
                let which = bytes.next()?;
                commands.push(Command {
                    id: id(state, which),
                    decision: pick(&OperatorDecision::ALL, b ^ (which >> 4))
                        .unwrap_or(OperatorDecision::Activate),
                });
            }
            Input::SetCommands { commands }
        }
        4 => {
            let mut policies = Vec::new();
            for _ in 0..a % 4 {
                let which = bytes.next()?;
                policies.push(PolicySetting {
                    module: module(state, which),
                    policy: pick(&Policy::ALL, which ^ b).unwrap_or(Policy::Required),
                });
            }
            Input::SetPolicies { policies }
        }
        _ => {
            let ttl_ms = state.limits().ttl_ms;
            let elapsed_ms = match a {
                255 => u64::MAX,
                254 => ttl_ms,
                253 => ttl_ms.saturating_add(1),
                _ => u64::from(a) * 100 + u64::from(b),
            };
            Input::Tick { elapsed_ms }
        }
    })
}

fuzz_target!(|data: &[u8]| {
    let mut stream = serde_json::Deserializer::from_slice(data).into_iter::<State>();
    let Some(Ok(mut state)) = stream.next() else {
        return;
    };
    let (text, rest) = data.split_at(stream.byte_offset());

    // What reads is a state the core could be in, under limits the core accepts, with every
    // entry it was given.
    assert_eq!(state.check_invariants(), Ok(()));
    let config = Config {
        policies: state.policies().map(|s| (s.module, s.policy)).collect(),
        limits: state.limits(),
    };
    assert!(
        State::new(config).is_ok(),
        "a state read with limits State::new refuses: {:?}",
        state.limits()
    );
    let json = round_trip(&state);
    assert_eq!(
        lengths(text),
        lengths(&json),
        "reading dropped entries given twice"
    );

    let mut twin = state.clone().with_table_layout(TableLayout::Colliding);
    match rest.trim_ascii_start() {
        array @ [b'[', ..] => {
            let Ok(inputs) = serde_json::from_slice::<Vec<Input>>(array) else {
                return;
            };
            for input in inputs.iter().take(MAX_STEPS) {
                step(&mut state, &mut twin, input);
            }
        }
        bytes => {
            // Built one at a time: each input picks among what the state holds before it.
            let mut bytes = Bytes(bytes);
            for _ in 0..MAX_STEPS {
                let Some(input) = input(&state, &mut bytes) else {
                    break;
                };
                step(&mut state, &mut twin, &input);
            }
        }
    }
});

/// Applies `input` to the state and its colliding twin, and checks what must hold after it.
fn step(state: &mut State, twin: &mut State, input: &Input) {
    let before = state.clone();
    let result = state.apply(input);
    if result.is_err() {
        assert_eq!(*state, before, "a rejection changed the state");
    }
    assert_eq!(
        twin.apply(input),
        result,
        "the table layout changed an answer"
    );
    assert_eq!(twin, state, "the table layout changed the state");
    assert_eq!(state.check_invariants(), Ok(()));
    round_trip(state);
}
