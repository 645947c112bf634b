//! The command and the publication in process, against their parts.

use super::*;

/// A `publish` frame as the node writes one, for timing the serialization alone.
#[derive(Serialize)]
struct Publish<'a, M> {
    op: &'static str,
    topic: &'static str,
    msg: &'a M,
}

/// The in-process measurements, by name.
pub(super) struct InProcess {
    names: Vec<&'static str>,
    samples: Vec<Vec<Duration>>,
}

/// Times each of `work` `PER_ROUND` times a round for `ROUNDS` rounds, interleaved.
fn interleaved(work: &mut [(&'static str, &mut dyn FnMut(usize))]) -> InProcess {
    let mut samples = vec![Vec::with_capacity(ROUNDS * PER_ROUND); work.len()];
    let mut iteration = 0;
    for _ in 0..ROUNDS {
        for ((_, run), out) in work.iter_mut().zip(samples.iter_mut()) {
            for _ in 0..PER_ROUND {
                let began = Instant::now();
                run(iteration);
                out.push(began.elapsed());
                iteration += 1;
            }
        }
    }
    InProcess {
        names: work.iter().map(|(name, _)| *name).collect(),
        samples,
    }
}

impl InProcess {
    pub(super) fn summary(&self, name: &str) -> Summary {
        self.names
            .iter()
            .position(|known| *known == name)
            .map_or_else(
                || Summary::of(Vec::new()),
                |at| Summary::of(self.samples[at].clone()),
            )
    }
}

pub(super) const CALL: &str = "Node::handle(SetCommands): JSON, engine, response, publication";
pub(super) const JSON_SERVICE: &str = "JSON service alone (read, engine under the lock, write)";
pub(super) const CORE_COMMAND: &str = "core alone (one SetCommands input under the lock)";
pub(super) const PUBLISH: &str =
    "a publication (Node::publish when one is due): the engine's messages, three frames serialized";
pub(super) const CONVERT: &str = "core query + conversion to AD API messages (under the lock)";
pub(super) const QUERY: &str = "core query alone (velocity_ + steering_factors_into)";
pub(super) const QUERY_KEYED: &str = "core query, keyed form (factors_into)";
pub(super) const SERIALIZE: &str = "serialization alone (two publish frames)";

pub(super) fn in_process(node: &Node) -> InProcess {
    let args: Vec<Vec<u8>> = (0..2 * SCENES)
        .map(|index| command_args(index, decision(index / SCENES)).into_bytes())
        .collect();
    let commands: Vec<Command> = (0..2 * SCENES)
        .map(|index| Command {
            id: SceneId::from_bytes(uuid(index % SCENES)),
            decision: if index < SCENES {
                OperatorDecision::Activate
            } else {
                OperatorDecision::Deactivate
            },
        })
        .collect();
    let stamp = node.clock().stamp();
    let (velocity, steering) = node
        .shared()
        .expect("a node over its own engine")
        .read(|host| {
            (
                wire::velocity_factors(host.state(), stamp),
                wire::steering_factors(host.state(), stamp),
            )
        });
    let (mut velocity_out, mut steering_out) = (Vec::new(), Vec::new());
    let mut lists = FactorLists::default();
    // What a connection does for a call: read the request, answer it under the lock, write
    // the response, and publish the change.
    let mut call = |i: usize| {
        let request = Endpoint::Ad(Service::SetCommands).read_json(&args[i % args.len()]);
        let (reply, revision) = node.handle(request);
        black_box(wire::to_json(&reply));
        if revision.is_some() {
            node.publish();
        }
    };
    let mut json_service = |i: usize| {
        let request = Endpoint::Ad(Service::SetCommands).read_json(&args[i % args.len()]);
        let now = node.clock().now();
        let handled = node
            .shared()
            .expect("a node over its own engine")
            .update(|engine| engine.handle(request, now));
        black_box(wire::to_json(&handled.reply));
    };
    // The core alone, behind a lock of its own: a copy of the node's.
    let core_alone = std::sync::Mutex::new(
        node.shared()
            .expect("a node over its own engine")
            .read(|engine| engine.state().clone()),
    );
    let mut core = |i: usize| {
        let commands = vec![commands[i % commands.len()]];
        let mut state = core_alone
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        black_box(state.apply(&Input::SetCommands { commands })).ok();
    };
    // What `Node::publish` does when the engine says a publication is due (here it would say
    // none is: nothing changes between iterations).
    let mut publish = |_: usize| {
        let stamp = node.clock().stamp();
        let publication = node
            .shared()
            .expect("a node over its own engine")
            .read(|engine| engine.publication(stamp));
        let _frames = black_box([
            serde_json::to_string(&Publish {
                op: "publish",
                topic: Topic::Velocity.name(),
                msg: &publication.velocity,
            }),
            serde_json::to_string(&Publish {
                op: "publish",
                topic: Topic::Steering.name(),
                msg: &publication.steering,
            }),
            serde_json::to_string(&Publish {
                op: "publish",
                topic: Topic::Scenes.name(),
                msg: &publication.scenes,
            }),
        ]);
    };
    let mut convert = |_: usize| {
        let stamp = node.clock().stamp();
        black_box(
            node.shared()
                .expect("a node over its own engine")
                .read(|host| {
                    (
                        wire::velocity_factors(host.state(), stamp),
                        wire::steering_factors(host.state(), stamp),
                    )
                }),
        );
    };
    let mut query = |_: usize| {
        node.shared()
            .expect("a node over its own engine")
            .read(|host| {
                host.state().velocity_factors_into(&mut velocity_out);
                host.state().steering_factors_into(&mut steering_out);
            });
        black_box((&velocity_out, &steering_out));
    };
    let mut query_keyed = |_: usize| {
        node.shared()
            .expect("a node over its own engine")
            .read(|host| host.state().factors_into(&mut lists));
        black_box(&lists);
    };
    let mut serialize = |_: usize| {
        let frames = (
            serde_json::to_string(&Publish {
                op: "publish",
                topic: Topic::Velocity.name(),
                msg: &velocity,
            }),
            serde_json::to_string(&Publish {
                op: "publish",
                topic: Topic::Steering.name(),
                msg: &steering,
            }),
        );
        black_box(&frames);
    };
    interleaved(&mut [
        (CALL, &mut call),
        (JSON_SERVICE, &mut json_service),
        (CORE_COMMAND, &mut core),
        (PUBLISH, &mut publish),
        (CONVERT, &mut convert),
        (QUERY, &mut query),
        (QUERY_KEYED, &mut query_keyed),
        (SERIALIZE, &mut serialize),
    ])
}
