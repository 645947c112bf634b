//! One client's heavy requests beside another's light ones: `get_policies` round trips from one
//! client while another sends `/cooperation/rtc/sync` requests of [`HEAVY_ENTRIES`] statuses
//! back to back, against the same round trips on the otherwise idle node, in the same run.

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use tokio::sync::Barrier;
use tokio_tungstenite::tungstenite::Message;

use super::{on_own_runtime, operator, sync_args, Ask, Summary, Until, INTERFACES};

/// The statuses of each heavy request (on one interface: those over its quota are refused,
/// each one read and answered).
pub(super) const HEAVY_ENTRIES: usize = 1_024;
/// The `get_policies` round trips timed, idle and beside the heavy client.
const ROUND_TRIPS: usize = 2_000;

/// The light client's round trips idle and beside the heavy client, and the heavy requests'.
pub(super) struct Fairness {
    pub(super) idle: Summary,
    pub(super) beside: Summary,
    pub(super) heavy: Summary,
}

/// `get_policies` round trips from a client on a thread and runtime of its own, so that it
/// does not wait behind the heavy client's task on the client side.
fn light(address: SocketAddr) -> Result<Vec<Duration>, String> {
    on_own_runtime(operator(
        address,
        Ask::GetPolicies,
        (0, 1),
        ROUND_TRIPS,
        Arc::new(Barrier::new(1)),
        Until::new(),
    ))
}

/// Sends heavy syncs back to back until `until`; each one's round trip.
async fn heavy(address: SocketAddr, until: Until) -> Result<Vec<Duration>, String> {
    let (mut socket, _) = tokio_tungstenite::connect_async(format!("ws://{address}/"))
        .await
        .map_err(|error| format!("the heavy client: {error}"))?;
    let args = sync_args(INTERFACES[0], 0..HEAVY_ENTRIES);
    let mut latencies = Vec::new();
    for request in 0.. {
        if until.reached() {
            break;
        }
        let id = format!("\"id\":\"h{request}\"");
        let frame = format!(
            "{{\"op\":\"call_service\",{id},\"service\":\"/cooperation/rtc/sync\",\"args\":{args}}}"
        );
        let sent = Instant::now();
        socket
            .send(Message::text(frame))
            .await
            .map_err(|error| format!("the heavy client: {error}"))?;
        loop {
            match socket.next().await {
                Some(Ok(Message::Text(response))) if response.contains(&id) => {
                    if !response.contains("\"result\":true") {
                        return Err(format!(
                            "the heavy client: an unexpected answer: {response}"
                        ));
                    }
                    break;
                }
                Some(Ok(_)) => {}
                Some(Err(error)) => return Err(format!("the heavy client: {error}")),
                None => return Err("the heavy client: the server closed".to_owned()),
            }
        }
        latencies.push(sent.elapsed());
    }
    let _closed = socket.close(None).await;
    Ok(latencies)
}

/// The light client alone, then beside the heavy one.
pub(super) fn fairness(
    clients: &tokio::runtime::Runtime,
    address: SocketAddr,
) -> Result<Fairness, String> {
    let idle = light(address)?;
    let (beside, heavy) = clients.block_on(async {
        let until = Until::new();
        let heavy = tokio::spawn(heavy(address, until.clone()));
        // The heavy client is under way before the light one starts.
        tokio::time::sleep(Duration::from_millis(200)).await;
        let beside = tokio::task::spawn_blocking(move || light(address))
            .await
            .map_err(|error| error.to_string())?;
        until.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        let heavy = heavy.await.map_err(|error| error.to_string())?;
        Ok::<_, String>((beside?, heavy?))
    })?;
    Ok(Fairness {
        idle: Summary::of(idle),
        beside: Summary::of(beside),
        heavy: Summary::of(heavy),
    })
}
