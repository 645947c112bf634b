//! Time (`COOP-TIME-*`).

use crate::common::*;
use cooperation::*;

/// `[COOP-TIME-AGE.1]`: ticks age every scene; an age equal to the TTL does not expire.
#[test]
fn coop_time_age_1() {
    let mut state = with_scenes();
    let transition = fires(
        &mut state,
        Input::Tick { elapsed_ms: TTL_MS },
        Rule::TimeAge,
    );
    assert!(transition.retired.is_empty());
    assert!(state.scenes().all(|(_, scene)| scene.age_ms() == TTL_MS));
    fires(&mut state, Input::Tick { elapsed_ms: 0 }, Rule::TimeAge);
    assert_eq!(state.scene_count(), 2);
}

/// `[COOP-TIME-EXPIRE.1]`: scenes older than the TTL retire as expired, in identifier order,
/// and only those; a huge elapsed time saturates instead of overflowing.
#[test]
fn coop_time_expire_1() {
    let mut state = with_scenes();
    fires(
        &mut state,
        register(id(3), LANE_CHANGE, Decision::Activate),
        Rule::RegisterNew,
    );
    fires(&mut state, Input::Tick { elapsed_ms: 60 }, Rule::TimeAge);
    fires(
        &mut state,
        update(id(1), LANE_CHANGE, Phase::Running, Decision::Activate),
        Rule::OwnerUpdate,
    );
    let transition = fires(&mut state, Input::Tick { elapsed_ms: 41 }, Rule::TimeExpire);
    assert_eq!(transition.retired, [id(2), id(3)]);
    assert_eq!(
        state.retirement(id(3)).map(|r| r.reason),
        Some(RetireReason::Expired)
    );
    assert_eq!(
        state.scenes().map(|(id, _)| id).collect::<Vec<_>>(),
        [id(1)]
    );
    let transition = fires(
        &mut state,
        Input::Tick {
            elapsed_ms: u64::MAX,
        },
        Rule::TimeExpire,
    );
    assert_eq!(transition.retired, [id(1)]);
}
