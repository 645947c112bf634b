//! The stack mode: the AD API over the planning modules of a stock Autoware stack.
//!
//! Beside an unmodified stack the planning modules keep their own RTC interfaces. The stack
//! node reads each interface's `/planning/cooperate_status/<name>` and
//! `/planning/auto_mode_status/<name>`, calls its `/planning/cooperate_commands/<name>` and
//! `/planning/enable_auto_mode/<name>`, and serves the AD API's cooperation services and factor
//! topics; what each message means is [`Relay`]'s to decide (spec §6.8). The node owns its
//! relay: one thread polls every entity, so nothing is shared and nothing is locked. Another
//! door of the same process (`cooperation-server --stack`: the rosbridge WebSocket and the
//! operator panel) reaches the relay through a [`Door`]: its calls are answered as the DDS
//! clients' are, and it is shown every publication DDS gets.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use cooperation_adapters::clock::Clock;
use cooperation_adapters::dds::{Endpoint, RequestHeader};
use cooperation_adapters::engine::{Engine, Now, Publication, Reply, Request};
use cooperation_adapters::refusals::Refusals;
use cooperation_adapters::relay::{self, factors, ModuleAnswer, OperatorCall, Relay};
use cooperation_adapters::wire::{self, Service};
use rustdds::mio1::{Events, Interest, Poll, Token, Waker};
use rustdds::{DomainParticipant, RTPSEntity};

use crate::entities::{refusal_log, refused, sum_up, wait, Factors, Participant, Replies, Server};
use crate::module::{Heard, Module};
use crate::raw::{Raw, RawAdapter};
use crate::Options;

/// The first poll token of the modules' readers (the servers take the ones below).
const MODULE_TOKENS: usize = 1_000;

/// The poll tokens of the stack's factor readers.
const INPUT_TOKENS: usize = 900;

/// The poll token of the [`Door`]'s waker.
const DOOR_TOKEN: usize = 899;

/// An operator's call the modules have not all answered yet: where its reply goes.
enum Awaiting {
    /// A DDS client of server `server`.
    Dds {
        server: usize,
        client: [u8; 12],
        header: RequestHeader,
    },
    /// A call through the [`Door`].
    Door(mpsc::Sender<Reply>),
}

/// A call through a [`Door`], and where its reply goes.
pub type DoorCall = (Request, mpsc::Sender<Reply>);

/// Another door of the process onto the stack's relay: its operators' calls, answered as the
/// DDS clients' are (a call the modules must answer first is answered when they have, or their
/// deadline passed), and every publication DDS gets, shown to it before the replies of the
/// same turn are sent, so that a caller answered success is already shown its change.
pub struct Door {
    /// The door's calls; the node is woken for them by [`Stack::waker`].
    pub calls: mpsc::Receiver<DoorCall>,
    /// Shown each publication: the factors as DDS gets them (the stack's with the scenes'
    /// statuses), and the scenes.
    pub shown: Box<dyn FnMut(&Publication) + Send>,
}

/// The readers of the stack's own factors (`default_adapi`'s, remapped,
/// `[COOP-RELAY-FACTORS.1]`).
struct Input {
    velocity_reader: rustdds::no_key::DataReader<Raw, RawAdapter>,
    steering_reader: rustdds::no_key::DataReader<Raw, RawAdapter>,
}

impl Input {
    fn open(participant: &Participant, poll: &Poll) -> Result<Self, String> {
        let qos = crate::entities::qos(rustdds::policy::Durability::Volatile, 1);
        let type_name = |name| cooperation_adapters::dds::type_name(name, "");
        let mut velocity_reader = participant.reader(
            &cooperation_adapters::dds::topic(factors::VELOCITY_INPUT),
            &type_name(wire::VELOCITY_FACTORS_TYPE),
            &qos,
        )?;
        let mut steering_reader = participant.reader(
            &cooperation_adapters::dds::topic(factors::STEERING_INPUT),
            &type_name(wire::STEERING_FACTORS_TYPE),
            &qos,
        )?;
        for (reader, token) in [
            (&mut velocity_reader, INPUT_TOKENS),
            (&mut steering_reader, INPUT_TOKENS + 1),
        ] {
            poll.registry()
                .register(reader, Token(token), Interest::READABLE)
                .map_err(|error| format!("poll: {error}"))?;
        }
        Ok(Self {
            velocity_reader,
            steering_reader,
        })
    }

    /// Gives `stream` the newest array of each topic that came.
    fn take(&mut self, stream: &mut factors::Stream, now: Now, refusals: &Refusals) {
        let velocity = newest(&mut self.velocity_reader, factors::VELOCITY_INPUT, refusals);
        if let Some(array) = velocity {
            stream.take_velocity(array, now);
        }
        let steering = newest(&mut self.steering_reader, factors::STEERING_INPUT, refusals);
        if let Some(array) = steering {
            stream.take_steering(array, now);
        }
    }
}

/// The newest message of `reader` that reads; one that does not is logged through `refusals`
/// and dropped.
fn newest<T: serde::de::DeserializeOwned>(
    reader: &mut rustdds::no_key::DataReader<Raw, RawAdapter>,
    topic: &str,
    refusals: &Refusals,
) -> Option<T> {
    let mut newest = None;
    loop {
        match reader.take_next_sample() {
            Ok(Some(sample)) => match cooperation_adapters::cdr::from_slice(&sample.into_value().0)
            {
                Ok(message) => newest = Some(message),
                Err(error) => refused(
                    refusals,
                    topic,
                    "a message that does not read dropped",
                    &error,
                ),
            },
            Ok(None) => return newest,
            Err(error) => {
                tracing::warn!(topic, %error, "not read");
                return newest;
            }
        }
    }
}

/// The stack node.
pub struct Stack {
    relay: Relay,
    clock: Clock,
    options: Options,
    poll: Poll,
    servers: Vec<Server>,
    modules: Vec<Module>,
    factors: Factors,
    input: Input,
    /// The one factor stream: what to publish, and when.
    stream: factors::Stream,
    replies: Replies,
    awaiting: BTreeMap<OperatorCall, Awaiting>,
    next_operator: u64,
    door: Option<Door>,
    /// The door's replies of this turn, sent after its publication.
    door_replies: Vec<(mpsc::Sender<Reply>, Reply)>,
    waker: Arc<Waker>,
    /// The interfaces whose status arrays are refused: the kind of reason last logged, and how
    /// many were refused for it since.
    refusing: BTreeMap<String, (std::mem::Discriminant<relay::ArrayError>, u64)>,
    /// The log of what the modules and the operators' clients send that is refused.
    refusals: Refusals,
    /// Kept for the life of the node: the graph's sample is transient-local.
    _graph: rustdds::no_key::DataWriter<Raw, RawAdapter>,
    /// Kept last: the entities above belong to it.
    _participant: DomainParticipant,
}

impl core::fmt::Debug for Stack {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Stack")
            .field("options", &self.options)
            .field("modules", &self.modules.len())
            .field("awaiting", &self.awaiting.len())
            .finish_non_exhaustive()
    }
}

impl Stack {
    /// A stack node over a new engine built from the settings file at `settings` (the built-in
    /// settings for `None`) and `options` ([`Engine::from_settings`]): the AD API's services
    /// and factor topics, and the endpoints of every RTC interface the core binds, each module
    /// given `deadline` to answer.
    ///
    /// # Errors
    /// The settings' or the core's refusal of the configuration, or what DDS could not create.
    pub fn new(
        settings: Option<&std::path::Path>,
        options: Options,
        deadline: Duration,
    ) -> Result<Self, String> {
        let engine =
            Engine::from_settings(settings, options.engine()).map_err(|error| error.to_string())?;
        let relay = Relay::new(
            engine,
            u64::try_from(deadline.as_millis()).unwrap_or(u64::MAX),
        );
        let joined = Participant::join(options.domain, &options.interfaces)?;
        let factors = Factors::open(&joined)?;
        let poll = Poll::new().map_err(|error| format!("poll: {error}"))?;
        let input = Input::open(&joined, &poll)?;
        let servers = Service::ALL
            .into_iter()
            .enumerate()
            .map(|(index, service)| Server::open(&joined, &poll, Endpoint::Ad(service), index))
            .collect::<Result<Vec<_>, _>>()?;
        // The clients' identifiers: unique in the domain as the participant's GUID prefix is.
        let prefix = joined.participant.guid().to_bytes();
        let base = prefix
            .get(4..12)
            .and_then(|bytes| bytes.try_into().ok())
            .map_or(1, u64::from_le_bytes)
            & !0xFFFF;
        let names: Vec<String> = relay
            .engine()
            .host()
            .rtc()
            .bindings()
            .iter()
            .map(|binding| binding.name.clone())
            .collect();
        let modules = names
            .iter()
            .enumerate()
            .map(|(index, name)| {
                Module::open(
                    &joined,
                    &poll,
                    name,
                    MODULE_TOKENS + 4 * index,
                    base + 2 * u64::try_from(index).unwrap_or(0) + 2,
                )
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut readers = vec![input.velocity_reader.guid(), input.steering_reader.guid()];
        let mut writers = Vec::new();
        for module in &modules {
            let (module_readers, module_writers) = module.guids();
            readers.extend(module_readers);
            writers.extend(module_writers);
        }
        let graph = joined.announce(&options, &servers, &factors, readers, writers)?;
        let waker = Waker::new(poll.registry(), Token(DOOR_TOKEN))
            .map_err(|error| format!("poll: {error}"))?;
        Ok(Self {
            relay,
            clock: Clock::start(),
            options,
            poll,
            servers,
            modules,
            factors,
            input,
            stream: factors::Stream::default(),
            replies: Replies::default(),
            awaiting: BTreeMap::new(),
            next_operator: 0,
            door: None,
            door_replies: Vec::new(),
            waker: Arc::new(waker),
            refusing: BTreeMap::new(),
            refusals: refusal_log(),
            _graph: graph,
            _participant: joined.participant,
        })
    }

    /// Wakes the node: for a call sent through its [`Door`].
    #[must_use]
    pub fn waker(&self) -> Arc<Waker> {
        Arc::clone(&self.waker)
    }

    /// Opens `door` (it replaces a door opened before), showing it the scenes as they stand.
    pub fn open_door(&mut self, mut door: Door) {
        (door.shown)(&self.relay.engine().publication(self.clock.stamp()));
        self.door = Some(door);
    }

    /// The names of the interfaces it relays.
    pub fn interfaces(&self) -> impl Iterator<Item = &str> {
        self.modules.iter().map(|module| module.endpoints.name())
    }

    /// Serves until `stop` is set (seen within 100 ms).
    ///
    /// # Errors
    /// The poll failed.
    pub fn run(&mut self, stop: &AtomicBool) -> Result<(), String> {
        let mut events = Events::with_capacity(256);
        while !stop.load(Ordering::Relaxed) {
            let now = self.clock.now();
            let until_timeout = Duration::from_millis(
                self.relay
                    .until_timeout_ms(now)
                    .min(self.stream.until_stale_ms(now)),
            );
            let busy = !self.replies.is_empty();
            wait(&mut self.poll, &mut events, busy, until_timeout)?;
            self.step();
        }
        if let Some(summary) = self.refusals.end_period() {
            tracing::warn!("{summary}");
        }
        Ok(())
    }

    /// One turn: time, what the modules said, the operators' calls, the calls to modules, the
    /// operators' answers, the replies due and the publications.
    fn step(&mut self) {
        let now = self.clock.now();
        sum_up(&self.refusals, now.reading_ns);
        self.relay.handle_timeout(now);
        for server in &mut self.servers {
            server.track_matches();
        }
        for index in 0..self.modules.len() {
            let Some(module) = self.modules.get_mut(index) else {
                continue;
            };
            let name = module.endpoints.name().to_owned();
            for heard in module.heard(&self.refusals) {
                self.hear(&name, heard, now);
            }
        }
        for index in 0..self.servers.len() {
            self.serve(index);
        }
        self.serve_door();
        while let Some(forward) = self.relay.poll_forward(now) {
            match self
                .modules
                .iter_mut()
                .find(|module| module.endpoints.name() == forward.interface)
            {
                Some(module) => {
                    module.send(forward.call, &forward.request);
                }
                None => tracing::error!(interface = %forward.interface, "a call to no module"),
            }
        }
        while let Some((call, response)) = self.relay.poll_answer() {
            if let Some(to) = self.awaiting.remove(&call) {
                self.deliver(to, Reply::Ad(response));
            }
        }
        self.replies.flush(&self.servers);
        self.publish(now);
        for (to, reply) in self.door_replies.drain(..) {
            // A caller that stopped waiting dropped its receiver: nothing to tell.
            let _gone = to.send(reply);
        }
    }

    /// Takes every call waiting at the door.
    fn serve_door(&mut self) {
        while let Some((request, reply)) = self
            .door
            .as_ref()
            .and_then(|door| door.calls.try_recv().ok())
        {
            self.take(request, Awaiting::Door(reply));
        }
    }

    /// Takes one request: answered at once, or once its modules answer; the answer goes `to`.
    fn take(&mut self, request: Request, to: Awaiting) {
        let endpoint = request.endpoint();
        match request {
            Request::Ad(request) => {
                let call = OperatorCall(self.next_operator);
                self.next_operator += 1;
                match self.relay.handle_operator(call, &request, self.clock.now()) {
                    Some(response) => self.deliver(to, Reply::Ad(response)),
                    None => {
                        self.awaiting.insert(call, to);
                    }
                }
            }
            Request::Malformed(endpoint, error) => {
                self.deliver(to, Reply::refusal(endpoint, error));
            }
            Request::Sync(_) => self.deliver(to, Reply::refusal(endpoint, NO_SYNC.to_owned())),
        }
    }

    /// Sends `reply` where `to` says: a DDS client's is framed for its server, the door's is
    /// kept until the turn's publication.
    fn deliver(&mut self, to: Awaiting, reply: Reply) {
        match to {
            Awaiting::Dds {
                server: index,
                client,
                header,
            } => {
                if let Some(server) = self.servers.get(index) {
                    self.replies.push(server, index, client, header, &reply);
                }
            }
            Awaiting::Door(to) => self.door_replies.push((to, reply)),
        }
    }

    /// Publishes the factors when the one factor stream says (`[COOP-RELAY-FACTORS.1]`).
    fn publish(&mut self, now: Now) {
        self.input.take(&mut self.stream, now, &self.refusals);
        if let Some(publication) = self.relay.poll_publication(now) {
            self.stream.take_scenes(publication);
        }
        let Some(publication) = self.stream.poll(now) else {
            return;
        };
        self.factors
            .write(&publication.velocity, &publication.steering);
        if let Some(door) = &mut self.door {
            (door.shown)(&publication);
        }
    }

    /// Gives the relay what module `name` said; what it refuses is logged.
    fn hear(&mut self, name: &str, heard: Heard, now: Now) {
        match heard {
            Heard::Statuses(array) => match self.relay.take_statuses(name, &array, now) {
                Ok(taken) => {
                    if let Some((_, repeats)) = self.refusing.remove(name) {
                        tracing::info!(
                            interface = name,
                            "status arrays taken again, after {} more refused for that reason",
                            repeats
                        );
                    }
                    for (id, error) in &taken.refused {
                        let what = format!("the status of scene {id} refused");
                        refused(&self.refusals, name, &what, error);
                    }
                }
                Err(error) => {
                    // Logged when the reason's kind changes: a module keeps publishing.
                    let kind = std::mem::discriminant(&error);
                    match self.refusing.get_mut(name) {
                        Some((logged, repeats)) if *logged == kind => *repeats += 1,
                        _ => {
                            tracing::warn!(interface = name, %error, "status array refused");
                            self.refusing.insert(name.to_owned(), (kind, 0));
                        }
                    }
                }
            },
            Heard::AutoMode(status) => {
                if let Err(error) = self.relay.take_auto_mode(name, &status, now) {
                    refused(&self.refusals, name, "an auto-mode status refused", &error);
                }
            }
            Heard::Answer(call, answer) => {
                if !self.relay.take_answer(call, &answer, now) {
                    tracing::warn!(interface = name, "an answer after its deadline, not taken");
                } else if !answered(&answer) {
                    tracing::info!(interface = name, "the module refused a call");
                }
            }
        }
    }

    /// Takes every request waiting at server `index`.
    fn serve(&mut self, index: usize) {
        while let Some((client, header, request)) = self
            .servers
            .get_mut(index)
            .and_then(|server| server.next_request(&self.refusals))
        {
            self.take(
                request,
                Awaiting::Dds {
                    server: index,
                    client,
                    header,
                },
            );
        }
    }
}

/// Why a module's sync is refused: the modules report on their own endpoints.
const NO_SYNC: &str = "the stack mode takes no sync requests: planning modules report on their \
                       own RTC endpoints (docs/autoware.md)";

/// Whether a module's answer says it did what it was asked.
fn answered(answer: &ModuleAnswer) -> bool {
    match answer {
        ModuleAnswer::Commands(response) => response.responses.iter().all(|r| r.success),
        ModuleAnswer::AutoMode(success) => *success,
    }
}

/// How long a module has to answer unless the command line says otherwise.
pub const DEADLINE: Duration = Duration::from_millis(relay::DEADLINE_MS);
