//! Credentials reloaded while the node runs (`docs/server.md`, *Who may connect*): a credential
//! dropped or changed is revoked at once, its connections closed and its token refused; an
//! unchanged one keeps its connections; a new one is let in.

use std::time::Duration;

use crate::common::{serve_reloading, status, Client, SETTINGS};
use cooperation_server::{Credentials, Node, Options};
use serde_json::json;

const OPERATOR: &str = "operator-token-0123456789abcdef";
const SECOND: &str = "second-operator-token-0123456789";
const MODULE: &str = "module-token-0123456789abcdefgh";
const INTERFACES: [&str; 2] = ["lane_change_left", "lane_change_right"];

fn credentials(text: &str) -> Credentials {
    Credentials::parse(text, &INTERFACES, 2).expect("the credentials read")
}

/// Whether the client's connection is closed within a second (publications skipped).
async fn closed(client: &mut Client) -> bool {
    tokio::time::timeout(Duration::from_secs(1), async {
        while client.next().await.is_some() {}
    })
    .await
    .is_ok()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_reload_revokes_what_it_drops_or_changes_and_keeps_the_rest() {
    let config = cooperation_adapters::settings::parse(SETTINGS).expect("the default settings");
    let node = std::sync::Arc::new(
        Node::with_scene_quota(config, cooperation_server::node::SCENE_QUOTA).expect("a node"),
    );
    let (reload, reloads) = tokio::sync::mpsc::unbounded_channel();
    let served = serve_reloading(
        node,
        Options {
            credentials: Some(credentials(&format!(
                "operator panel {OPERATOR}\nmodule lanes {MODULE} lane_change_left\n"
            ))),
            ..Options::default()
        },
        tokio_stream_of(reloads),
    )
    .await;
    let url = served.url.as_str();
    let mut operator = Client::connect_as(url, Some(OPERATOR)).await.expect("in");
    let mut module = Client::connect_as(url, Some(MODULE)).await.expect("in");
    assert_eq!(Client::connect_as(url, Some(SECOND)).await.err(), Some(401));

    // The operator's credential dropped, another added, the module's unchanged.
    reload
        .send(credentials(&format!(
            "operator second {SECOND}\nmodule lanes {MODULE} lane_change_left\n"
        )))
        .expect("sent");
    assert!(
        closed(&mut operator).await,
        "a revoked credential's connection stays open"
    );
    assert_eq!(
        Client::connect_as(url, Some(OPERATOR)).await.err(),
        Some(401)
    );
    let mut second = Client::connect_as(url, Some(SECOND)).await.expect("in");
    let read = second
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(read["values"]["status"]["success"], true, "{read}");
    // The module kept its connection, and its places: one more, then full.
    let values = module
        .sync("lane_change_left", vec![status(1, true, 20.0)])
        .await;
    assert_eq!(values["success"], true, "{values}");
    let _another = Client::connect_as(url, Some(MODULE)).await.expect("in");
    assert_eq!(Client::connect_as(url, Some(MODULE)).await.err(), Some(503));

    // The module's interfaces changed: a changed credential is revoked too, and its token now
    // lets in a connection with the new grant.
    reload
        .send(credentials(&format!(
            "operator second {SECOND}\nmodule lanes {MODULE} lane_change_right\n"
        )))
        .expect("sent");
    assert!(
        closed(&mut module).await,
        "a changed credential's connection stays open"
    );
    let mut module = Client::connect_as(url, Some(MODULE)).await.expect("in");
    let values = module
        .sync("lane_change_left", vec![status(2, true, 20.0)])
        .await;
    assert_eq!(values["success"], false, "{values}");
    let values = module
        .sync("lane_change_right", vec![status(2, true, 20.0)])
        .await;
    assert_eq!(values["success"], true, "{values}");
    // The operator that stayed, stays.
    let read = second
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(read["values"]["status"]["success"], true, "{read}");
}

/// The credentials an unbounded channel yields, as a stream.
fn tokio_stream_of(
    mut reloads: tokio::sync::mpsc::UnboundedReceiver<Credentials>,
) -> impl futures_util::Stream<Item = Credentials> + Send + 'static {
    futures_util::stream::poll_fn(move |context| reloads.poll_recv(context))
}
