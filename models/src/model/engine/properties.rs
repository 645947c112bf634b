//! The engine model's properties: the specification's rules for a host (`[COOP-ENGINE-*]`),
//! each a condition on one state, and witnesses that the checked runs reach what the rules are
//! about.

use cooperation::Phase;
use stateright::Property;

use super::{broken, content, EngineModel, EngineStep};
use crate::model::spec::{messages, responses};

/// `COOP-ENGINE-TIME.1`'s property.
pub const TIME: &str =
    "COOP-ENGINE-TIME.1: no command applies to a scene whose time to live had passed at the request's time";
/// `COOP-ENGINE-STEP.1`'s property.
pub const STEP: &str = "COOP-ENGINE-STEP.1: a scene lives its time to live in the core's time, where a step of the clock counts at most the step limit";
/// The witness of a jump: reachable only when a step of the clock is longer than the limit.
pub(super) const JUMP_WITNESS: &str =
    "witness: a scene outlives its time to live on the clock after the core is told (a jump)";
/// `COOP-ENGINE-TIME.1`'s other property.
pub const LIFETIME: &str =
    "COOP-ENGINE-TIME.1: a scene lives its time to live from the time of its last report";
/// The messages' property.
pub const MESSAGES: &str = "COOP-OUT-STATUS.1, COOP-OUT-ORDER.1 (engine): the streams' factors are the spec's mapping of the state, field by field, ordered by distance";
/// The witness of a clock that went back: reachable only when it can.
pub(super) const REWIND_WITNESS: &str = "witness: a scene is live after the clock went back";
/// The witness of a scene past its time to live, before the core is told: reachable only when
/// the clock runs past the time to live.
pub(super) const STALE_WITNESS: &str =
    "witness: a scene outlives its time to live on the clock before the core is told";
/// The `get_policies` answer's property.
pub const POLICIES: &str = "COOP-POL-GET.2, COOP-API-STATUS.1 (engine): get_policies answers success and every configured module's policy constant, in the spec's order";
/// The scenes topic's property.
pub const SCENES: &str = "COOP-MERGE.1, COOP-REQUESTED.1 (engine): /cooperation/scenes shows each live scene's merged decision, policy and wait for an operator as the spec states them, in identifier order";
/// `COOP-ENGINE-PUBLISH.1`'s other property.
pub const HINTED: &str = "COOP-ENGINE-PUBLISH.1: a call that changes what the streams show asks for a publication at once";
/// `COOP-ENGINE-PUBLISH.1`'s periodic property.
pub const PERIODIC: &str = "COOP-ENGINE-PUBLISH.1: a publication is due once the interval has passed on the clock since the last, or the clock reads earlier than it";
/// `COOP-ENGINE-PUBLISH.1`'s property.
pub const PUBLISH: &str = "COOP-ENGINE-PUBLISH.1: whenever no publication is due, the last one shows what the state shows";
/// `COOP-ENGINE-WAKE.1`'s property.
pub const WAKE: &str = "COOP-ENGINE-WAKE.1: a host that waits as long as the engine asks tells it the time at the earliest scene expiry, periodic publication or step limit";
/// `COOP-ENGINE-ANSWER.1`'s property.
pub const ANSWER: &str = "COOP-ENGINE-ANSWER.1: an operator's call is answered as the core's transition at the request's time answers it";

fn unbroken<const FLAG: u8>(_: &EngineModel, state: &EngineStep) -> bool {
    state.broken & FLAG == 0
}

/// Every scene reported and not removed (`reported`: when, by `now`'s clock), whose time to live
/// has not passed by `now` since its last report, is live.
fn live_while_fresh(
    model: &EngineModel,
    state: &EngineStep,
    reported: &[Option<u64>],
    now: u64,
) -> bool {
    let ttl = model.config().limits.ttl_ms;
    reported.iter().enumerate().all(|(at, reported)| {
        let id = cooperation::SceneId::from_u128(at as u128 + 1);
        reported.map_or(true, |reported| now.saturating_sub(reported) > ttl)
            || state.engine.state().scene(id).is_some()
    })
}

/// Every scene reported and not removed, whose time to live has not passed on the clock since
/// its last report, is live.
fn reported_scenes_live(model: &EngineModel, state: &EngineStep) -> bool {
    live_while_fresh(model, state, &state.reported_ms, state.clock_ms)
}

/// Every scene reported and not removed, whose time to live has not passed in the core's time
/// by the model's count since its last report, is live.
fn reported_scenes_live_in_core_time(model: &EngineModel, state: &EngineStep) -> bool {
    live_while_fresh(model, state, &state.reported_core_ms, state.core_ms)
}

/// A scene is live though its time to live has passed on the clock since its last report, the
/// core told of the clock's reading: a step longer than the limit counted less.
fn scene_outlives_a_jump(model: &EngineModel, state: &EngineStep) -> bool {
    let ttl = model.config().limits.ttl_ms;
    state.read_ms == state.clock_ms
        && state.reported_ms.iter().enumerate().any(|(at, reported)| {
            let id = cooperation::SceneId::from_u128(at as u128 + 1);
            reported.is_some_and(|reported| state.clock_ms.saturating_sub(reported) > ttl)
                && state.engine.state().scene(id).is_some()
        })
}

/// The factors the engine writes are those the spec's oracle states for the core, field by
/// field and in order.
fn messages_are_the_spec(model: &EngineModel, state: &EngineStep) -> bool {
    model.messages(state) == messages::factors(state.engine.state(), model.steering())
}

/// `get_policies`, asked in this state, answers what the spec's oracle states for the core.
fn policies_are_the_spec(model: &EngineModel, state: &EngineStep) -> bool {
    model.policies_answer(state) == Some(responses::policies(state.engine.state()))
}

/// `/cooperation/scenes` shows what the spec's oracle states for the core, row by row.
fn scenes_are_the_spec(model: &EngineModel, state: &EngineStep) -> bool {
    model.scenes_shown(state) == responses::scenes(state.engine.state(), model.merge())
}

/// When the engine says no publication is due, what the streams last carried is what the core
/// shows now: every change the streams show is followed by a publication that shows it.
fn published_shows_state(_: &EngineModel, state: &EngineStep) -> bool {
    state.engine.publication_due(state.now())
        || state.published.as_deref() == Some(content(state.engine.state()).as_slice())
}

/// A publication is due before the first, once the interval has passed on the clock since the
/// last, and while the clock reads earlier than the last (it went back).
fn periodic_due(model: &EngineModel, state: &EngineStep) -> bool {
    let every = super::PUBLISH_EVERY_MS;
    let owed = state.published_at_ms.map_or(true, |at| {
        state.clock_ms < at || state.clock_ms - at >= every
    });
    !owed || model.due(state)
}

/// A scene is live and waiting while its time to live has passed on the clock, the core not yet
/// told: the time a command could be applied late.
fn stale_scene_awaits_tick(model: &EngineModel, state: &EngineStep) -> bool {
    let ttl = model.config().limits.ttl_ms;
    state.reported_ms.iter().enumerate().any(|(at, reported)| {
        let id = cooperation::SceneId::from_u128(at as u128 + 1);
        reported.is_some_and(|reported| state.clock_ms.saturating_sub(reported) > ttl)
            && state
                .engine
                .state()
                .scene(id)
                .map(cooperation::Scene::phase)
                == Some(Phase::Waiting)
    })
}

/// The clock went back, and a scene is live.
fn live_after_rewind(_: &EngineModel, state: &EngineStep) -> bool {
    state.went_back && state.engine.state().scenes().next().is_some()
}

/// An operator's command has applied.
fn command_applied(_: &EngineModel, state: &EngineStep) -> bool {
    state
        .engine
        .state()
        .scenes()
        .any(|(_, scene)| scene.operator_decision() != cooperation::OperatorDecision::Undecided)
}

/// The properties.
#[must_use]
pub fn properties() -> Vec<Property<EngineModel>> {
    vec![
        Property::always(TIME, unbroken::<{ broken::STALE_COMMAND }>),
        Property::always(LIFETIME, reported_scenes_live),
        Property::always(STEP, reported_scenes_live_in_core_time),
        Property::always(PUBLISH, published_shows_state),
        Property::always(PERIODIC, periodic_due),
        Property::always(HINTED, unbroken::<{ broken::UNHINTED }>),
        Property::always(ANSWER, unbroken::<{ broken::ANSWER }>),
        Property::always(WAKE, unbroken::<{ broken::WAKE }>),
        Property::always(MESSAGES, messages_are_the_spec),
        Property::always(POLICIES, policies_are_the_spec),
        Property::always(SCENES, scenes_are_the_spec),
        Property::sometimes(STALE_WITNESS, stale_scene_awaits_tick),
        Property::sometimes(JUMP_WITNESS, scene_outlives_a_jump),
        Property::sometimes(REWIND_WITNESS, live_after_rewind),
        Property::sometimes("witness: an operator's command applies", command_applied),
    ]
}
