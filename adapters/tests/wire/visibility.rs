//! What the AD API shows of a scene: a requested scene's status is the one it would have
//! without the request, which only the RTC status and the factor's detail can carry.

use super::*;
use cooperation_adapters::rtc;

/// A velocity scene under an optional policy, its owner asking (or not) for a decision.
fn scene(requested: bool) -> (State, SceneId) {
    let mut state = State::new(Config::new([(LANE_CHANGE, Policy::Optional)])).expect("valid");
    let id = SceneId::from_u128(3);
    let report = Report {
        requested,
        ..Report::new(Decision::Activate, Geometry::velocity(20.0))
    };
    state
        .apply(&Input::Register {
            id,
            module: LANE_CHANGE,
            report,
        })
        .expect("registers");
    (state, id)
}

/// `[COOP-DEV-REQUESTED-HIDDEN.1]`: on the AD API a requested scene's status and policy are
/// those of the same scene not requested, while the planner holds only the requested one
/// back; the RTC status says `requested`.
#[test]
fn coop_dev_requested_hidden_1() {
    let (asked, id) = scene(true);
    let (plain, _) = scene(false);
    let stamp = Time::default();
    assert_eq!(
        wire::velocity_factors(&asked, stamp),
        wire::velocity_factors(&plain, stamp)
    );
    let policies = |state: &mut State| json(&Service::GetPolicies.call_json(state, b"{}"));
    let (mut asked_mut, mut plain_mut) = (asked.clone(), plain.clone());
    assert_eq!(policies(&mut asked_mut), policies(&mut plain_mut));
    assert_eq!(asked.merged_decision(id), Some(Decision::Deactivate));
    assert_eq!(plain.merged_decision(id), Some(Decision::Activate));

    // The RTC status has the field, and says it.
    let mut state = State::new(Config::new([(
        Module::new(Behavior::LaneChange),
        Policy::Optional,
    )]))
    .expect("valid");
    let mut rtc = rtc::Rtc::standard();
    let mut interface = rtc
        .interface(&mut state, "lane_change_left")
        .expect("bound");
    let report = rtc::StatusReport::new(id, true, Phase::Waiting, 20.0, 60.0).requesting();
    interface
        .update_cooperate_status(&report)
        .expect("registers");
    let statuses = interface.view().cooperate_status_array(Time::default());
    assert!(statuses.statuses.iter().all(|status| status.requested));
    assert_eq!(statuses.statuses.len(), 1);
}
