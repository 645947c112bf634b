//! An interface's scenes are found from the adapter's list of them, not among all the core's
//! live scenes: after any sequence of calls, including inputs a host sends the core itself, each
//! interface's walks give exactly the live scenes routed to it, in identifier order.

use proptest::prelude::*;

use super::*;

/// Three velocity interfaces, each a module of its own.
const NAMES: [&str; 3] = ["intersection", "crosswalk", "blind_spot"];

/// What a step does.
#[derive(Clone, Debug)]
enum Step {
    /// Interface `k` reports scene `id` (0 waiting, 1 running, 2 succeeded).
    Report { k: usize, id: u128, phase: u8 },
    /// Interface `k` removes scene `id`.
    Remove { k: usize, id: u128 },
    /// Interface `k` clears its scenes.
    Clear { k: usize },
    /// The adapter's tick.
    Tick { ms: u64 },
    /// The host removes scene `id` from the core itself, past the adapter.
    HostRemove { id: u128 },
    /// The host tells the core the time itself, past the adapter.
    HostTick { ms: u64 },
    /// The host registers a scene no interface knows in the core itself.
    HostRegister { id: u128 },
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        6 => (0..3_usize, 1..=40_u128, 0..3_u8).prop_map(|(k, id, phase)| Step::Report { k, id, phase }),
        1 => (0..3_usize, 1..=40_u128).prop_map(|(k, id)| Step::Remove { k, id }),
        1 => (0..3_usize).prop_map(|k| Step::Clear { k }),
        1 => (0..30_u64).prop_map(|ms| Step::Tick { ms }),
        1 => (1..=40_u128).prop_map(|id| Step::HostRemove { id }),
        1 => (0..30_u64).prop_map(|ms| Step::HostTick { ms }),
        1 => (1000..=1010_u128).prop_map(|id| Step::HostRegister { id }),
    ]
}

/// Makes the step; refusals are part of the run and change nothing.
fn make(rtc: &mut Rtc, state: &mut State, step: &Step) {
    let phase = |phase: u8| match phase {
        0 => Phase::Waiting,
        1 => Phase::Running,
        _ => Phase::Succeeded,
    };
    match *step {
        Step::Report { k, id, phase: p } => {
            let report = rtc::StatusReport::new(SceneId::from_u128(id), true, phase(p), 5.0, 5.0);
            let mut interface = rtc.interface(state, NAMES[k]).expect("bound");
            let _ = interface.update_cooperate_status(&report);
        }
        Step::Remove { k, id } => {
            let mut interface = rtc.interface(state, NAMES[k]).expect("bound");
            let _ = interface.remove_cooperate_status(SceneId::from_u128(id));
        }
        Step::Clear { k } => {
            let mut interface = rtc.interface(state, NAMES[k]).expect("bound");
            let _ = interface.clear_cooperate_status();
        }
        Step::Tick { ms } => {
            rtc.tick(state, ms).expect("a tick is never refused");
        }
        Step::HostRemove { id } => {
            let id = SceneId::from_u128(id);
            if let Some(module) = state.scene(id).map(Scene::module) {
                state.apply(&Input::Remove { id, module }).expect("live");
            }
        }
        Step::HostTick { ms } => {
            state
                .apply(&Input::Tick { elapsed_ms: ms })
                .expect("a tick is never refused");
        }
        Step::HostRegister { id } => {
            let module = rtc
                .bindings()
                .iter()
                .find(|binding| binding.name == "traffic_light")
                .and_then(rtc::Binding::only_module)
                .expect("bound to one module");
            let geometry = Geometry::Velocity {
                pose: Pose::IDENTITY,
                distance: Distance(1.0),
                status: VelocityStatus::Unknown,
            };
            let report = Report::new(Decision::Activate, geometry);
            let _ = state.apply(&Input::Register {
                id: SceneId::from_u128(id),
                module,
                report,
            });
        }
    }
}

/// Each interface's scenes, statuses and answers are the live scenes routed to it (those its
/// `scene` query finds), in identifier order.
fn check(rtc: &Rtc, state: &State) -> Result<(), TestCaseError> {
    for name in NAMES {
        let view = rtc.view(state, name).expect("bound");
        let expected: Vec<SceneId> = state
            .scenes()
            .map(|(id, _)| id)
            .filter(|id| view.scene(*id).is_some())
            .collect();
        let walked: Vec<SceneId> = view.scenes().map(|(id, _)| id).collect();
        prop_assert_eq!(&walked, &expected, "{}'s scenes", name);
        let answered: Vec<SceneId> = view.answers().map(|(id, _)| id).collect();
        prop_assert_eq!(&answered, &expected, "{}'s answers", name);
        let published: Vec<SceneId> = view
            .cooperate_statuses(Time::new(1, 0))
            .map(|status| status.uuid.into())
            .collect();
        prop_assert_eq!(&published, &expected, "{}'s statuses", name);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Up to 40 identifiers shared by three interfaces, a core that remembers 6 retired ones
    /// (so identifiers are forgotten and registered again, through other interfaces too), scenes
    /// that expire after 40 ms, and the host's own removals, ticks and registrations.
    #[test]
    fn each_interface_walks_exactly_its_live_scenes(steps in proptest::collection::vec(step(), 1..120)) {
        let rtc_standard = Rtc::standard();
        let config = Config::new(rtc_standard.policies(false))
            .ttl_ms(40)
            .retired_capacity(6);
        let mut state = State::new(config).expect("valid configuration");
        let mut rtc = rtc_standard;
        for step in &steps {
            make(&mut rtc, &mut state, step);
            check(&rtc, &state)?;
        }
    }
}

/// A scene the host retired itself stays on its interface's list while the core holds as many
/// live scenes the adapter has no route for; when its forgotten identifier is registered again
/// through another interface, it is that interface's scene only.
#[test]
fn an_identifier_registered_again_elsewhere_leaves_its_old_interface() {
    let standard = Rtc::standard();
    let config = Config::new(standard.policies(false)).retired_capacity(1);
    let mut state = State::new(config).expect("valid configuration");
    let mut rtc = standard;
    let steps = [
        Step::Report {
            k: 0,
            id: 1,
            phase: 0,
        },
        // Retired past the adapter; the host's own scene keeps the lists from looking stale.
        Step::HostRemove { id: 1 },
        Step::HostRegister { id: 1000 },
        // Retiring another identifier makes the core forget the first.
        Step::Report {
            k: 2,
            id: 2,
            phase: 0,
        },
        Step::Remove { k: 2, id: 2 },
        Step::Report {
            k: 1,
            id: 1,
            phase: 0,
        },
    ];
    for step in &steps {
        make(&mut rtc, &mut state, step);
    }
    assert!(
        state.retirement(SceneId::from_u128(1)).is_none(),
        "forgotten, then live"
    );
    let crosswalk = rtc.view(&state, NAMES[1]).expect("bound");
    assert!(crosswalk.scene(SceneId::from_u128(1)).is_some());
    check(&rtc, &state).expect("each interface walks its own scenes");
}
