//! `Shared` under many threads at once (`[COOP-DEV-RACE.1]`): planning cycles, operator
//! commands through the AD API (some of them rejected), policy changes, time and readers, all
//! hammering one handle. No update may be lost, no rejected batch may leave a trace, and every
//! state a reader sees must be whole.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Barrier};
use std::thread;

use cooperation::*;
use cooperation_adapters::engine::{self, Engine, Reply, Request};
use cooperation_adapters::wire::{self, ResponseStatus};
use cooperation_adapters::{Shared, Time};

const PLANNERS: usize = 4;
const SCENES_PER_PLANNER: usize = 16;
const ROUNDS: usize = 300;

const MODULES: [Behavior; 4] = [
    Behavior::LaneChange,
    Behavior::Avoidance,
    Behavior::Intersection,
    Behavior::Crosswalk,
];

fn module(planner: usize) -> Module {
    Module::new(MODULES[planner % MODULES.len()])
}

fn scene(planner: usize, n: usize) -> SceneId {
    SceneId::from_u128(((planner as u128 + 1) << 32) | n as u128)
}

fn shared() -> Arc<Shared> {
    let config = Config {
        policies: MODULES
            .iter()
            .map(|&b| (Module::new(b), Policy::Optional))
            .collect(),
        limits: Limits {
            ttl_ms: 1_000_000,
            max_scenes: PLANNERS * SCENES_PER_PLANNER,
            retired_capacity: 16,
            max_batch: 64,
        },
    };
    let state = State::new(config).expect("valid config");
    // The planners apply core inputs, not RTC calls: no interface quota, whose total the small
    // table could not hold.
    let options = engine::Options {
        scene_quota: 0,
        ..engine::Options::default()
    };
    Arc::new(Shared::new(
        Engine::from_state(state, options).expect("no quota"),
    ))
}

/// The AD API's answer to `request`, made at the time the core was last told.
fn answer(shared: &Shared, request: wire::Request) -> ResponseStatus {
    shared.update(|engine| {
        let now = engine.told(Time::default());
        match engine.handle(Request::Ad(request), now).reply {
            Reply::Ad(response) => response.status().clone(),
            Reply::Sync(response) => panic!("an AD API request got a sync's reply: {response:?}"),
        }
    })
}

fn decision(round: usize, n: usize) -> Decision {
    if (round + n) % 2 == 0 {
        Decision::Activate
    } else {
        Decision::Deactivate
    }
}

fn operator(round: usize, n: usize) -> OperatorDecision {
    OperatorDecision::ALL[(round * 7 + n) % OperatorDecision::ALL.len()]
}

#[test]
fn the_handle_is_send_and_sync() {
    fn send_sync<T: Send + Sync>() {}
    send_sync::<Shared>();
}

/// Planners (one per module) each run `ROUNDS` cycles over their own scenes; one operator per
/// planner sends commands for that planner's scenes, every third batch spoiled by a command for
/// an unknown identifier; a policy thread flips policies; a clock thread ticks; readers check
/// every snapshot. At the end every scene holds exactly the last module decision and the last
/// accepted operator decision sent for it, and every module its last policy.
#[test]
fn many_threads_lose_nothing_and_half_apply_nothing() {
    let shared = shared();
    let start = Arc::new(Barrier::new(PLANNERS * 2 + 3));
    let done = Arc::new(AtomicBool::new(false));
    let mut planners = Vec::new();
    let mut operators = Vec::new();
    // Each operator starts commanding once its planner's scenes exist.
    let registered: Vec<Arc<Barrier>> = (0..PLANNERS).map(|_| Arc::new(Barrier::new(2))).collect();

    for p in 0..PLANNERS {
        let (shared, start) = (Arc::clone(&shared), Arc::clone(&start));
        let registered = Arc::clone(&registered[p]);
        planners.push(thread::spawn(move || {
            start.wait();
            for n in 0..SCENES_PER_PLANNER {
                let register = Input::Register {
                    id: scene(p, n),
                    module: module(p),
                    report: Report::new(decision(0, n), Geometry::velocity(n as f32)),
                };
                assert_eq!(
                    shared.update(|engine| engine
                        .call(|host| host.state_mut().apply(&register))
                        .0
                        .map(|t| t.rule)),
                    Ok(Rule::RegisterNew)
                );
            }
            registered.wait();
            for round in 1..=ROUNDS {
                let cycle: Vec<Input> = (0..SCENES_PER_PLANNER)
                    .map(|n| Input::Update {
                        id: scene(p, n),
                        module: module(p),
                        phase: Phase::Running,
                        report: Report::new(decision(round, n), Geometry::velocity(n as f32)),
                    })
                    .collect();
                let results = shared
                    .update(|engine| engine.call(|host| host.state_mut().apply_all(&cycle)).0)
                    .expect("every update applies");
                assert_eq!(results.len(), SCENES_PER_PLANNER);
                for result in results {
                    assert_eq!(result.rule, Rule::OwnerUpdate);
                }
            }
        }));
    }

    for p in 0..PLANNERS {
        let (shared, start) = (Arc::clone(&shared), Arc::clone(&start));
        let registered = Arc::clone(&registered[p]);
        operators.push(thread::spawn(move || {
            start.wait();
            registered.wait();
            // What this operator last got accepted, per scene; only it commands these scenes.
            let mut last = vec![None; SCENES_PER_PLANNER];
            let mut accepted = 0usize;
            for round in 0..ROUNDS {
                let mut batch: Vec<Command> = (0..SCENES_PER_PLANNER)
                    .filter(|n| (n + round) % 3 != 0)
                    .map(|n| Command {
                        id: scene(p, n),
                        decision: operator(round, n),
                    })
                    .collect();
                let spoiled = round % 3 == 2;
                if spoiled {
                    batch.push(Command {
                        id: SceneId::from_u128(u128::MAX - p as u128),
                        decision: OperatorDecision::Activate,
                    });
                }
                let request = batch.iter().copied().collect();
                let status = answer(&shared, wire::Request::SetCommands(request));
                // Every scene is live and cancellable throughout: a batch fails exactly when
                // it is spoiled.
                assert_eq!(status.success, !spoiled, "round {round}");
                if status.success {
                    accepted += 1;
                    for command in &batch {
                        let n = (command.id.to_u128() & 0xffff_ffff) as usize;
                        last[n] = Some(command.decision);
                    }
                } else {
                    assert_eq!(status.code, ResponseStatus::PARAMETER_ERROR);
                }
                // Nobody else commands these scenes: each holds this operator's last accepted
                // decision, so a rejected batch left nothing behind.
                shared.read(|host| {
                    let state = host.state();
                    for (n, expected) in last.iter().enumerate() {
                        if let Some(expected) = expected {
                            let now = state.scene(scene(p, n)).map(Scene::operator_decision);
                            assert_eq!(now, Some(*expected), "scene {n} of planner {p}");
                        }
                    }
                });
            }
            (last, accepted)
        }));
    }

    let policies = {
        let (shared, start) = (Arc::clone(&shared), Arc::clone(&start));
        thread::spawn(move || {
            start.wait();
            let mut last = None;
            for round in 0..ROUNDS {
                let policy = Policy::ALL[round % 2];
                let settings = vec![
                    PolicySetting {
                        module: module(round),
                        policy,
                    },
                    PolicySetting {
                        module: module(round + 1),
                        policy,
                    },
                ];
                let request = settings.into_iter().collect();
                let status = answer(&shared, wire::Request::SetPolicies(request));
                assert!(status.success);
                last = Some((round, policy));
            }
            last
        })
    };

    let clock = {
        let (shared, start, done) = (Arc::clone(&shared), Arc::clone(&start), Arc::clone(&done));
        thread::spawn(move || {
            start.wait();
            // The engine's time 0: its first reading.
            shared.update(|engine| engine.advance(engine::Now::default()));
            let mut ticks = 0u64;
            while !done.load(Ordering::Relaxed) && ticks < 100_000 {
                // One millisecond later than the core was last told.
                let ticked = shared.update(|engine| {
                    let told = engine.told(Time::default());
                    let later = engine::Now::new(told.reading_ns + 1_000_000, told.stamp);
                    engine.advance(later).1
                });
                assert!(ticked.is_some());
                ticks += 1;
            }
            ticks
        })
    };

    let reader = {
        let (shared, start, done) = (Arc::clone(&shared), Arc::clone(&start), Arc::clone(&done));
        thread::spawn(move || {
            start.wait();
            let mut seen = 0usize;
            while !done.load(Ordering::Relaxed) {
                let snapshot = shared.read(|host| host.state().clone());
                snapshot.check_invariants().expect("a whole state");
                // Every scene's merged decision is there and the statuses list every scene.
                let mut statuses = Vec::new();
                snapshot.statuses_into(&mut statuses);
                assert_eq!(statuses.len(), snapshot.scene_count());
                for (id, _) in snapshot.scenes() {
                    assert!(snapshot.merged_decision(id).is_some());
                }
                seen += 1;
            }
            seen
        })
    };

    for planner in planners {
        planner.join().expect("planner thread");
    }
    let (operators, accepted): (Vec<Vec<Option<OperatorDecision>>>, Vec<usize>) = operators
        .into_iter()
        .map(|w| w.join().expect("operator thread"))
        .unzip();
    let unspoiled = (0..ROUNDS).filter(|round| round % 3 != 2).count();
    assert!(accepted.iter().all(|&n| n == unspoiled), "{accepted:?}");
    let (round, policy) = policies
        .join()
        .expect("policy thread")
        .expect("policies set");
    done.store(true, Ordering::Relaxed);
    let ticks = clock.join().expect("clock thread");
    let reads = reader.join().expect("reader thread");
    assert!(ticks > 0 && reads > 0);

    let host = Arc::try_unwrap(shared)
        .expect("every thread is done")
        .into_inner();
    let state = host.state();
    state.check_invariants().expect("a whole state");
    assert_eq!(state.scene_count(), PLANNERS * SCENES_PER_PLANNER);
    for (p, last) in operators.iter().enumerate() {
        for (n, expected) in last.iter().enumerate() {
            let scene = state.scene(scene(p, n)).expect("every scene is live");
            assert_eq!(
                scene.module_decision(),
                decision(ROUNDS, n),
                "last cycle's decision"
            );
            assert_eq!(
                scene.operator_decision(),
                expected.unwrap_or(OperatorDecision::Undecided),
                "last accepted command"
            );
            assert_eq!(scene.phase(), Phase::Running);
        }
    }
    assert_eq!(state.policy(module(round)), Some(policy));
    assert_eq!(state.policy(module(round + 1)), Some(policy));
}

/// A reader that panics while holding the lock leaves the handle usable and the state whole.
#[test]
fn a_panicking_reader_does_not_break_the_handle() {
    let shared = shared();
    let id = scene(0, 0);
    let register = Input::Register {
        id,
        module: module(0),
        report: Report::new(Decision::Activate, Geometry::velocity(1.0)),
    };
    shared
        .update(|engine| engine.call(|host| host.state_mut().apply(&register)).0)
        .expect("registers");
    let before = shared.read(Engine::clone);
    let other = Arc::clone(&shared);
    let panicked = thread::spawn(move || other.read(|_| panic!("a reader's own bug"))).join();
    assert!(panicked.is_err());
    assert_eq!(shared.read(Engine::clone), before);
    let request = [Command {
        id,
        decision: OperatorDecision::Deactivate,
    }]
    .into_iter()
    .collect();
    assert!(answer(&shared, wire::Request::SetCommands(request)).success);
    assert_eq!(
        shared.read(|host| host.state().merged_decision(id)),
        Some(Decision::Deactivate)
    );
}
