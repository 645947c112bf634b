//! Fixtures shared by the integration tests (the adapters' tests use them too:
//! `adapters/tests/common/mod.rs`).

#![allow(dead_code, unreachable_pub)]

pub mod forms;
pub mod inputs;

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
        report: Report::new(decision, Geometry::velocity(10.0)),
    }
}

pub fn update(id: SceneId, module: Module, phase: Phase, decision: Decision) -> Input {
    update_with(id, module, phase, decision, false, Geometry::velocity(5.0))
}

/// `update`, with the owner asking for an operator decision or not (`[COOP-REQUESTED.1]`).
pub fn update_requested(
    id: SceneId,
    module: Module,
    phase: Phase,
    decision: Decision,
    requested: bool,
) -> Input {
    update_with(
        id,
        module,
        phase,
        decision,
        requested,
        Geometry::velocity(5.0),
    )
}

/// An owner's update with every field given.
pub fn update_with(
    id: SceneId,
    module: Module,
    phase: Phase,
    decision: Decision,
    requested: bool,
    geometry: Geometry,
) -> Input {
    Input::Update {
        id,
        module,
        phase,
        report: Report {
            requested,
            ..Report::new(decision, geometry)
        },
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

/// A state with one live lane-change scene, 1: its module's policy set by a policy batch, its
/// module decision by its registration, its operator decision by a command.
pub fn one_scene(policy: Policy, module_decision: Decision, operator: OperatorDecision) -> State {
    let mut state = state();
    fires(
        &mut state,
        policies(&[(LANE_CHANGE, policy)]),
        Rule::PolicySet,
    );
    fires(
        &mut state,
        register(id(1), LANE_CHANGE, module_decision),
        Rule::RegisterNew,
    );
    fires(
        &mut state,
        commands(&[(id(1), operator)]),
        Rule::CommandApply,
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

/// The order of distances in the factor lists, written from the words of `[COOP-OUT-ORDER.1]`
/// rather than with the library's comparison: ascending; `-0.0` before `0.0`; every NaN, of
/// either sign, after every number (`inf` included); positive NaNs before negative ones; NaNs
/// of one sign in IEEE 754 total order (for negative NaNs, the larger payload first).
pub fn spec_distance_order(a: f32, b: f32) -> std::cmp::Ordering {
    use std::cmp::Ordering;
    match (a.is_nan(), b.is_nan()) {
        (false, false) => a
            .partial_cmp(&b)
            .unwrap_or(Ordering::Equal)
            .then_with(|| a.is_sign_positive().cmp(&b.is_sign_positive())),
        (false, true) => Ordering::Less,
        (true, false) => Ordering::Greater,
        (true, true) => {
            let payload = |x: f32| x.to_bits() & 0x7fff_ffff;
            let by_payload = if a.is_sign_negative() {
                payload(b).cmp(&payload(a))
            } else {
                payload(a).cmp(&payload(b))
            };
            a.is_sign_negative()
                .cmp(&b.is_sign_negative())
                .then(by_payload)
        }
    }
}

/// Whether `a` is listed before `b` in a factor list (`[COOP-OUT-ORDER.1]`): by distance in
/// [`spec_distance_order`], then by identifier.
pub fn listed_before(a: (Distance, SceneId), b: (Distance, SceneId)) -> bool {
    spec_distance_order(a.0 .0, b.0 .0)
        .then(a.1.cmp(&b.1))
        .is_lt()
}

/// Whether a factor at `a` may be listed before one at `b` in a list with factors of modules
/// that do not cooperate (scene `None`): by distance in [`spec_distance_order`]; at equal
/// distance, scenes by identifier before the others, which keep the order they were given in.
pub fn factor_listed_before(
    a: (Distance, Option<SceneId>),
    b: (Distance, Option<SceneId>),
) -> bool {
    let tie = match (a.1, b.1) {
        (Some(x), Some(y)) => x.cmp(&y),
        (Some(_), None) => core::cmp::Ordering::Less,
        (None, Some(_)) => core::cmp::Ordering::Greater,
        (None, None) => core::cmp::Ordering::Less,
    };
    spec_distance_order(a.0 .0, b.0 .0).then(tie).is_lt()
}
