//! Credentials and roles (`docs/server.md`, *Who may connect*): a node with credentials lets in
//! only a client that presents one, lets each do what its role may, and keeps each
//! credential's places for it.

use crate::common::{serve, status, Client};
use cooperation_server::{Credentials, Options};
use serde_json::json;

const OPERATOR: &str = "operator-token-0123456789abcdef";
const MODULE: &str = "module-token-0123456789abcdefgh";
const FILE: &str = "# who may connect\n\
    operator panel operator-token-0123456789abcdef\n\
    module   lanes module-token-0123456789abcdefgh lane_change_left\n";

fn credentials(places: usize) -> Credentials {
    Credentials::parse(FILE, &["lane_change_left", "lane_change_right"], places)
        .expect("the credentials read")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_client_without_a_known_credential_is_refused_before_its_websocket_opens() {
    let served = serve(Options {
        credentials: Some(credentials(4)),
        ..Options::default()
    })
    .await;
    assert_eq!(Client::connect_as(&served.url, None).await.err(), Some(401));
    let wrong = format!("{OPERATOR}x");
    assert_eq!(
        Client::connect_as(&served.url, Some(&wrong)).await.err(),
        Some(401)
    );
    let query = format!("{}?token={}", served.url, &OPERATOR[1..]);
    assert_eq!(Client::connect_as(&query, None).await.err(), Some(401));
    // The token in the URL, as a browser sends it, or in the header.
    let query = format!("{}?token={OPERATOR}", served.url);
    assert!(Client::connect_as(&query, None).await.is_ok());
    assert!(Client::connect_as(&served.url, Some(MODULE)).await.is_ok());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_role_does_what_it_may_and_is_refused_the_rest() {
    let served = serve(Options {
        credentials: Some(credentials(4)),
        ..Options::default()
    })
    .await;
    let mut module = Client::connect_as(&served.url, Some(MODULE))
        .await
        .expect("in");
    let mut operator = Client::connect_as(&served.url, Some(OPERATOR))
        .await
        .expect("in");

    // The module reports for its interface, and only for it.
    let values = module
        .sync("lane_change_left", vec![status(1, false, 20.0)])
        .await;
    assert_eq!(values["success"], true, "{values}");
    let values = module
        .sync("lane_change_right", vec![status(2, true, 20.0)])
        .await;
    assert_eq!(values["success"], false, "{values}");
    assert!(
        values["message"].as_str().is_some_and(|m| m.contains(
            "credential \"lanes\" may report for lane_change_left, not for \"lane_change_right\""
        )),
        "{values}"
    );
    // It may read the policies, not change them, nor command a scene.
    let read = module
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(read["values"]["status"]["success"], true, "{read}");
    for (service, args) in [
        (
            "/api/planning/cooperation/set_commands",
            json!({"commands": []}),
        ),
        (
            "/api/planning/cooperation/set_policies",
            json!({"policies": []}),
        ),
    ] {
        let refused = module.call(service, args).await;
        assert_eq!(refused["result"], false, "{refused}");
        assert!(
            refused["values"]
                .as_str()
                .is_some_and(|m| m.contains("is the operator's")),
            "{refused}"
        );
    }

    // The operator commands the module's scene, and may not report as a module.
    let answer = operator.set_commands(&[(1, 2)]).await;
    assert_eq!(answer["values"]["status"]["success"], true, "{answer}");
    let refused = operator
        .call(
            "/cooperation/rtc/sync",
            json!({"interface": "lane_change_left", "statuses": [status(1, true, 10.0)]}),
        )
        .await;
    assert_eq!(refused["result"], false, "{refused}");
    // Nothing the refused calls asked changed: the scene is as the module and operator left it.
    let values = module
        .sync("lane_change_left", vec![status(1, false, 20.0)])
        .await;
    assert_eq!(
        values["activations"][0]["force_activated"], true,
        "{values}"
    );
    assert_eq!(
        values["statuses"]["statuses"].as_array().map(Vec::len),
        Some(1)
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn each_credential_keeps_its_places_whoever_else_connects() {
    let served = serve(Options {
        credentials: Some(credentials(2)),
        ..Options::default()
    })
    .await;
    // The module's places fill, and its next connection is refused ...
    let _first = Client::connect_as(&served.url, Some(MODULE))
        .await
        .expect("in");
    let _second = Client::connect_as(&served.url, Some(MODULE))
        .await
        .expect("in");
    assert_eq!(
        Client::connect_as(&served.url, Some(MODULE)).await.err(),
        Some(503)
    );
    // ... as are any number of clients without a credential, none of them holding a place ...
    for _ in 0..20 {
        assert_eq!(Client::connect_as(&served.url, None).await.err(), Some(401));
    }
    // ... and the operator still gets in.
    let mut operator = Client::connect_as(&served.url, Some(OPERATOR))
        .await
        .expect("in");
    let read = operator
        .call("/api/planning/cooperation/get_policies", json!({}))
        .await;
    assert_eq!(read["values"]["status"]["success"], true, "{read}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_auth_op_is_refused_with_where_a_credential_goes() {
    let served = serve(Options::default()).await;
    let mut client = Client::connect(&served.url).await;
    client
        .send(
            &json!({"op": "auth", "mac": "x", "client": "", "dest": "", "rand": "", "t": 0,
                      "level": "admin", "end": 0}),
        )
        .await;
    let status = client.next_op("status").await;
    assert!(
        status["msg"]
            .as_str()
            .is_some_and(|m| m.contains("Authorization: Bearer")),
        "{status}"
    );
}

/// The tokens docs/server.md shows are the ones the node refuses as examples, and the page
/// says so.
#[test]
fn the_documented_example_tokens_are_refused() {
    let page = include_str!("../../docs/server.md");
    for token in cooperation_server::auth::EXAMPLE_TOKENS {
        assert!(page.contains(token), "{token} is not on the page");
        let error =
            Credentials::parse(&format!("operator panel {token}"), &["lane_change_left"], 4)
                .expect_err(token);
        assert!(error.to_string().contains("an example"), "{error}");
    }
    assert!(page.contains("The tokens above are examples: the node refuses them"));
    assert!(page.contains("openssl rand -hex 24"));
}
