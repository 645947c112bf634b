//! The AD API services and streams over the core, typed and as JSON bytes.

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::State;

use super::{
    FieldPath, GetCooperationPoliciesRequest, GetCooperationPoliciesResponse, Header, Malformed,
    SetCooperationCommandsRequest, SetCooperationCommandsResponse, SetCooperationPoliciesRequest,
    SetCooperationPoliciesResponse, SteeringFactorArray, Time, VelocityFactorArray,
};

/// The coordinate frame of every pose the core reports.
pub const FRAME_ID: &str = "map";

/// `/api/planning/cooperation/set_commands`: converts the request and applies it with
/// [`State::set_commands`], all commands or none.
///
/// A malformed request is answered `PARAMETER_ERROR` with a message naming the field, and
/// leaves the state unchanged; so does a batch the core rejects, with the core's explanation.
/// An empty batch succeeds with the `NO_EFFECT` warning.
pub fn set_commands(
    state: &mut State,
    request: &SetCooperationCommandsRequest,
) -> SetCooperationCommandsResponse {
    let status = match request.to_commands() {
        Ok(commands) => state.set_commands(commands).status.into(),
        Err(malformed) => malformed.to_status(),
    };
    SetCooperationCommandsResponse { status }
}

/// `/api/planning/cooperation/set_policies`: converts the request and applies it with
/// [`State::set_policies`], all settings or none. Answers as [`set_commands`] does.
pub fn set_policies(
    state: &mut State,
    request: &SetCooperationPoliciesRequest,
) -> SetCooperationPoliciesResponse {
    let status = match request.to_policies() {
        Ok(policies) => state.set_policies(policies).into(),
        Err(malformed) => malformed.to_status(),
    };
    SetCooperationPoliciesResponse { status }
}

/// `/api/planning/cooperation/get_policies`: every configured module's current policy, in
/// module order ([`State::get_policies`]).
#[must_use]
pub fn get_policies(
    state: &State,
    _request: &GetCooperationPoliciesRequest,
) -> GetCooperationPoliciesResponse {
    let (status, policies) = state.get_policies();
    GetCooperationPoliciesResponse {
        status: status.into(),
        policies: policies.into_iter().map(Into::into).collect(),
    }
}

/// `/api/planning/velocity_factors`: the live velocity scenes, nearest first
/// ([`State::velocity_factors_into`]), stamped `stamp`, in the `map` frame.
#[must_use]
pub fn velocity_factors(state: &State, stamp: Time) -> VelocityFactorArray {
    let mut factors = Vec::new();
    state.velocity_factors_into(&mut factors);
    VelocityFactorArray {
        header: Header {
            stamp,
            frame_id: FRAME_ID.to_owned(),
        },
        factors: factors.into_iter().map(Into::into).collect(),
    }
}

/// `/api/planning/steering_factors`: the live steering scenes, nearest start first
/// ([`State::steering_factors_into`]), stamped `stamp`, in the `map` frame.
#[must_use]
pub fn steering_factors(state: &State, stamp: Time) -> SteeringFactorArray {
    let mut factors = Vec::new();
    state.steering_factors_into(&mut factors);
    SteeringFactorArray {
        header: Header {
            stamp,
            frame_id: FRAME_ID.to_owned(),
        },
        factors: factors.into_iter().map(Into::into).collect(),
    }
}

/// Reads a message from JSON as rosbridge writes it. Nesting deeper than 128 levels is
/// refused, so no input exhausts the stack; memory grows with the input's length only.
///
/// # Errors
/// [`Malformed::NotJson`] for bad syntax or an early end, [`Malformed::Shape`] for JSON of
/// another shape; both name where the reader was.
pub fn from_json<T: DeserializeOwned>(json: &[u8]) -> Result<T, Malformed> {
    let fault = |path: FieldPath, error: serde_json::Error| {
        if error.is_data() {
            Malformed::Shape {
                path,
                detail: error.to_string(),
            }
        } else if serde_json::from_slice::<serde_json::Value>(json).is_ok() {
            // The text is JSON (strings checked too), yet the reader met more than it expected:
            // a list longer than the message or fixed-size array it stands for.
            Malformed::Shape {
                path,
                detail: format!("a list with more values than its field takes: {error}"),
            }
        } else {
            Malformed::NotJson {
                path,
                detail: error.to_string(),
            }
        }
    };
    let mut reader = serde_json::Deserializer::from_slice(json);
    let message = serde_path_to_error::deserialize(&mut reader)
        .map_err(|error| fault(error.path().into(), error.into_inner()))?;
    // Text after the message, other than white space, is not JSON of one message.
    reader
        .end()
        .map_err(|error| fault(FieldPath::root(), error))?;
    Ok(message)
}

/// Writes a message as JSON as rosbridge reads it (UUIDs as lists of numbers). JSON has no
/// NaN or infinity: a non-finite float is written `null`, which no reader turns back into a
/// number.
///
/// Writing this module's messages cannot fail (they hold no maps and no custom serializers,
/// and the output is memory); for a type whose serializer fails, the result is empty.
#[must_use]
pub fn to_json<T: Serialize>(message: &T) -> Vec<u8> {
    serde_json::to_vec(message).unwrap_or_default()
}

/// The answer to a call whose response could not be written.
const UNWRITABLE: &[u8] =
    br#"{"status":{"success":false,"code":50000,"message":"the response could not be written"}}"#;

/// The three AD API cooperation services.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub enum Service {
    /// `set_commands`: operator decisions for scenes.
    SetCommands,
    /// `set_policies`: policies for modules.
    SetPolicies,
    /// `get_policies`: every module's policy.
    GetPolicies,
}

impl Service {
    /// Every service.
    pub const ALL: [Self; 3] = [Self::SetCommands, Self::SetPolicies, Self::GetPolicies];

    /// The service's AD API name, e.g. `/api/planning/cooperation/set_commands`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::SetCommands => "/api/planning/cooperation/set_commands",
            Self::SetPolicies => "/api/planning/cooperation/set_policies",
            Self::GetPolicies => "/api/planning/cooperation/get_policies",
        }
    }

    /// The service's ROS type, e.g. `autoware_adapi_v1_msgs/srv/SetCooperationCommands`.
    #[must_use]
    pub const fn type_name(self) -> &'static str {
        match self {
            Self::SetCommands => "autoware_adapi_v1_msgs/srv/SetCooperationCommands",
            Self::SetPolicies => "autoware_adapi_v1_msgs/srv/SetCooperationPolicies",
            Self::GetPolicies => "autoware_adapi_v1_msgs/srv/GetCooperationPolicies",
        }
    }

    /// The service with this AD API name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|service| service.name() == name)
    }

    /// Answers one call: the request's JSON (rosbridge's `args`) in, the response's JSON
    /// (rosbridge's `values`) out. Never panics. Any request that does not decode is answered
    /// `PARAMETER_ERROR` with a message naming the field, and changes nothing.
    pub fn call_json(self, state: &mut State, request: &[u8]) -> Vec<u8> {
        fn answer<Q: DeserializeOwned, R: Serialize>(
            request: &[u8],
            handle: impl FnOnce(&Q) -> R,
            refuse: impl FnOnce(Malformed) -> R,
        ) -> Vec<u8> {
            let response = match from_json::<Q>(request) {
                Ok(request) => handle(&request),
                Err(malformed) => refuse(malformed),
            };
            // Writing a response cannot fail (see `to_json`); were it to, the caller still
            // gets a response: an error status, the other fields left to their defaults.
            serde_json::to_vec(&response).unwrap_or_else(|_| UNWRITABLE.to_vec())
        }
        match self {
            Self::SetCommands => answer(
                request,
                |request| set_commands(state, request),
                |malformed| SetCooperationCommandsResponse {
                    status: malformed.to_status(),
                },
            ),
            Self::SetPolicies => answer(
                request,
                |request| set_policies(state, request),
                |malformed| SetCooperationPoliciesResponse {
                    status: malformed.to_status(),
                },
            ),
            Self::GetPolicies => answer(
                request,
                |request| get_policies(state, request),
                |malformed| GetCooperationPoliciesResponse {
                    status: malformed.to_status(),
                    policies: Vec::new(),
                },
            ),
        }
    }
}
