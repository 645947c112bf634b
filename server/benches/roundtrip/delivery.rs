//! One publication's delivery to 1 and 100 subscribers.

use super::*;

/// One subscriber: subscribes to both topics and reports every frame's arrival.
async fn subscriber(
    address: SocketAddr,
    index: usize,
    arrivals: mpsc::UnboundedSender<(usize, Topic, Instant)>,
) -> Result<(), String> {
    let url = format!("ws://{address}/");
    let (mut socket, _) = tokio_tungstenite::connect_async(url.as_str())
        .await
        .map_err(|error| format!("subscriber {index}: {error}"))?;
    for topic in Topic::ALL {
        let subscribe = format!(
            "{{\"op\":\"subscribe\",\"topic\":\"{}\",\"type\":\"{}\"}}",
            topic.name(),
            topic.type_name()
        );
        socket
            .send(Message::text(subscribe))
            .await
            .map_err(|error| format!("subscriber {index}: {error}"))?;
    }
    let velocity = format!(
        "{{\"op\":\"publish\",\"topic\":\"{}\"",
        Topic::Velocity.name()
    );
    while let Some(received) = socket.next().await {
        let Ok(Message::Text(text)) = received else {
            break;
        };
        let at = Instant::now();
        let topic = if text.starts_with(velocity.as_str()) {
            Topic::Velocity
        } else {
            Topic::Steering
        };
        if arrivals.send((index, topic, at)).is_err() {
            break;
        }
    }
    Ok(())
}

/// Waits until each of `count` subscribers has received a frame of each topic; answers when
/// each arrived (the later one if a topic arrived twice).
async fn both_frames(
    arrived: &mut mpsc::UnboundedReceiver<(usize, Topic, Instant)>,
    count: usize,
) -> Result<Vec<[Option<Instant>; 2]>, String> {
    let mut last = vec![[None::<Instant>; 2]; count];
    let mut missing = 2 * count;
    while missing > 0 {
        let Some((index, topic, at)) = arrived.recv().await else {
            return Err("a subscriber stopped".to_owned());
        };
        let slot = &mut last[index][usize::from(topic == Topic::Steering)];
        if slot.is_none() {
            missing -= 1;
        }
        *slot = Some(at);
    }
    Ok(last)
}

/// Delivery with `count` subscribers over `rounds` publications: each subscriber's time to
/// both frames, and each round's time to the last subscriber's.
pub(super) async fn delivery(
    address: SocketAddr,
    node: &Node,
    count: usize,
    rounds: usize,
) -> Result<(Summary, Summary), String> {
    let (arrivals, mut arrived) = mpsc::unbounded_channel();
    let tasks: Vec<_> = (0..count)
        .map(|index| tokio::spawn(subscriber(address, index, arrivals.clone())))
        .collect();
    drop(arrivals);
    // A new subscriber is sent the newest publication of each topic at once.
    tokio::time::timeout(CASE_DEADLINE, both_frames(&mut arrived, count))
        .await
        .map_err(|_| "subscribers did not receive the first publications".to_owned())??;
    let mut each = Vec::with_capacity(count * rounds);
    let mut all = Vec::with_capacity(rounds);
    let deadline = Instant::now() + CASE_DEADLINE;
    for round in 0..rounds {
        if Instant::now() > deadline {
            break;
        }
        // A change the streams show, straight to the engine (no publishing task is asked), so
        // that the engine has a publication due for `Node::publish` to send: the first scene's
        // decision, set to whichever of the two it does not have.
        let now = node.clock().now();
        node.shared()
            .expect("a node over its own engine")
            .update(|engine| {
                for pass in [round, round + 1] {
                    let request = Endpoint::Ad(Service::SetCommands)
                        .read_json(command_args(0, decision(pass)).as_bytes());
                    if engine.handle(request, now).change.publish {
                        break;
                    }
                }
            });
        let began = Instant::now();
        node.publish();
        let last = tokio::time::timeout(CASE_DEADLINE, both_frames(&mut arrived, count))
            .await
            .map_err(|_| "a publication was not delivered".to_owned())??;
        let mut slowest = Duration::ZERO;
        for both in last {
            let received = both.iter().flatten().max().copied().unwrap_or(began);
            let took = received.duration_since(began);
            slowest = slowest.max(took);
            each.push(took);
        }
        all.push(slowest);
    }
    for task in tasks {
        task.abort();
    }
    Ok((Summary::of(each), Summary::of(all)))
}
