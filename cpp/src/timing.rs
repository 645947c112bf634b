//! The benchmark's Rust baseline (`cpp/bench/calls.cpp`, `docs/performance-cpp.md`): the
//! calls the C++ class makes, timed here on the Rust side of the bridge, so that one run
//! compares the same work with and without the C++ boundary.

use std::hint::black_box;
use std::time::Instant;

use crate::bridge::ffi::{CallCost, CommandIn, Stamp, Uuid};
use crate::calls::{self, Core};

/// The interface the benchmark reports through.
const NAME: &str = "intersection";
/// The node's clock as the benchmark's C++ side reads it: standing still.
const ZERO: Stamp = Stamp { sec: 0, nanosec: 0 };

fn scene(index: usize) -> Uuid {
    let mut bytes = [0_u8; 16];
    bytes[8..].copy_from_slice(&(index as u64 + 1).to_be_bytes());
    Uuid { bytes }
}

fn cost(method: &str, rounds: usize, mut call: impl FnMut(usize)) -> CallCost {
    let rounds = rounds.max(1);
    let started = Instant::now();
    for round in 0..rounds {
        call(round);
    }
    #[allow(clippy::cast_precision_loss)] // A mean, for a report.
    let nanos = started.elapsed().as_nanos() as f64 / rounds as f64;
    CallCost {
        method: method.to_owned(),
        nanos,
    }
}

/// Each call of the C++ class's hot path with `scenes` live scenes in one interface, `rounds`
/// times, cycling over the scenes; the mean nanoseconds per call. Then a planning cycle as
/// upstream's velocity planner makes it, `rounds / scenes` times: `isActivated` and
/// `isRTCEnabled` of every scene, `updateCooperateStatus` of every scene, the expired removed
/// and the statuses published; the mean nanoseconds per cycle. Empty if the core cannot be
/// built (it always can with the standard bindings).
#[must_use]
pub fn time_rust_calls(scenes: usize, rounds: usize) -> Vec<CallCost> {
    let Ok(core) = Core::new(0) else {
        return Vec::new();
    };
    let handle = calls::find(&core, NAME);
    let _ = calls::bind(&core, &handle, false);
    let scenes = scenes.max(1);
    let ids: Vec<Uuid> = (0..scenes).map(scene).collect();
    for uuid in &ids {
        let _ = calls::update(
            &core, ZERO, &handle, uuid, true, 0, 10.0, 10.0, false, false, "",
        );
    }
    let at = |round: usize| ids.get(round % scenes).copied().unwrap_or(scene(0));
    let mut statuses = Vec::new();
    vec![
        cost("updateCooperateStatus", rounds, |round| {
            black_box(calls::update(
                &core,
                ZERO,
                &handle,
                &at(round),
                true,
                0,
                10.0,
                10.0,
                false,
                false,
                "",
            ));
        }),
        cost("isRegistered", rounds, |round| {
            black_box(calls::is_registered(&core, &handle, &at(round)));
        }),
        cost("isActivated", rounds, |round| {
            black_box(calls::is_activated(&core, &handle, &at(round)));
        }),
        cost("isForceActivated", rounds, |round| {
            black_box(calls::is_force_activated(&core, &handle, &at(round)));
        }),
        cost("isForceDeactivated", rounds, |round| {
            black_box(calls::is_force_deactivated(&core, &handle, &at(round)));
        }),
        cost("isRTCEnabled", rounds, |round| {
            black_box(calls::is_rtc_enabled(&core, &handle, &at(round)));
        }),
        cost("isTerminated", rounds, |round| {
            black_box(calls::is_terminated(&core, &handle, &at(round)));
        }),
        cost("cooperateCommands", rounds, |round| {
            let command = CommandIn {
                uuid: at(round),
                module: 0,
                command: 1,
            };
            black_box(calls::cooperate_commands(&core, ZERO, &handle, &[command]));
        }),
        cost("publishCooperateStatus", rounds.div_ceil(scenes), |_| {
            calls::statuses_into(&core, &handle, ZERO, &mut statuses);
            black_box(&statuses);
        }),
        cost("removeExpiredCooperateStatus", rounds, |_| {
            black_box(calls::advance(&core, ZERO));
        }),
        cost("planningCycle", rounds.div_ceil(scenes), |_| {
            for uuid in &ids {
                black_box(calls::is_activated(&core, &handle, uuid));
                black_box(calls::is_rtc_enabled(&core, &handle, uuid));
            }
            for uuid in &ids {
                black_box(calls::update(
                    &core, ZERO, &handle, uuid, true, 0, 10.0, 10.0, false, false, "",
                ));
            }
            black_box(calls::advance(&core, ZERO));
            calls::statuses_into(&core, &handle, ZERO, &mut statuses);
            black_box(&statuses);
        }),
    ]
}
