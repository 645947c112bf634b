//! The node's time through the rosbridge door (`[COOP-ENGINE-TIME.1]`): every call is answered
//! at its own time, whenever the node's periodic tick comes.

use std::time::Duration;

use crate::common::*;
use cooperation_server::Options;
use serde_json::json;

/// An operator's command made after its scene's time to live ran out, before the node's next
/// tick, is refused: the call tells the core the time first, and the scene has retired.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_command_after_the_time_to_live_is_refused_between_ticks() {
    let mut config = cooperation_adapters::settings::parse(SETTINGS).expect("the settings read");
    config.limits.ttl_ms = 200;
    // No tick for an hour, and a step limit longer than that (`[COOP-ENGINE-STEP.1]`): only the
    // calls tell the core the time.
    let hour = Duration::from_secs(3_600);
    let node = cooperation_server::Node::with_options(
        config,
        cooperation_adapters::engine::Options {
            max_step_ms: 7_200_000,
            ..cooperation_adapters::engine::Options::default()
        },
    )
    .expect("a configuration");
    let served = serve_node(
        std::sync::Arc::new(node),
        Options {
            tick_every: hour,
            publish_every: hour,
            ..Options::default()
        },
    )
    .await;
    let mut module = Client::connect(&served.url).await;
    let mut operator = Client::connect(&served.url).await;
    module
        .sync("intersection", vec![status(1, false, 20.0)])
        .await;
    // Within the time to live: applied.
    let response = operator.set_commands(&[(1, 2)]).await;
    assert_eq!(
        response["values"]["status"]["success"],
        json!(true),
        "{response}"
    );
    // Past it, and no tick since the scene's report: refused, the scene retired by expiry.
    tokio::time::sleep(Duration::from_millis(400)).await;
    let response = operator.set_commands(&[(1, 1)]).await;
    let status = &response["values"]["status"];
    assert_eq!(status["success"], json!(false), "{response}");
    assert!(
        status["message"]
            .as_str()
            .is_some_and(|m| m.contains("retired")),
        "{response}"
    );
}
