//! Deviations met in the core itself (`cooperation::State`).

use crate::common::*;
use cooperation::*;

/// `[COOP-DEV-STORED-COMMANDS.1]`: a command for a scene that registers later never applies,
/// and an old command never re-applies over a newer one.
#[test]
fn coop_dev_stored_commands_1() {
    let mut state = state();
    rejects(
        &mut state,
        commands(&[(id(1), OperatorDecision::Activate)]),
        Rule::CommandUnknown,
    );
    fires(
        &mut state,
        register(id(1), LANE_CHANGE, Decision::Deactivate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Activate)]),
        Rule::CommandApply,
    );
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Deactivate)]),
        Rule::CommandApply,
    );
    // Upstream re-applies the stored ACTIVATE at every planning cycle's unlock.
    for _ in 0..3 {
        fires(
            &mut state,
            update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
            Rule::OwnerUpdate,
        );
        assert_eq!(state.merged_decision(id(1)), Some(Decision::Deactivate));
    }
}

/// `[COOP-DEV-NONE.1]`: a new scene is undecided, not deactivated, and can be made undecided
/// again.
#[test]
fn coop_dev_none_1() {
    let mut state = with_scenes();
    assert_eq!(
        state.status(id(1)).map(|s| s.operator_decision),
        Some(OperatorDecision::Undecided)
    );
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Deactivate)]),
        Rule::CommandApply,
    );
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Waiting, Decision::Activate),
        Rule::OwnerUpdate,
    );
    assert_eq!(state.merged_decision(id(1)), Some(Decision::Deactivate));
    fires(
        &mut state,
        commands(&[(id(1), OperatorDecision::Undecided)]),
        Rule::CommandApply,
    );
    assert_eq!(
        state.merged_decision(id(1)),
        Some(Decision::Activate),
        "optional: follows module"
    );
}

/// `[COOP-DEV-POLICY-CLOBBER.1]`: switching policies back and forth keeps every operator
/// decision.
#[test]
fn coop_dev_policy_clobber_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        commands(&[
            (id(1), OperatorDecision::Deactivate),
            (id(2), OperatorDecision::Activate),
        ]),
        Rule::CommandApply,
    );
    for policy in [Policy::Optional, Policy::Required, Policy::Optional] {
        fires(
            &mut state,
            policies(&[(LANE_CHANGE, policy), (AVOIDANCE, policy)]),
            Rule::PolicySet,
        );
        assert_eq!(
            state.scene(id(1)).map(Scene::operator_decision),
            Some(OperatorDecision::Deactivate)
        );
        assert_eq!(
            state.scene(id(2)).map(Scene::operator_decision),
            Some(OperatorDecision::Activate)
        );
        assert_eq!(state.merged_decision(id(2)), Some(Decision::Activate));
    }
}

/// `[COOP-DEV-SILENT-DROP.1]`: a forbidden phase change is an error the owner sees.
#[test]
fn coop_dev_silent_drop_1() {
    let mut state = with_scenes();
    let result = state.apply(&update(
        id(1),
        LANE_CHANGE,
        Phase::Succeeded,
        Decision::Activate,
    ));
    let error = result.expect_err("waiting cannot become succeeded");
    assert_eq!(error.rule(), Rule::OwnerTransition);
    assert_eq!(
        error.to_string(),
        "scene 00000000-0000-0000-0000-000000000001 cannot go from waiting to succeeded"
    );
}

/// `[COOP-DEV-RACE.1]`: the state is a plain value: sending it to another thread and applying
/// there gives the same result as here (no hidden shared lock or global).
#[test]
fn coop_dev_race_1() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<State>();
    let input = commands(&[(id(1), OperatorDecision::Activate)]);
    let mut here = with_scenes();
    let there = std::thread::spawn({
        let mut state = with_scenes();
        let input = input.clone();
        move || {
            state.apply(&input).expect("applies");
            state
        }
    })
    .join()
    .expect("thread");
    here.apply(&input).expect("applies");
    assert_eq!(here, there);
    // Shared: two threads through one handle, each input whole; the full hammering is in
    // adapters/tests/concurrency.rs.
    // The fixture's table is small, and the race is between core inputs: no interface quota.
    let options = cooperation_adapters::engine::Options {
        scene_quota: 0,
        ..Default::default()
    };
    let engine =
        cooperation_adapters::engine::Engine::from_state(with_scenes(), options).expect("no quota");
    let shared = std::sync::Arc::new(cooperation_adapters::Shared::new(engine));
    let other = std::sync::Arc::clone(&shared);
    let operator = std::thread::spawn(move || {
        let commands = vec![Command {
            id: id(1),
            decision: OperatorDecision::Deactivate,
        }];
        other.update(|engine| {
            engine
                .call(|host| host.state_mut().apply(&Input::SetCommands { commands }))
                .0
        })
    });
    let owner = shared.update(|engine| {
        let input = update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate);
        engine.call(|host| host.state_mut().apply(&input)).0
    });
    assert!(operator.join().expect("thread").is_ok());
    assert_eq!(owner.map(|t| t.rule), Ok(Rule::OwnerUpdate));
    let scene = shared
        .read(|host| host.state().scene(id(1)).cloned())
        .expect("live");
    assert_eq!(
        (scene.phase(), scene.operator_decision()),
        (Phase::Running, OperatorDecision::Deactivate)
    );
}

/// `[COOP-DEV-IMPLICIT-REGISTER.1]`: an update for an unknown identifier is rejected, and a
/// registration always starts waiting.
#[test]
fn coop_dev_implicit_register_1() {
    let mut state = state();
    rejects(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUnknown,
    );
    fires(
        &mut state,
        register(id(1), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    assert_eq!(state.scene(id(1)).map(Scene::phase), Some(Phase::Waiting));
}

/// `[COOP-DEV-ID-REUSE.1]`: after removal, the identifier stays retired for every module.
#[test]
fn coop_dev_id_reuse_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        Input::Remove {
            id: id(1),
            module: LANE_CHANGE,
        },
        Rule::OwnerRemove,
    );
    rejects(
        &mut state,
        register(id(1), LANE_CHANGE, Decision::Activate),
        Rule::RegisterRetired,
    );
    rejects(
        &mut state,
        register(id(2), LANE_CHANGE, Decision::Activate),
        Rule::OwnerModule,
    );
}

/// `[COOP-DEV-TERMINAL.1]`: succeeded retires at once; repeating it is rejected, and the
/// retirement record still says how the scene ended.
#[test]
fn coop_dev_terminal_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Succeeded, Decision::Activate),
        Rule::OwnerFinish,
    );
    assert!(state.status(id(1)).is_none());
    rejects(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Succeeded, Decision::Activate),
        Rule::OwnerRetired,
    );
    assert_eq!(
        state.retirement(id(1)).map(|r| r.reason),
        Some(RetireReason::Succeeded)
    );
}

/// `[COOP-DEV-UNKNOWN-QUERY.1]`: every per-scene query answers `None` for a scene that is not
/// live, whatever the policies.
#[test]
fn coop_dev_unknown_query_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        Input::Remove {
            id: id(1),
            module: LANE_CHANGE,
        },
        Rule::OwnerRemove,
    );
    for absent in [id(1), id(9)] {
        assert!(state.scene(absent).is_none());
        assert_eq!(state.status(absent), None);
        assert_eq!(state.merged_decision(absent), None);
        assert_eq!(state.force_activated(absent), None);
        assert_eq!(state.force_deactivated(absent), None);
    }
}

/// `[COOP-DEV-BATCH.1]`: one failing command means no command applied.
#[test]
fn coop_dev_batch_1() {
    let mut state = with_scenes();
    let request = [1, 2, 3]
        .map(|n| Command {
            id: id(n),
            decision: OperatorDecision::Activate,
        })
        .into_iter()
        .collect();
    let answer = cooperation_adapters::wire::set_commands(&mut state, &request);
    assert!(!answer.response.status.success && !answer.changed);
    assert!(state
        .scenes()
        .all(|(_, scene)| scene.operator_decision() == OperatorDecision::Undecided));
}

/// `[COOP-DEV-FORCE.1]`: in every combination of live phase, module decision, operator
/// decision, policy and request, each force flag is what its definition says
/// (`[COOP-FORCE-ACTIVATED.1]`, `[COOP-FORCE-DEACTIVATED.1]`, written here from the spec's
/// words), and a forced scene's merged decision is the forced one. The flags are true in 12 and
/// 4 of the 96 combinations, so the agreement is not met by flags that are never set.
#[test]
fn coop_dev_force_1() {
    let (mut activated, mut deactivated) = (0, 0);
    for phase in [Phase::Waiting, Phase::Running, Phase::Aborting] {
        for module_decision in Decision::ALL {
            for operator in OperatorDecision::ALL {
                for policy in Policy::ALL {
                    for requested in [false, true] {
                        let mut state = one_scene(policy, module_decision, operator);
                        let path: &[Phase] = match phase {
                            Phase::Aborting => &[Phase::Running, Phase::Aborting],
                            _ => &[phase],
                        };
                        for step in path {
                            let input = update_requested(
                                id(1),
                                LANE_CHANGE,
                                *step,
                                module_decision,
                                requested,
                            );
                            fires(&mut state, input, Rule::OwnerUpdate);
                        }
                        let cancellable = matches!(phase, Phase::Waiting | Phase::Running);
                        let force_activated = cancellable
                            && operator == OperatorDecision::Activate
                            && (module_decision == Decision::Deactivate || requested);
                        let force_deactivated = phase == Phase::Running
                            && operator == OperatorDecision::Deactivate
                            && module_decision == Decision::Activate;
                        let case = (phase, module_decision, operator, policy, requested);
                        assert_eq!(
                            state.force_activated(id(1)),
                            Some(force_activated),
                            "{case:?}"
                        );
                        assert_eq!(
                            state.force_deactivated(id(1)),
                            Some(force_deactivated),
                            "{case:?}"
                        );
                        let merged = state.merged_decision(id(1));
                        if force_activated {
                            assert_eq!(merged, Some(Decision::Activate), "{case:?}");
                            activated += 1;
                        }
                        if force_deactivated {
                            assert_eq!(merged, Some(Decision::Deactivate), "{case:?}");
                            deactivated += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!((activated, deactivated), (12, 4));
}

/// `[COOP-DEV-EXPIRY.1]`: the TTL is configuration and expiry names what it retired.
#[test]
fn coop_dev_expiry_1() {
    let mut config = config();
    config.limits.ttl_ms = 250;
    let mut state = State::new(config).expect("valid");
    fires(
        &mut state,
        register(id(1), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    fires(&mut state, Input::Tick { elapsed_ms: 250 }, Rule::TimeAge);
    let transition = fires(&mut state, Input::Tick { elapsed_ms: 1 }, Rule::TimeExpire);
    assert_eq!(transition.retired, [id(1)]);
}

/// `[COOP-DEV-ORDER.1]`: registered far to near, reported near to far.
#[test]
fn coop_dev_order_1() {
    let mut state = state();
    for (n, distance) in [(1, 300.0), (2, 200.0), (3, 100.0)] {
        let input = Input::Register {
            id: id(n),
            module: LANE_CHANGE,
            report: Report::new(Decision::Activate, Geometry::velocity(distance)),
        };
        fires(&mut state, input, Rule::RegisterNew);
    }
    let mut out = Vec::new();
    state.velocity_factors_into(&mut out);
    let distances: Vec<f32> = out.iter().map(|f| f.distance.0).collect();
    assert_eq!(distances, [100.0, 200.0, 300.0]);
}
