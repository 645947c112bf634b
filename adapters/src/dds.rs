//! The node's services as ROS 2 carries them over DDS, independent of any DDS library: the DDS
//! names and types of the topics and services, the request header of `rmw_cyclonedds_cpp`, and
//! each service answered from the bytes of a request to the bytes of its reply.
//!
//! ROS 2 maps a topic `/a/b` to the DDS topic `rt/a/b` and a service `/a/b` to two topics,
//! `rq/a/bRequest` and `rr/a/bReply`; a message type `pkg/msg/Name` is the DDS type
//! `pkg::msg::dds_::Name_`, a service type's request `pkg::srv::dds_::Name_Request_`. Cyclone DDS
//! (the middleware Autoware recommends) puts a [`RequestHeader`] in front of each request's and
//! reply's fields; the server copies the request's into its reply, and the client takes only the
//! replies that carry its own.
//!
//! Reading takes no lock ([`Endpoint::read`]); answering is the engine's
//! ([`Engine::handle`](crate::engine::Engine::handle)), whatever door a request came through.
//! Nothing here re-states a rule of the core.
//!
//! ```
//! use cooperation_adapters::dds::{self, RequestHeader};
//! use cooperation_adapters::engine::{Endpoint, Engine, Now, Options};
//! use cooperation_adapters::wire::{GetCooperationPoliciesRequest, Service};
//! use cooperation_adapters::cdr;
//!
//! let endpoint = Endpoint::Ad(Service::GetPolicies);
//! assert_eq!(endpoint.request_topic(), "rq/api/planning/cooperation/get_policiesRequest");
//! assert_eq!(
//!     endpoint.request_type(),
//!     "autoware_adapi_v1_msgs::srv::dds_::GetCooperationPolicies_Request_"
//! );
//!
//! // A request as Cyclone DDS sends it: the header, then the message's fields.
//! let header = RequestHeader { guid: 7, seq: 1 };
//! let request = header.frame(&cdr::to_vec(&GetCooperationPoliciesRequest {})?);
//! let (read_header, incoming) = endpoint.read(&request)?;
//! assert_eq!(read_header, header);
//!
//! let mut engine = Engine::from_settings(None, Options::default())?;
//! let handled = engine.handle(incoming, Now::default());
//! let reply = header.frame(&dds::to_cdr(&handled.reply)?);
//! assert_eq!(RequestHeader::split(&reply)?.0, header);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::cdr::{self, CdrError, CDR_LE};
pub use crate::engine::Endpoint;
use crate::engine::{Reply, Request};
use crate::sync::{SyncCooperateStatusRequest, SyncRequest};
use crate::wire::{self, Response, Service};

/// The DDS topic of the ROS 2 topic `name` (`/api/planning/velocity_factors` →
/// `rt/api/planning/velocity_factors`).
#[must_use]
pub fn topic(name: &str) -> String {
    format!("rt{name}")
}

/// The DDS type of the ROS 2 type `name` (`pkg/msg/Name` → `pkg::msg::dds_::Name_`; a service
/// type `pkg/srv/Name` with `suffix` `_Request` or `_Response`).
#[must_use]
pub fn type_name(name: &str, suffix: &str) -> String {
    let mut parts = name.rsplitn(2, '/');
    let last = parts.next().unwrap_or_default();
    let package = parts.next().unwrap_or_default().replace('/', "::");
    format!("{package}::dds_::{last}{suffix}_")
}

/// The request header of `rmw_cyclonedds_cpp`: two little-endian integers right after the
/// encapsulation header, before the message's fields (whose alignment they keep, being 16
/// bytes).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Default)]
pub struct RequestHeader {
    /// The client's identifier (its request writer's instance handle).
    pub guid: u64,
    /// The request's sequence number at that client.
    pub seq: i64,
}

impl RequestHeader {
    /// Its length in bytes.
    pub const LEN: usize = 16;

    /// The header of `framed` (a request or reply: encapsulation header, request header, fields)
    /// and the message that follows, with its encapsulation header, for [`cdr::from_slice`].
    ///
    /// # Errors
    /// Fewer bytes than the two headers, or an encapsulation other than little-endian CDR.
    pub fn split(framed: &[u8]) -> Result<(Self, Vec<u8>), CdrError> {
        let header = framed
            .get(CDR_LE.len()..CDR_LE.len() + Self::LEN)
            .ok_or_else(|| CdrError {
                message: format!(
                    "{} bytes, fewer than the {} of the encapsulation and request headers",
                    framed.len(),
                    CDR_LE.len() + Self::LEN
                ),
                offset: 0,
            })?;
        // The representation (little-endian CDR); the options that follow say only how much
        // padding ends the message, which the reader ignores.
        if framed.get(..2) != CDR_LE.get(..2) {
            return Err(CdrError {
                message: "not little-endian plain CDR (encapsulation 00 01)".to_owned(),
                offset: 0,
            });
        }
        let (guid, seq) = header.split_at(8);
        let header = Self {
            guid: u64::from_le_bytes(guid.try_into().unwrap_or_default()),
            seq: i64::from_le_bytes(seq.try_into().unwrap_or_default()),
        };
        let mut message = CDR_LE.to_vec();
        message.extend_from_slice(framed.get(CDR_LE.len() + Self::LEN..).unwrap_or_default());
        Ok((header, message))
    }

    /// `message` (as [`cdr::to_vec`] writes it) with this header in front of its fields.
    #[must_use]
    pub fn frame(self, message: &[u8]) -> Vec<u8> {
        let mut framed = Vec::with_capacity(message.len() + Self::LEN);
        framed.extend_from_slice(&CDR_LE);
        framed.extend_from_slice(&self.guid.to_le_bytes());
        framed.extend_from_slice(&self.seq.to_le_bytes());
        framed.extend_from_slice(message.get(CDR_LE.len()..).unwrap_or_default());
        framed
    }
}

/// The DDS names of an endpoint's topics and types, and its requests read from CDR.
impl Endpoint {
    /// The DDS topic requests arrive on.
    #[must_use]
    pub fn request_topic(self) -> String {
        format!("rq{}Request", self.name())
    }

    /// The DDS topic replies leave on.
    #[must_use]
    pub fn reply_topic(self) -> String {
        format!("rr{}Reply", self.name())
    }

    /// The requests' DDS type.
    #[must_use]
    pub fn request_type(self) -> String {
        type_name(self.ros_type(), "_Request")
    }

    /// The replies' DDS type.
    #[must_use]
    pub fn reply_type(self) -> String {
        type_name(self.ros_type(), "_Response")
    }

    /// A request as it arrived (encapsulation header, request header, fields): its header and
    /// what it asks, or why it cannot be read ([`Request::Malformed`], answered with a refusal).
    /// Takes no lock.
    ///
    /// # Errors
    /// A request too short for its headers, or not little-endian CDR: it cannot be answered.
    pub fn read(self, framed: &[u8]) -> Result<(RequestHeader, Request), CdrError> {
        let (header, message) = RequestHeader::split(framed)?;
        if let Err(malformed) = wire::check_request_len(message.len()) {
            return Ok((header, Request::Malformed(self, malformed.to_string())));
        }
        let request = match self {
            Self::Ad(Service::SetCommands) => {
                cdr::from_slice(&message).map(|r| Request::Ad(wire::Request::SetCommands(r)))
            }
            Self::Ad(Service::SetPolicies) => {
                cdr::from_slice(&message).map(|r| Request::Ad(wire::Request::SetPolicies(r)))
            }
            Self::Ad(Service::GetPolicies) => {
                cdr::from_slice(&message).map(|r| Request::Ad(wire::Request::GetPolicies(r)))
            }
            Self::Sync => cdr::from_slice::<SyncCooperateStatusRequest>(&message)
                .map(|r| Request::Sync(SyncRequest::from(r))),
        };
        Ok((
            header,
            request.unwrap_or_else(|error| Request::Malformed(self, error.to_string())),
        ))
    }
}

/// A reply in CDR, with its encapsulation header (frame it with the request's
/// [`RequestHeader::frame`]).
///
/// # Errors
/// A UUID that is not 16 bytes long (the node's replies never hold one).
pub fn to_cdr(reply: &Reply) -> Result<Vec<u8>, CdrError> {
    match reply {
        Reply::Ad(Response::SetCommands(response)) => cdr::to_vec(response),
        Reply::Ad(Response::SetPolicies(response)) => cdr::to_vec(response),
        Reply::Ad(Response::GetPolicies(response)) => cdr::to_vec(response),
        Reply::Sync(response) => cdr::to_vec(response),
    }
}

/// A planning module's RTC interface as upstream's `rtc_interface` names it
/// (`/planning/cooperate_status/<name>` and the others): the DDS names and types of its four
/// endpoints, and its requests and answers in CDR, for a node that calls it
/// ([`relay`](crate::relay)).
///
/// ```
/// use cooperation_adapters::dds::{ModuleEndpoints, RequestHeader};
/// use cooperation_adapters::relay::{ModuleAnswer, ModuleRequest};
/// use cooperation_adapters::rtc::{AutoModeRequest, AutoModeResponse};
/// use cooperation_adapters::cdr;
///
/// let module = ModuleEndpoints::new("intersection");
/// assert_eq!(module.status_topic(), "rt/planning/cooperate_status/intersection");
/// assert_eq!(module.auto_mode_request_topic(), "rq/planning/enable_auto_mode/intersectionRequest");
///
/// let header = RequestHeader { guid: 3, seq: 9 };
/// let request = module.request(header, &ModuleRequest::AutoMode(AutoModeRequest { enable: true }))?;
/// assert_eq!(RequestHeader::split(&request)?.0, header);
///
/// // The module's reply, as its server frames it.
/// let reply = header.frame(&cdr::to_vec(&AutoModeResponse { success: true })?);
/// assert_eq!(module.auto_mode_answer(&reply)?, (header, ModuleAnswer::AutoMode(true)));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub struct ModuleEndpoints {
    name: String,
}

impl ModuleEndpoints {
    /// The ROS 2 type of the status topic.
    pub const STATUS_TYPE: &'static str = "tier4_rtc_msgs/msg/CooperateStatusArray";
    /// The ROS 2 type of the auto-mode status topic.
    pub const AUTO_MODE_STATUS_TYPE: &'static str = "tier4_rtc_msgs/msg/AutoModeStatus";
    /// The ROS 2 type of the command service.
    pub const COMMANDS_TYPE: &'static str = "tier4_rtc_msgs/srv/CooperateCommands";
    /// The ROS 2 type of the auto-mode service.
    pub const AUTO_MODE_TYPE: &'static str = "tier4_rtc_msgs/srv/AutoMode";

    /// The endpoints of the interface `name` (`lane_change_left`, …).
    #[must_use]
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_owned(),
        }
    }

    /// The interface's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The ROS 2 name of the status topic, `/planning/cooperate_status/<name>`.
    #[must_use]
    pub fn status(&self) -> String {
        format!("/planning/cooperate_status/{}", self.name)
    }

    /// The ROS 2 name of the auto-mode status topic, `/planning/auto_mode_status/<name>`.
    #[must_use]
    pub fn auto_mode_status(&self) -> String {
        format!("/planning/auto_mode_status/{}", self.name)
    }

    /// The ROS 2 name of the command service, `/planning/cooperate_commands/<name>`.
    #[must_use]
    pub fn commands(&self) -> String {
        format!("/planning/cooperate_commands/{}", self.name)
    }

    /// The ROS 2 name of the auto-mode service, `/planning/enable_auto_mode/<name>`.
    #[must_use]
    pub fn auto_mode(&self) -> String {
        format!("/planning/enable_auto_mode/{}", self.name)
    }

    /// The DDS topic of the statuses.
    #[must_use]
    pub fn status_topic(&self) -> String {
        topic(&self.status())
    }

    /// The DDS topic of the auto-mode statuses.
    #[must_use]
    pub fn auto_mode_status_topic(&self) -> String {
        topic(&self.auto_mode_status())
    }

    /// The DDS topic the command service's requests go to.
    #[must_use]
    pub fn commands_request_topic(&self) -> String {
        format!("rq{}Request", self.commands())
    }

    /// The DDS topic the command service's replies come from.
    #[must_use]
    pub fn commands_reply_topic(&self) -> String {
        format!("rr{}Reply", self.commands())
    }

    /// The DDS topic the auto-mode service's requests go to.
    #[must_use]
    pub fn auto_mode_request_topic(&self) -> String {
        format!("rq{}Request", self.auto_mode())
    }

    /// The DDS topic the auto-mode service's replies come from.
    #[must_use]
    pub fn auto_mode_reply_topic(&self) -> String {
        format!("rr{}Reply", self.auto_mode())
    }

    /// `request` in CDR with `header` in front of its fields.
    ///
    /// # Errors
    /// A UUID that is not 16 bytes long (never in a request the relay makes).
    pub fn request(
        &self,
        header: RequestHeader,
        request: &crate::relay::ModuleRequest,
    ) -> Result<Vec<u8>, CdrError> {
        let message = match request {
            crate::relay::ModuleRequest::Commands(request) => cdr::to_vec(request)?,
            crate::relay::ModuleRequest::AutoMode(request) => cdr::to_vec(request)?,
        };
        Ok(header.frame(&message))
    }

    /// A reply of the command service: its header and the answer.
    ///
    /// # Errors
    /// Bytes that are not a framed `CooperateCommands` response.
    pub fn commands_answer(
        &self,
        framed: &[u8],
    ) -> Result<(RequestHeader, crate::relay::ModuleAnswer), CdrError> {
        let (header, message) = RequestHeader::split(framed)?;
        let response: crate::rtc::CooperateCommandsResponse = cdr::from_slice(&message)?;
        Ok((header, crate::relay::ModuleAnswer::Commands(response)))
    }

    /// A reply of the auto-mode service: its header and the answer.
    ///
    /// # Errors
    /// Bytes that are not a framed `AutoMode` response.
    pub fn auto_mode_answer(
        &self,
        framed: &[u8],
    ) -> Result<(RequestHeader, crate::relay::ModuleAnswer), CdrError> {
        let (header, message) = RequestHeader::split(framed)?;
        let response: crate::rtc::AutoModeResponse = cdr::from_slice(&message)?;
        Ok((
            header,
            crate::relay::ModuleAnswer::AutoMode(response.success),
        ))
    }
}
