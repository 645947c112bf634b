//! One planning module's RTC interface as the stack node reaches it over DDS: readers of its
//! status and auto-mode topics, and clients of its two services as `rmw_cyclonedds_cpp` makes
//! them (a request header with the client's identifier and a sequence number; a reply is the
//! client's when both match).

use std::collections::BTreeMap;

use cooperation_adapters::cdr::{self, CdrError};
use cooperation_adapters::dds::{ModuleEndpoints, RequestHeader};
use cooperation_adapters::refusals::Refusals;
use cooperation_adapters::relay::{CallId, ModuleAnswer, ModuleRequest};
use cooperation_adapters::rtc::{AutoModeStatus, CooperateStatusArray};
use rustdds::mio1::{Interest, Poll, Token};
use rustdds::no_key::{DataReader, DataWriter};
use rustdds::policy::Durability;
use rustdds::{DataReaderStatus, DataWriterStatus, RTPSEntity, StatusEvented, GUID};

use crate::entities::{qos, refused, services_qos, Participant};
use crate::raw::{Raw, RawAdapter};

/// Which of the interface's two services.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Service {
    Commands,
    AutoMode,
}

/// A service client: its request writer and reply reader, whether each is matched, and its
/// calls awaiting replies by sequence number.
pub(crate) struct Client {
    service: Service,
    name: String,
    requests: DataWriter<Raw, RawAdapter>,
    replies: DataReader<Raw, RawAdapter>,
    servers_reading: i32,
    servers_writing: i32,
    guid: u64,
    seq: i64,
    calls: BTreeMap<i64, CallId>,
}

impl Client {
    fn open(
        participant: &Participant,
        endpoints: &ModuleEndpoints,
        service: Service,
        guid: u64,
    ) -> Result<Self, String> {
        let (name, request_topic, reply_topic, type_name) = match service {
            Service::Commands => (
                endpoints.commands(),
                endpoints.commands_request_topic(),
                endpoints.commands_reply_topic(),
                ModuleEndpoints::COMMANDS_TYPE,
            ),
            Service::AutoMode => (
                endpoints.auto_mode(),
                endpoints.auto_mode_request_topic(),
                endpoints.auto_mode_reply_topic(),
                ModuleEndpoints::AUTO_MODE_TYPE,
            ),
        };
        let dds_type = |suffix| cooperation_adapters::dds::type_name(type_name, suffix);
        Ok(Self {
            service,
            requests: participant.writer(&request_topic, &dds_type("_Request"), &services_qos())?,
            replies: participant.reader(&reply_topic, &dds_type("_Response"), &services_qos())?,
            name,
            servers_reading: 0,
            servers_writing: 0,
            guid,
            seq: 0,
            calls: BTreeMap::new(),
        })
    }

    /// Whether a server is there: its request reader and reply writer both matched, as
    /// `rmw_cyclonedds_cpp` checks before it calls.
    fn available(&mut self) -> bool {
        while let Some(status) = self.requests.try_recv_status() {
            if let DataWriterStatus::PublicationMatched { current, .. } = status {
                self.servers_reading = current.count();
            }
        }
        while let Some(status) = self.replies.try_recv_status() {
            if let DataReaderStatus::SubscriptionMatched { current, .. } = status {
                self.servers_writing = current.count();
            }
        }
        self.servers_reading > 0 && self.servers_writing > 0
    }

    /// Sends `request` as call `call`; false if no server is there or the write failed (the
    /// call then runs out of time in the relay, as an unanswered one).
    fn send(&mut self, endpoints: &ModuleEndpoints, call: CallId, request: &ModuleRequest) -> bool {
        if !self.available() {
            tracing::warn!(service = %self.name, "no server: a call not sent runs out of time");
            return false;
        }
        self.seq += 1;
        let header = RequestHeader {
            guid: self.guid,
            seq: self.seq,
        };
        let written = endpoints
            .request(header, request)
            .map_err(|error| error.to_string())
            .and_then(|bytes| {
                self.requests
                    .write(Raw(bytes), None)
                    .map_err(|error| error.to_string())
            });
        match written {
            Ok(()) => {
                self.calls.insert(self.seq, call);
                true
            }
            Err(error) => {
                tracing::error!(service = %self.name, %error, "a call not written");
                false
            }
        }
    }

    /// Every reply to one of this client's calls: the call and the answer. Replies to other
    /// clients are passed over; one that does not read is logged and dropped.
    fn answers(
        &mut self,
        endpoints: &ModuleEndpoints,
        refusals: &Refusals,
    ) -> Vec<(CallId, ModuleAnswer)> {
        let mut answers = Vec::new();
        loop {
            let bytes = match self.replies.take_next_sample() {
                Ok(Some(sample)) => sample.into_value().0,
                Ok(None) => return answers,
                Err(error) => {
                    tracing::warn!(service = %self.name, %error, "replies not read");
                    return answers;
                }
            };
            let read: Result<(RequestHeader, ModuleAnswer), CdrError> = match self.service {
                Service::Commands => endpoints.commands_answer(&bytes),
                Service::AutoMode => endpoints.auto_mode_answer(&bytes),
            };
            match read {
                Ok((header, answer)) if header.guid == self.guid => {
                    if let Some(call) = self.calls.remove(&header.seq) {
                        answers.push((call, answer));
                    }
                }
                Ok(_) => {}
                Err(error) => {
                    refused(
                        refusals,
                        &self.name,
                        "a reply that does not read dropped",
                        &error,
                    );
                }
            }
        }
    }
}

/// One interface: its name, topics and services.
pub(crate) struct Module {
    pub(crate) endpoints: ModuleEndpoints,
    statuses: DataReader<Raw, RawAdapter>,
    auto_mode: DataReader<Raw, RawAdapter>,
    commands: Client,
    enable: Client,
}

/// What a module sent since the last turn.
pub(crate) enum Heard {
    Statuses(CooperateStatusArray),
    AutoMode(AutoModeStatus),
    Answer(CallId, ModuleAnswer),
}

impl Module {
    /// The interface `name`'s endpoints, its readers polled with tokens from `token` on (four),
    /// its clients identified by `guid` and `guid + 1`.
    pub(crate) fn open(
        participant: &Participant,
        poll: &Poll,
        name: &str,
        token: usize,
        guid: u64,
    ) -> Result<Self, String> {
        let endpoints = ModuleEndpoints::new(name);
        // Upstream publishes both topics with depth 1, reliable and volatile.
        let topics = qos(Durability::Volatile, 1);
        let dds_type = |type_name| cooperation_adapters::dds::type_name(type_name, "");
        let mut statuses = participant.reader(
            &endpoints.status_topic(),
            &dds_type(ModuleEndpoints::STATUS_TYPE),
            &topics,
        )?;
        let mut auto_mode = participant.reader(
            &endpoints.auto_mode_status_topic(),
            &dds_type(ModuleEndpoints::AUTO_MODE_STATUS_TYPE),
            &topics,
        )?;
        let mut commands = Client::open(participant, &endpoints, Service::Commands, guid)?;
        let mut enable = Client::open(participant, &endpoints, Service::AutoMode, guid + 1)?;
        let registry = poll.registry();
        let register = |reader: &mut DataReader<Raw, RawAdapter>, offset: usize| {
            registry
                .register(reader, Token(token + offset), Interest::READABLE)
                .map_err(|error| format!("poll: {error}"))
        };
        register(&mut statuses, 0)?;
        register(&mut auto_mode, 1)?;
        register(&mut commands.replies, 2)?;
        register(&mut enable.replies, 3)?;
        Ok(Self {
            endpoints,
            statuses,
            auto_mode,
            commands,
            enable,
        })
    }

    /// The GUIDs of its readers and writers, for the graph.
    pub(crate) fn guids(&self) -> (Vec<GUID>, Vec<GUID>) {
        (
            vec![
                self.statuses.guid(),
                self.auto_mode.guid(),
                self.commands.replies.guid(),
                self.enable.replies.guid(),
            ],
            vec![self.commands.requests.guid(), self.enable.requests.guid()],
        )
    }

    /// Sends `request` as call `call` to the service it is for.
    pub(crate) fn send(&mut self, call: CallId, request: &ModuleRequest) -> bool {
        let client = match request {
            ModuleRequest::Commands(_) => &mut self.commands,
            ModuleRequest::AutoMode(_) => &mut self.enable,
        };
        client.send(&self.endpoints, call, request)
    }

    /// What arrived since the last turn, in order of kind: status arrays in the order they
    /// came, the newest auto-mode status, the services' answers. A message that does not read
    /// is logged through `refusals` and dropped.
    pub(crate) fn heard(&mut self, refusals: &Refusals) -> Vec<Heard> {
        let name = self.endpoints.name().to_owned();
        let mut heard: Vec<Heard> = read_all(&mut self.statuses, &name, "statuses", refusals)
            .into_iter()
            .map(Heard::Statuses)
            .collect();
        if let Some(status) =
            read_all::<AutoModeStatus>(&mut self.auto_mode, &name, "auto mode", refusals)
                .into_iter()
                .last()
        {
            heard.push(Heard::AutoMode(status));
        }
        for client in [&mut self.commands, &mut self.enable] {
            heard.extend(
                client
                    .answers(&self.endpoints, refusals)
                    .into_iter()
                    .map(|(call, answer)| Heard::Answer(call, answer)),
            );
        }
        heard
    }
}

fn read_all<T: serde::de::DeserializeOwned>(
    reader: &mut DataReader<Raw, RawAdapter>,
    interface: &str,
    what: &str,
    refusals: &Refusals,
) -> Vec<T> {
    let mut messages = Vec::new();
    loop {
        match reader.take_next_sample() {
            Ok(Some(sample)) => match cdr::from_slice(&sample.into_value().0) {
                Ok(message) => messages.push(message),
                Err(error) => refused(
                    refusals,
                    interface,
                    &format!("a message of {what} that does not read dropped"),
                    &error,
                ),
            },
            Ok(None) => return messages,
            Err(error) => {
                tracing::warn!(interface, %error, "{what} not read");
                return messages;
            }
        }
    }
}
