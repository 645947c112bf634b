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
//! Reading takes no lock ([`Endpoint::read`]); answering is one call on the node's [`Host`]
//! ([`answer`]), through [`Host::answer`](crate::Host::answer) for the AD API services and
//! [`sync::answer`] for the planning modules'. Nothing here re-states a rule of the core.
//!
//! ```
//! use cooperation_ros::dds::{self, Endpoint, RequestHeader};
//! use cooperation_ros::wire::{GetCooperationPoliciesRequest, Service};
//! use cooperation_ros::{cdr, Host, Time};
//! use cooperation_ros::rtc::Rtc;
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
//! let config = cooperation_ros::settings::load(None)?;
//! let mut host = Host::new(cooperation::State::new(config)?, Rtc::standard());
//! let answered = dds::answer(&mut host, incoming, Time::default());
//! let reply = header.frame(&answered.outgoing.to_cdr()?);
//! assert_eq!(RequestHeader::split(&reply)?.0, header);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::cdr::{self, CdrError, CDR_LE};
use crate::sync::{self, SyncCooperateStatusRequest, SyncRequest, SyncResponse};
use crate::wire::{self, Request, Response, ResponseStatus, Service};
use crate::{Host, Time};

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

/// A service the node serves over DDS.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Endpoint {
    /// One of the AD API's three cooperation services.
    Ad(Service),
    /// The planning modules' `/cooperation/rtc/sync` ([`sync`]).
    Sync,
}

impl Endpoint {
    /// Every endpoint.
    pub const ALL: [Self; 4] = [
        Self::Ad(Service::SetCommands),
        Self::Ad(Service::SetPolicies),
        Self::Ad(Service::GetPolicies),
        Self::Sync,
    ];

    /// The ROS 2 service name.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Ad(service) => service.name(),
            Self::Sync => sync::NAME,
        }
    }

    /// The ROS 2 service type.
    #[must_use]
    pub const fn ros_type(self) -> &'static str {
        match self {
            Self::Ad(service) => service.type_name(),
            Self::Sync => sync::TYPE,
        }
    }

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
    /// what it asks, or why it cannot be read ([`Incoming::Malformed`], answered with a refusal).
    /// Takes no lock.
    ///
    /// # Errors
    /// A request too short for its headers, or not little-endian CDR: it cannot be answered.
    pub fn read(self, framed: &[u8]) -> Result<(RequestHeader, Incoming), CdrError> {
        let (header, message) = RequestHeader::split(framed)?;
        if message.len() > wire::MAX_REQUEST_BYTES {
            let malformed = CdrError {
                message: format!(
                    "the request is {} bytes, more than the {} a request may have",
                    message.len(),
                    wire::MAX_REQUEST_BYTES
                ),
                offset: 0,
            };
            return Ok((header, Incoming::Malformed(self, malformed)));
        }
        let incoming = match self {
            Self::Ad(Service::SetCommands) => {
                cdr::from_slice(&message).map(|r| Incoming::Ad(Request::SetCommands(r)))
            }
            Self::Ad(Service::SetPolicies) => {
                cdr::from_slice(&message).map(|r| Incoming::Ad(Request::SetPolicies(r)))
            }
            Self::Ad(Service::GetPolicies) => {
                cdr::from_slice(&message).map(|r| Incoming::Ad(Request::GetPolicies(r)))
            }
            Self::Sync => cdr::from_slice::<SyncCooperateStatusRequest>(&message)
                .map(|r| Incoming::Sync(SyncRequest::from(r))),
        };
        Ok((
            header,
            incoming.unwrap_or_else(|error| Incoming::Malformed(self, error)),
        ))
    }
}

/// A request, read.
#[derive(Clone, PartialEq, Debug)]
pub enum Incoming {
    /// An AD API request.
    Ad(Request),
    /// A planning module's sync.
    Sync(SyncRequest),
    /// A request of this endpoint that does not decode, and why.
    Malformed(Endpoint, CdrError),
}

/// A reply, before it is written.
#[derive(Clone, PartialEq, Debug)]
pub enum Outgoing {
    /// An AD API response.
    Ad(Response),
    /// A sync's response.
    Sync(SyncResponse),
}

impl Outgoing {
    /// The reply in CDR, with its encapsulation header (frame it with the request's
    /// [`RequestHeader::frame`]).
    ///
    /// # Errors
    /// A UUID that is not 16 bytes long (the node's replies never hold one).
    pub fn to_cdr(&self) -> Result<Vec<u8>, CdrError> {
        match self {
            Self::Ad(Response::SetCommands(response)) => cdr::to_vec(response),
            Self::Ad(Response::SetPolicies(response)) => cdr::to_vec(response),
            Self::Ad(Response::GetPolicies(response)) => cdr::to_vec(response),
            Self::Sync(response) => cdr::to_vec(response),
        }
    }

    /// Whether it reports success.
    #[must_use]
    pub fn success(&self) -> bool {
        match self {
            Self::Ad(response) => response.status().success,
            Self::Sync(response) => response.success,
        }
    }
}

/// What answering a request did.
#[derive(Clone, PartialEq, Debug)]
pub struct Answered {
    /// The reply.
    pub outgoing: Outgoing,
    /// The core changed.
    pub changed: bool,
    /// The factors show the change: publish them soon.
    pub shown: bool,
}

/// Answers `incoming` from `host` (`stamp`: the time the sync's statuses are stamped with).
pub fn answer(host: &mut Host, incoming: Incoming, stamp: Time) -> Answered {
    match incoming {
        Incoming::Ad(request) => {
            let answer = host.answer(&request);
            Answered {
                outgoing: Outgoing::Ad(answer.response),
                changed: answer.changed,
                shown: answer.changed,
            }
        }
        Incoming::Sync(request) => {
            let (response, effect) = sync::answer(host, &request, stamp);
            Answered {
                outgoing: Outgoing::Sync(response),
                changed: effect.changed,
                shown: effect.shown,
            }
        }
        Incoming::Malformed(endpoint, error) => Answered {
            outgoing: refusal(endpoint, &error),
            changed: false,
            shown: false,
        },
    }
}

/// The reply to a request of `endpoint` that does not decode: `PARAMETER_ERROR` (for the AD
/// API) with the reader's explanation, every other field at its default.
#[must_use]
pub fn refusal(endpoint: Endpoint, error: &CdrError) -> Outgoing {
    match endpoint {
        Endpoint::Ad(service) => Outgoing::Ad(service.refused(ResponseStatus {
            success: false,
            code: ResponseStatus::PARAMETER_ERROR,
            message: error.to_string(),
        })),
        Endpoint::Sync => Outgoing::Sync(sync::refused(error.to_string())),
    }
}
