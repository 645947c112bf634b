//! What a door brings the engine: a request of one of the node's services, read from JSON
//! (rosbridge) or CDR (DDS) with no lock held, and the reply the engine gives.

use crate::sync::{self, SyncRequest, SyncResponse};
use crate::wire::{self, ResponseStatus, Service};

/// A service the node serves, whatever door its requests come through.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum Endpoint {
    /// One of the AD API's three cooperation services.
    Ad(Service),
    /// The planning modules' `/cooperation/rtc/sync` ([`sync`]).
    Sync,
}

impl Endpoint {
    /// Every endpoint: the one list of the node's services.
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

    /// The endpoint named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|endpoint| endpoint.name() == name)
    }

    /// A request of this endpoint from its JSON (rosbridge's `args`), or the refusal of one that
    /// does not read ([`Request::Malformed`]). Takes no lock; a request over
    /// [`MAX_REQUEST_BYTES`](wire::MAX_REQUEST_BYTES) is refused unread.
    #[must_use]
    pub fn read_json(self, json: &[u8]) -> Request {
        match self {
            Self::Ad(service) => match service.read(json) {
                Ok(request) => Request::Ad(request),
                Err(malformed) => Request::Malformed(self, malformed.to_string()),
            },
            Self::Sync => match sync::read_json(json) {
                Ok(request) => Request::Sync(request),
                Err(message) => Request::Malformed(self, message),
            },
        }
    }
}

/// A request, read.
#[derive(Clone, PartialEq, Debug)]
pub enum Request {
    /// An AD API request.
    Ad(wire::Request),
    /// A planning module's sync.
    Sync(SyncRequest),
    /// A request of this endpoint that does not read, and why: answered with a refusal.
    Malformed(Endpoint, String),
}

impl Request {
    /// The endpoint it is a request of.
    #[must_use]
    pub const fn endpoint(&self) -> Endpoint {
        match self {
            Self::Ad(request) => Endpoint::Ad(request.service()),
            Self::Sync(_) => Endpoint::Sync,
            Self::Malformed(endpoint, _) => *endpoint,
        }
    }
}

/// A reply, before a door writes it. It serializes as the response message itself, with
/// nothing around it.
#[derive(Clone, PartialEq, Debug, serde::Serialize)]
#[serde(untagged)]
pub enum Reply {
    /// An AD API response.
    Ad(wire::Response),
    /// A sync's response.
    Sync(SyncResponse),
}

impl Reply {
    /// Whether it reports success.
    #[must_use]
    pub fn success(&self) -> bool {
        match self {
            Self::Ad(response) => response.status().success,
            Self::Sync(response) => response.success,
        }
    }

    /// The reply to a request of `endpoint` that does not read: `PARAMETER_ERROR` (for the AD
    /// API) with the reader's explanation, every other field at its default.
    #[must_use]
    pub fn refusal(endpoint: Endpoint, message: String) -> Self {
        match endpoint {
            Endpoint::Ad(service) => Self::Ad(service.refused(ResponseStatus {
                success: false,
                code: ResponseStatus::PARAMETER_ERROR,
                message,
            })),
            Endpoint::Sync => Self::Sync(sync::refused(message)),
        }
    }
}
