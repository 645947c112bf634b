//! The node's time through the rosbridge door (`[COOP-ENGINE-TIME.1]`): every call is answered
//! at its own time, whenever the node's periodic tick comes.

use std::time::Duration;

use crate::common::*;
use serde_json::json;

/// An operator's command made after its scene's time to live ran out, with no tick since, is
/// refused: the call tells the core the time first, and the scene has retired. The node is not
/// served, so nothing else tells it the time.
#[test]
fn a_command_after_the_time_to_live_is_refused_between_ticks() {
    use cooperation_adapters::engine::{Endpoint, Reply};
    use cooperation_adapters::wire::Service;
    let mut config = cooperation_adapters::settings::parse(SETTINGS).expect("the settings read");
    config.limits.ttl_ms = 200;
    // A step limit longer than the test (`[COOP-ENGINE-STEP.1]`): all the time counts.
    let node = cooperation_server::Node::with_options(
        config,
        cooperation_adapters::engine::Options {
            max_step_ms: 7_200_000,
            ..cooperation_adapters::engine::Options::default()
        },
    )
    .expect("a configuration");
    let call = |endpoint: Endpoint, args: serde_json::Value| {
        node.handle(endpoint.read_json(args.to_string().as_bytes()))
            .0
    };
    let sync = json!({"interface": "intersection", "statuses": [status(1, false, 20.0)]});
    let Reply::Sync(synced) = call(Endpoint::Sync, sync) else {
        panic!("a sync's reply")
    };
    assert!(synced.success, "{synced:?}");
    let command = |decision: u8| {
        call(
            Endpoint::Ad(Service::SetCommands),
            json!({"commands": [{"uuid": uuid(1), "cooperator": {"decision": decision}}]}),
        )
    };
    // Within the time to live: applied.
    let Reply::Ad(response) = command(2) else {
        panic!("an AD API reply")
    };
    assert!(response.status().success, "{response:?}");
    // Past it, and no tick since the scene's report: refused, the scene retired by expiry.
    std::thread::sleep(Duration::from_millis(400));
    let Reply::Ad(response) = command(1) else {
        panic!("an AD API reply")
    };
    let status = response.status();
    assert!(!status.success, "{response:?}");
    assert!(status.message.contains("retired"), "{response:?}");
}
