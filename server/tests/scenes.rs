//! `/cooperation/scenes` (`docs/server.md`): each live scene's merged decision, whether it waits
//! for an operator, the policy that applies and its age, as the core has them; and the
//! planning modules' sync, which reads only the status fields a module owns.

use std::time::Duration;

use crate::common::{serve, status, uuid, Client};
use cooperation_server::Options;
use serde_json::{json, Value};

const SCENES: &str = "/cooperation/scenes";

/// The next publication of the topic that lists scene `n` and satisfies `wanted`.
async fn until(client: &mut Client, n: u128, wanted: impl Fn(&Value) -> bool) -> Value {
    loop {
        let publication = client.next_op("publish").await;
        if publication["topic"] != SCENES {
            continue;
        }
        let scene = publication["msg"]["scenes"]
            .as_array()
            .and_then(|scenes| scenes.iter().find(|s| s["uuid"] == uuid(n)).cloned());
        if let Some(scene) = scene.filter(|scene| wanted(scene)) {
            return scene;
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_requested_scene_waits_for_the_operator_until_one_decides() {
    let served = serve(Options {
        publish_every: Duration::from_millis(50),
        ..Options::default()
    })
    .await;
    let mut module = Client::connect(&served.url).await;
    let mut operator = Client::connect(&served.url).await;
    operator
        .send(&json!({"op": "subscribe", "topic": SCENES,
                      "type": "cooperation_server/msg/SceneArray"}))
        .await;
    let mut asking = status(1, true, 20.0);
    asking["requested"] = json!(true);
    module.sync("intersection", vec![asking]).await;
    // The module says go, its policy is optional, but it asked: the vehicle waits (deactivate).
    let waiting = until(&mut operator, 1, |s| s["awaits_operator"] == true).await;
    assert_eq!(waiting["merged"]["decision"], 1, "{waiting}");
    assert_eq!(waiting["requested"], true, "{waiting}");
    assert_eq!(waiting["policy"], 2, "{waiting}");
    // It ages while the module is silent.
    let aged = until(&mut operator, 1, |s| s["age_ms"].as_u64() >= Some(200)).await;
    assert_eq!(aged["awaits_operator"], true, "{aged}");
    // The operator activates: merged activate, no longer waiting.
    operator.set_commands(&[(1, 2)]).await;
    let decided = until(&mut operator, 1, |s| s["awaits_operator"] == false).await;
    assert_eq!(decided["merged"]["decision"], 2, "{decided}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_module_sends_only_the_fields_it_owns() {
    let served = serve(Options::default()).await;
    let mut module = Client::connect(&served.url).await;
    let owned = json!({"uuid": uuid(1), "safe": true, "state": {"type": 0},
                       "start_distance": 10.0, "finish_distance": 20.0});
    let values = module.sync("intersection", vec![owned]).await;
    assert_eq!(values["success"], true, "{values}");
    // A field the module owns is not optional: its absence is named.
    let missing = json!({"uuid": uuid(2), "state": {"type": 0},
                         "start_distance": 10.0, "finish_distance": 20.0});
    let values = module.sync("intersection", vec![missing]).await;
    assert_eq!(values["success"], false, "{values}");
    assert!(
        values["message"]
            .as_str()
            .is_some_and(|m| m.contains("safe")),
        "{values}"
    );
}
