//! Fixtures shared by the integration tests.
#![allow(dead_code, unreachable_pub)]

use cooperation::*;

/// Lane change: optional by default.
pub const LANE_CHANGE: Module = Module::new(Behavior::LaneChange);
/// Avoidance (change): required by default.
pub const AVOIDANCE: Module = Module::with_sequence(Behavior::Avoidance, Sequence::Change);
/// Intersection: not configured, so it has no policy.
pub const INTERSECTION: Module = Module::new(Behavior::Intersection);

pub const TTL_MS: u64 = 100;

pub fn id(n: u128) -> SceneId {
    SceneId::from_u128(n)
}

pub fn config() -> Config {
    Config {
        policies: [
            (LANE_CHANGE, Policy::Optional),
            (AVOIDANCE, Policy::Required),
        ]
        .into(),
        limits: Limits {
            ttl_ms: TTL_MS,
            max_scenes: 4,
            retired_capacity: 3,
            max_batch: 4,
        },
    }
}

pub fn state() -> State {
    State::new(config()).expect("valid configuration")
}

pub fn register(id: SceneId, module: Module, decision: Decision) -> Input {
    Input::Register {
        id,
        module,
        decision,
        requested: false,
        geometry: Geometry::velocity(10.0),
    }
}

pub fn update(id: SceneId, module: Module, phase: Phase, decision: Decision) -> Input {
    Input::Update {
        id,
        module,
        phase,
        decision,
        requested: false,
        geometry: Geometry::velocity(5.0),
    }
}

/// `update`, with the owner asking for an operator decision or not (`[COOP-REQUESTED.1]`).
pub fn update_requested(
    id: SceneId,
    module: Module,
    phase: Phase,
    decision: Decision,
    requested: bool,
) -> Input {
    match update(id, module, phase, decision) {
        Input::Update {
            id,
            module,
            phase,
            decision,
            geometry,
            ..
        } => Input::Update {
            id,
            module,
            phase,
            decision,
            requested,
            geometry,
        },
        other => other,
    }
}

pub fn commands(list: &[(SceneId, OperatorDecision)]) -> Input {
    Input::SetCommands {
        commands: list
            .iter()
            .map(|&(id, decision)| Command { id, decision })
            .collect(),
    }
}

pub fn policies(list: &[(Module, Policy)]) -> Input {
    Input::SetPolicies {
        policies: list
            .iter()
            .map(|&(module, policy)| PolicySetting { module, policy })
            .collect(),
    }
}

/// Applies `input`, asserting that `rule` fired and the invariants hold.
pub fn fires(state: &mut State, input: Input, rule: Rule) -> Transition {
    let transition = state
        .apply(&input)
        .unwrap_or_else(|r| panic!("{input:?} rejected: {r}"));
    assert_eq!(transition.rule, rule, "{input:?}");
    state.check_invariants().expect("invariants hold");
    transition
}

/// Applies `input`, asserting that `rule` rejected it and that nothing changed.
pub fn rejects(state: &mut State, input: Input, rule: Rule) -> Rejection {
    let before = state.clone();
    let rejection = state.apply(&input).expect_err("rejected");
    assert_eq!(rejection.rule(), rule, "{input:?}: {rejection}");
    assert_eq!(*state, before, "a rejection changed the state");
    assert!(!rejection.to_string().is_empty());
    rejection
}

/// A state with one live scene of each configured module: 1 (lane change), 2 (avoidance).
pub fn with_scenes() -> State {
    let mut state = state();
    fires(
        &mut state,
        register(id(1), LANE_CHANGE, Decision::Deactivate),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        register(id(2), AVOIDANCE, Decision::Activate),
        Rule::RegisterNew,
    );
    state
}

/// Moves a live scene through `phases` by its owner's updates (module decision activate),
/// asserting each is an accepted, non-terminal update.
pub fn walk(state: &mut State, id: SceneId, module: Module, phases: &[Phase]) {
    for phase in phases {
        fires(
            state,
            update(id, module, *phase, Decision::Activate),
            Rule::OwnerUpdate,
        );
    }
}

/// Registers and removes each identifier of `ids` in turn, so that each retires as removed.
pub fn churn(state: &mut State, ids: std::ops::RangeInclusive<u128>) {
    for n in ids {
        fires(
            state,
            register(id(n), LANE_CHANGE, Decision::Activate),
            Rule::RegisterNew,
        );
        fires(
            state,
            Input::Remove {
                id: id(n),
                module: LANE_CHANGE,
            },
            Rule::OwnerRemove,
        );
    }
}

/// The standard RTC interfaces over a core that has every bound module, each with the policy
/// upstream's `enable_rtc` flag stands for, and the default limits (a 10 s TTL, as upstream).
pub fn rtc_setup(enable_rtc: bool) -> (rtc::Rtc, State) {
    let rtc = rtc::Rtc::standard();
    let state = State::new(Config::new(rtc.policies(enable_rtc))).expect("valid configuration");
    (rtc, state)
}

/// A `CooperateCommands` request; each command's module is `NONE`, as a default-constructed
/// upstream message has it.
pub fn rtc_commands(list: &[(SceneId, u8)]) -> rtc::CooperateCommandsRequest {
    rtc::CooperateCommandsRequest {
        stamp: rtc::Time::default(),
        commands: list
            .iter()
            .map(|&(id, command)| rtc::CooperateCommand {
                uuid: id.into(),
                module: rtc::Module::default(),
                command: rtc::Command::new(command),
            })
            .collect(),
    }
}
