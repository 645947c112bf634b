//! The AD API services and streams over the core, typed and as JSON bytes.

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::{CooperatingFactor, State};

use super::error::Leaf;
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
        Ok(commands) => state.set_commands(commands).status,
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
        Ok(policies) => state.set_policies(policies).status,
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
        status,
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
        header: map_header(stamp),
        factors: factors.into_iter().map(Into::into).collect(),
    }
}

/// A stream's header: `stamp`, in the `map` frame.
fn map_header(stamp: Time) -> Header {
    Header {
        stamp,
        frame_id: FRAME_ID.to_owned(),
    }
}

/// `/api/planning/velocity_factors` with factors of modules that do not cooperate: the live
/// velocity scenes and `others` in one stream, nearest first
/// ([`State::velocity_factors_with`]), stamped `stamp`, in the `map` frame. Each of `others`
/// is published with an empty `cooperation` list.
///
/// # Errors
/// [`CooperatingFactor`] for the first of `others` with a cooperation status.
pub fn velocity_factors_with(
    state: &State,
    stamp: Time,
    others: &[crate::VelocityFactor],
) -> Result<VelocityFactorArray, CooperatingFactor> {
    let mut factors = Vec::new();
    state.velocity_factors_with(others, &mut factors)?;
    Ok(VelocityFactorArray {
        header: map_header(stamp),
        factors: factors.into_iter().map(Into::into).collect(),
    })
}

/// `/api/planning/steering_factors` with factors of modules that do not cooperate: the live
/// steering scenes and `others` in one stream, nearest start first
/// ([`State::steering_factors_with`]), stamped `stamp`, in the `map` frame. Each of `others`
/// is published with an empty `cooperation` list.
///
/// # Errors
/// [`CooperatingFactor`] for the first of `others` with a cooperation status.
pub fn steering_factors_with(
    state: &State,
    stamp: Time,
    others: &[crate::SteeringFactor],
) -> Result<SteeringFactorArray, CooperatingFactor> {
    let mut factors = Vec::new();
    state.steering_factors_with(others, &mut factors)?;
    Ok(SteeringFactorArray {
        header: map_header(stamp),
        factors: factors.into_iter().map(Into::into).collect(),
    })
}

/// `/api/planning/steering_factors`: the live steering scenes, nearest start first
/// ([`State::steering_factors_into`]), stamped `stamp`, in the `map` frame.
#[must_use]
pub fn steering_factors(state: &State, stamp: Time) -> SteeringFactorArray {
    let mut factors = Vec::new();
    state.steering_factors_into(&mut factors);
    SteeringFactorArray {
        header: map_header(stamp),
        factors: factors.into_iter().map(Into::into).collect(),
    }
}

/// The most bytes a service request may have: [`Service::call_json`] refuses a longer one
/// with [`Malformed::TooLarge`] before reading it. 1 MiB: the largest batch the core accepts
/// by default (1 024 entries) takes under 400 KiB written out at its most verbose
/// (pretty-printed, UUIDs as lists of numbers).
pub const MAX_REQUEST_BYTES: usize = 1 << 20;

/// Reads a message from JSON as rosbridge writes it, of any length (a request on its way to
/// a service is first held to [`MAX_REQUEST_BYTES`] by [`Service::call_json`]). The reader
/// never builds more than the message itself: memory grows with the input's length only, on
/// success and on failure, and nesting deeper than the message is refused where the message
/// ends.
///
/// # Errors
/// [`Malformed::NotJson`] for bad syntax, an early end or text after the message,
/// [`Malformed::Shape`] for JSON of another shape; both name where the reader was, by field
/// name also in a message given as a list of its field values.
pub fn from_json<T: DeserializeOwned>(json: &[u8]) -> Result<T, Malformed> {
    let mut reader = serde_json::Deserializer::from_slice(json);
    let message = serde_path_to_error::deserialize(&mut reader).map_err(|error| {
        let (path, leaf) = FieldPath::named::<T>(error.path());
        fault(json, path, leaf, &error.into_inner())
    })?;
    // Text after the message, other than white space, is not JSON of one message.
    reader.end().map_err(|error| Malformed::NotJson {
        path: FieldPath::root(),
        detail: error.to_string(),
    })?;
    Ok(message)
}

/// How the JSON reader says a number does not fit the type it is read as.
const OUT_OF_RANGE: &str = "number out of range";
/// How the JSON reader says a list goes on where its reader expected it to end.
const TRAILING: &str = "trailing characters";

/// The fault of a message the reader stopped in, at `path`, ending at a `leaf`.
fn fault(json: &[u8], path: FieldPath, leaf: Leaf, error: &serde_json::Error) -> Malformed {
    let detail = error.to_string();
    if error.is_data() {
        return Malformed::Shape { path, detail };
    }
    if error.is_syntax() {
        if detail.starts_with(OUT_OF_RANGE) {
            // A number in JSON's grammar, too large for its field's type.
            return Malformed::Shape {
                detail: out_of_range(json, leaf, error),
                path,
            };
        }
        if detail.starts_with(TRAILING) && is_json(json) {
            // The text is JSON, yet the reader met more than it expected: a list longer than
            // the message or fixed-size array it stands for.
            return Malformed::Shape {
                path,
                detail: format!("a list with more values than its field takes: {detail}"),
            };
        }
    }
    Malformed::NotJson { path, detail }
}

/// Whether the text is JSON (one value, strings in UTF-8), checked without building it.
fn is_json(json: &[u8]) -> bool {
    core::str::from_utf8(json).is_ok()
        && serde_json::from_slice::<serde::de::IgnoredAny>(json).is_ok()
}

/// At most this many characters of a number from the input are quoted in a message.
const NUMBER_QUOTED: usize = 64;

/// The explanation of a number too large for its field: the number as written (cut short if
/// long), the type, and where.
fn out_of_range(json: &[u8], leaf: Leaf, error: &serde_json::Error) -> String {
    let (line, column) = (error.line(), error.column());
    // The reader stops on the number's last character, `column` bytes into its line.
    let number = json
        .split(|&byte| byte == b'\n')
        .nth(line.saturating_sub(1))
        .and_then(|text| text.get(..column))
        .map(|text| {
            let start = text
                .iter()
                .rposition(|byte| !matches!(byte, b'0'..=b'9' | b'-' | b'+' | b'.' | b'e' | b'E'))
                .map_or(0, |at| at + 1);
            text.get(start..).unwrap_or_default()
        })
        .and_then(|digits| core::str::from_utf8(digits).ok())
        .filter(|number| !number.is_empty());
    let number = match number {
        None => "the number".to_owned(),
        Some(number) => match number.get(..NUMBER_QUOTED) {
            Some(head) if number.len() > NUMBER_QUOTED => {
                format!("{head}… ({} characters)", number.len())
            }
            _ => number.to_owned(),
        },
    };
    let kind = match leaf {
        Leaf::Number(kind) => kind,
        // A value read as any JSON: its numbers are read as the widest float.
        Leaf::Other => "a 64-bit float (f64), the widest number read from JSON",
    };
    format!("{number} is out of range for {kind} at line {line} column {column}")
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
    /// (rosbridge's `values`) out. Never panics. A request longer than [`MAX_REQUEST_BYTES`]
    /// is refused unread ([`Malformed::TooLarge`]); any request that does not decode is
    /// answered `PARAMETER_ERROR` with a message naming the field. Neither changes anything.
    pub fn call_json(self, state: &mut State, request: &[u8]) -> Vec<u8> {
        fn answer<Q: DeserializeOwned, R: Serialize>(
            request: &[u8],
            handle: impl FnOnce(&Q) -> R,
            refuse: impl FnOnce(Malformed) -> R,
        ) -> Vec<u8> {
            let read = if request.len() > MAX_REQUEST_BYTES {
                Err(Malformed::TooLarge {
                    path: FieldPath::root(),
                    len: request.len(),
                    max: MAX_REQUEST_BYTES,
                })
            } else {
                from_json::<Q>(request)
            };
            let response = match read {
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
