//! Hostile bytes into the AD API services, one call after another on one state: each
//! newline-separated chunk is a call, its first byte choosing `set_commands`, `set_policies`,
//! `get_policies`, or a core input in its serde form. No call may panic, every answer must be
//! JSON, a refused call or input (and `get_policies`, and an empty batch) must leave the state
//! unchanged, and the state must keep its invariants whatever was asked.
#![no_main]

use cooperation::{
    Behavior, Config, Decision, Detail, Geometry, Input, Limits, Module, Policy, Report, SceneId,
    State,
};
use cooperation_adapters::wire::{self, ResponseStatus, Service};
use libfuzzer_sys::fuzz_target;

fn start() -> State {
    let lane_change = Module::new(Behavior::LaneChange);
    let avoidance = Module::new(Behavior::Avoidance);
    let config = Config {
        policies: [
            (lane_change, Policy::Optional),
            (avoidance, Policy::Required),
        ]
        .into(),
        limits: Limits {
            ttl_ms: 1_000,
            max_scenes: 8,
            retired_capacity: 8,
            max_batch: 16,
        },
    };
    let Ok(mut state) = State::new(config) else {
        unreachable!("a valid configuration")
    };
    for n in 1..=3u128 {
        let register = Input::Register {
            id: SceneId::from_u128(n),
            module: if n % 2 == 0 { avoidance } else { lane_change },
            report: Report {
                requested: n == 3,
                ..Report::new(Decision::Activate, Geometry::velocity(n as f32))
                    .with_detail(Detail::new("why it waits"))
            },
        };
        assert!(state.apply(&register).is_ok());
    }
    state
}

fuzz_target!(|data: &[u8]| {
    let mut state = start();
    for chunk in data.split(|b| *b == b'\n') {
        let Some((&selector, body)) = chunk.split_first() else {
            continue;
        };
        match selector % 4 {
            3 => {
                if let Ok(input) = serde_json::from_slice::<Input>(body) {
                    let before = state.clone();
                    if state.apply(&input).is_err() {
                        assert_eq!(state, before, "a rejection changed the state");
                    }
                }
            }
            service => {
                let service = Service::ALL[usize::from(service)];
                let before = state.clone();
                // Read, answered (or refused), written: the server's path.
                let (response, changed) = match service.read(body) {
                    Ok(request) => {
                        let answer = request.answer(&mut state);
                        (answer.response, answer.changed)
                    }
                    Err(malformed) => (service.refusal(&malformed), false),
                };
                assert_eq!(
                    changed,
                    state != before,
                    "{service:?}: changed is what happened"
                );
                let response = wire::to_json(&response);
                let Ok(answer) = serde_json::from_slice::<serde_json::Value>(&response) else {
                    panic!("the answer is not JSON")
                };
                // A refused call, an empty batch (success with NO_EFFECT) and every
                // get_policies call leave the state exactly as it was.
                let status = &answer["status"];
                let changes_nothing = service == Service::GetPolicies
                    || status["success"] == false
                    || status["code"] == ResponseStatus::NO_EFFECT;
                if changes_nothing {
                    assert_eq!(
                        state, before,
                        "{service:?} answered {status} but changed the state"
                    );
                }
            }
        }
        assert_eq!(state.check_invariants(), Ok(()));
    }
});
