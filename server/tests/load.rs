//! Load (`docs/server.md`, *Limits and faults*): 100 operator clients at once while planning
//! modules keep 500 scenes live, each updated at 10 Hz. Every call is answered, every batch
//! is applied, and each operator sees its command in the first publication after the answer.

use std::time::{Duration, Instant};

use crate::common::{operator_decision, serve, status, Client};
use cooperation_server::Options;

/// Five velocity interfaces with 100 scenes each.
const INTERFACES: [&str; 5] = [
    "intersection",
    "crosswalk",
    "blind_spot",
    "traffic_light",
    "roundabout",
];
const PER_INTERFACE: u128 = 100;
const OPERATORS: u128 = 100;
const COMMANDS_PER_OPERATOR: u8 = 6;
/// Each module's updates of all its scenes, 100 ms apart.
const CYCLES: u32 = 20;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_hundred_operators_and_500_scenes_at_10_hz() {
    let served = serve(Options::default()).await;
    let scene = |interface: usize, n: u128| (interface as u128) * PER_INTERFACE + n + 1;

    // The modules: each registers its scenes, then re-reports all of them every 100 ms, 20
    // times (2 s), while the operators work.
    let mut modules = Vec::new();
    for (index, interface) in INTERFACES.into_iter().enumerate() {
        let mut client = Client::connect(&served.url).await;
        let statuses = move |cycle: u32| -> Vec<_> {
            (0..PER_INTERFACE)
                .map(|n| status(scene(index, n), true, 5.0 + n as f32 + cycle as f32 * 0.01))
                .collect()
        };
        let synced = client.sync(interface, statuses(0)).await;
        assert_eq!(synced["success"], true, "{interface}");
        modules.push(tokio::spawn(async move {
            let mut next = Instant::now();
            for cycles in 1..=CYCLES {
                next += Duration::from_millis(100);
                tokio::time::sleep_until(next.into()).await;
                let synced = client.sync(interface, statuses(cycles)).await;
                assert_eq!(
                    synced["success"], true,
                    "{interface} cycle {cycles}: {synced}"
                );
                assert_eq!(synced["activations"].as_array().map(Vec::len), Some(100));
            }
        }));
    }

    // The operators: each commands 5 scenes of its own, in turn, and checks the next
    // publication of the velocity factors shows the command.
    let mut operators = Vec::new();
    for operator in 0..OPERATORS {
        let url = served.url.clone();
        operators.push(tokio::spawn(async move {
            let mut client = Client::connect(&url).await;
            client.subscribe("/api/planning/velocity_factors").await;
            for round in 0..COMMANDS_PER_OPERATOR {
                let n = operator * 5 + u128::from(round % 5) + 1;
                let decision = 1 + round % 3;
                let response = client.set_commands(&[(n, decision)]).await;
                assert_eq!(response["values"]["status"]["success"], true, "{response}");
                let publication = client.next_op("publish").await;
                assert_eq!(
                    operator_decision(&publication, n),
                    Some(u64::from(decision)),
                    "operator {operator}, scene {n}"
                );
            }
        }));
    }
    for operator in operators {
        operator
            .await
            .expect("every operator's commands were answered and published");
    }
    for module in modules {
        module.await.expect("every module's syncs were answered");
    }
    // Still serving.
    let mut late = Client::connect(&served.url).await;
    let response = late.set_commands(&[(1, 3)]).await;
    assert_eq!(response["values"]["status"]["success"], true, "{response}");
    served
        .node
        .shared()
        .expect("a node over its own engine")
        .read(|host| assert_eq!(host.state().scenes().count(), 500));
}
