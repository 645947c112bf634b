//! The AD API services and streams over the core, typed and as JSON bytes.

use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::error::Category;

use cooperation::{CooperatingFactor, Input, Scene, State};

use super::error::Leaf;
use super::{
    FieldPath, GetCooperationPoliciesRequest, GetCooperationPoliciesResponse, Header, Malformed,
    ResponseStatus, SetCooperationCommandsRequest, SetCooperationCommandsResponse,
    SetCooperationPoliciesRequest, SetCooperationPoliciesResponse, SteeringFactorArray,
    VelocityFactorArray,
};
use crate::Time;

/// The coordinate frame of every pose the core reports.
pub const FRAME_ID: &str = "map";

/// The topic of [`velocity_factors`].
pub const VELOCITY_FACTORS: &str = "/api/planning/velocity_factors";
/// Its message type.
pub const VELOCITY_FACTORS_TYPE: &str = "autoware_adapi_v1_msgs/msg/VelocityFactorArray";
/// The topic of [`steering_factors`].
pub const STEERING_FACTORS: &str = "/api/planning/steering_factors";
/// Its message type.
pub const STEERING_FACTORS_TYPE: &str = "autoware_adapi_v1_msgs/msg/SteeringFactorArray";

/// `/api/planning/cooperation/set_commands` (`[COOP-API-SET-COMMANDS.1]`): converts the request
/// and applies it as the core's `SetCommands`, all commands or none.
///
/// A malformed request is answered `PARAMETER_ERROR` with a message naming the field, and
/// leaves the state unchanged; so does a batch the core rejects, with the core's explanation.
/// An empty batch succeeds with the `NO_EFFECT` warning. The answer says whether an operator
/// decision changed.
pub fn set_commands(
    state: &mut State,
    request: &SetCooperationCommandsRequest,
) -> Answer<SetCooperationCommandsResponse> {
    let commands = match request.to_commands() {
        Ok(commands) => commands,
        Err(malformed) => return Answer::refused(malformed.to_status()),
    };
    let changed = commands.iter().any(|command| {
        state.scene(command.id).map(Scene::operator_decision) != Some(command.decision)
    });
    let len = commands.len();
    let result = state.apply(&Input::SetCommands { commands });
    Answer {
        changed: changed && result.is_ok(),
        response: SetCooperationCommandsResponse {
            status: ResponseStatus::for_batch(len, &result),
        },
    }
}

/// `/api/planning/cooperation/set_policies` (`[COOP-API-SET-POLICIES.1]`): converts the request
/// and applies it as the core's `SetPolicies`, all settings or none. Answers as
/// [`set_commands`] does; the answer says whether a policy changed.
pub fn set_policies(
    state: &mut State,
    request: &SetCooperationPoliciesRequest,
) -> Answer<SetCooperationPoliciesResponse> {
    let policies = match request.to_policies() {
        Ok(policies) => policies,
        Err(malformed) => return Answer::refused(malformed.to_status()),
    };
    let changed = policies
        .iter()
        .any(|setting| state.policy(setting.module) != Some(setting.policy));
    let len = policies.len();
    let result = state.apply(&Input::SetPolicies { policies });
    Answer {
        changed: changed && result.is_ok(),
        response: SetCooperationPoliciesResponse {
            status: ResponseStatus::for_batch(len, &result),
        },
    }
}

/// `/api/planning/cooperation/get_policies` (`[COOP-POL-GET.2]`): every configured module's
/// current policy, in module order ([`State::policies`]).
#[must_use]
pub fn get_policies(
    state: &State,
    _request: &GetCooperationPoliciesRequest,
) -> GetCooperationPoliciesResponse {
    GetCooperationPoliciesResponse {
        status: ResponseStatus::success(),
        policies: state.policies().map(Into::into).collect(),
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
    others: &[cooperation::VelocityFactor],
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
    others: &[cooperation::SteeringFactor],
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

/// The most bytes a service request may have: [`Service::read`] refuses a longer one
/// with [`Malformed::TooLarge`] before reading it. 1 MiB: the largest batch the core accepts
/// by default (1 024 entries) takes under 400 KiB written out at its most verbose
/// (pretty-printed, UUIDs as lists of numbers).
pub const MAX_REQUEST_BYTES: usize = 1 << 20;

/// Refuses a request of `len` bytes if it is longer than [`MAX_REQUEST_BYTES`]: the one check
/// of every door (JSON and CDR, the AD API and the modules' sync), made before a request is read.
///
/// # Errors
/// [`Malformed::TooLarge`].
pub fn check_request_len(len: usize) -> Result<(), Malformed> {
    if len > MAX_REQUEST_BYTES {
        return Err(Malformed::TooLarge {
            path: FieldPath::root(),
            len,
            max: MAX_REQUEST_BYTES,
        });
    }
    Ok(())
}

/// Reads a message from JSON as rosbridge writes it, of any length (a request on its way to
/// a service is first held to [`MAX_REQUEST_BYTES`] by [`Service::read`]). The reader
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

/// The fault of a message the reader stopped in, at `path`, ending at a `leaf`.
///
/// The reader's error says only its category and where it stopped; the rest is read from the
/// text at that place. Where the text is JSON and the reader still stopped on its syntax, one of
/// two things happened, told apart by what is there: a number the reader cannot hold (the
/// reader stops after it, and it is beyond a float's range), or a list with more values than the
/// array or message it stands for (the reader stops on the first value too many, just after a
/// comma). Anything else stays a syntax fault.
fn fault(json: &[u8], path: FieldPath, leaf: Leaf, error: &serde_json::Error) -> Malformed {
    let detail = error.to_string();
    match error.classify() {
        Category::Data => return Malformed::Shape { path, detail },
        Category::Syntax if is_json(json) => {
            let read = consumed(json, error);
            if let Some(number) = number_ending(read).filter(|number| overflows(number)) {
                return Malformed::Shape {
                    detail: out_of_range(number, leaf, error),
                    path,
                };
            }
            if let Some((&at, before)) = read.split_last() {
                if starts_value(at) && last_token(before) == Some(b',') {
                    return Malformed::Shape {
                        path,
                        detail: format!("a list with more values than its field takes: {detail}"),
                    };
                }
            }
        }
        Category::Syntax | Category::Io | Category::Eof => {}
    }
    Malformed::NotJson { path, detail }
}

/// Whether the text is JSON (one value, strings in UTF-8), checked without building it.
fn is_json(json: &[u8]) -> bool {
    core::str::from_utf8(json).is_ok()
        && serde_json::from_slice::<serde::de::IgnoredAny>(json).is_ok()
}

/// The text the reader consumed before it stopped, the byte it stopped on included (the reader
/// counts lines from 1 and the bytes of a line it consumed as the column).
fn consumed<'j>(json: &'j [u8], error: &serde_json::Error) -> &'j [u8] {
    let mut start = 0;
    for _ in 1..error.line() {
        match json
            .get(start..)
            .and_then(|rest| rest.iter().position(|&b| b == b'\n'))
        {
            Some(newline) => start += newline + 1,
            None => return json,
        }
    }
    let end = start.saturating_add(error.column()).min(json.len());
    json.get(..end).unwrap_or(json)
}

/// A JSON number's characters.
const fn in_number(byte: u8) -> bool {
    matches!(byte, b'0'..=b'9' | b'-' | b'+' | b'.' | b'e' | b'E')
}

/// The number `text` ends with, if it ends with one.
fn number_ending(text: &[u8]) -> Option<&str> {
    let start = text
        .iter()
        .rposition(|&byte| !in_number(byte))
        .map_or(0, |at| at + 1);
    let digits = text.get(start..)?;
    core::str::from_utf8(digits)
        .ok()
        .filter(|number| !number.is_empty())
}

/// Whether a number is too large for a float field: beyond a 32-bit float, the narrowest float
/// a message has (the reader refuses such a number for an `f32` field, and beyond a 64-bit float
/// for any field).
fn overflows(number: &str) -> bool {
    number.parse::<f32>().is_ok_and(f32::is_infinite)
}

/// Whether a JSON value can start with this byte.
const fn starts_value(byte: u8) -> bool {
    matches!(byte, b'{' | b'[' | b'"' | b't' | b'f' | b'n') || in_number(byte)
}

/// The last byte of `text` that is not white space.
fn last_token(text: &[u8]) -> Option<u8> {
    text.iter()
        .rev()
        .find(|byte| !byte.is_ascii_whitespace())
        .copied()
}

/// At most this many characters of a number from the input are quoted in a message.
const NUMBER_QUOTED: usize = 64;

/// The explanation of a number too large for its field: the number as written (cut short if
/// long), the type, and where.
fn out_of_range(number: &str, leaf: Leaf, error: &serde_json::Error) -> String {
    let (line, column) = (error.line(), error.column());
    let number = match number.get(..NUMBER_QUOTED) {
        Some(head) if number.len() > NUMBER_QUOTED => {
            format!("{head}… ({} characters)", number.len())
        }
        _ => number.to_owned(),
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

    /// Reads a request of this service from its JSON (rosbridge's `args`). Reading needs no
    /// state, so a server reads before it takes any lock.
    ///
    /// # Errors
    /// [`Malformed::TooLarge`] for a request longer than [`MAX_REQUEST_BYTES`], refused unread;
    /// otherwise as [`from_json`], naming the field that does not decode.
    pub fn read(self, json: &[u8]) -> Result<Request, Malformed> {
        check_request_len(json.len())?;
        Ok(match self {
            Self::SetCommands => Request::SetCommands(from_json(json)?),
            Self::SetPolicies => Request::SetPolicies(from_json(json)?),
            Self::GetPolicies => Request::GetPolicies(from_json(json)?),
        })
    }

    /// This service's response to a request that could not be read: `PARAMETER_ERROR` with the
    /// fault's explanation, every other field at its default.
    #[must_use]
    pub fn refusal(self, malformed: &Malformed) -> Response {
        self.refused(malformed.to_status())
    }

    /// This service's response with `status`, every other field at its default: a refusal
    /// before the request reached the core.
    #[must_use]
    pub fn refused(self, status: ResponseStatus) -> Response {
        match self {
            Self::SetCommands => Response::SetCommands(SetCooperationCommandsResponse { status }),
            Self::SetPolicies => Response::SetPolicies(SetCooperationPoliciesResponse { status }),
            Self::GetPolicies => Response::GetPolicies(GetCooperationPoliciesResponse {
                status,
                policies: Vec::new(),
            }),
        }
    }
}

/// A request of one of the three services, read by [`Service::read`].
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Request {
    /// A `set_commands` request.
    SetCommands(SetCooperationCommandsRequest),
    /// A `set_policies` request.
    SetPolicies(SetCooperationPoliciesRequest),
    /// A `get_policies` request.
    GetPolicies(GetCooperationPoliciesRequest),
}

impl Request {
    /// The service it is a request of.
    #[must_use]
    pub const fn service(&self) -> Service {
        match self {
            Self::SetCommands(_) => Service::SetCommands,
            Self::SetPolicies(_) => Service::SetPolicies,
            Self::GetPolicies(_) => Service::GetPolicies,
        }
    }

    /// Answers it from `state`: [`set_commands`], [`set_policies`] or [`get_policies`].
    pub fn answer(&self, state: &mut State) -> Answer<Response> {
        match self {
            Self::SetCommands(request) => set_commands(state, request).map(Response::SetCommands),
            Self::SetPolicies(request) => set_policies(state, request).map(Response::SetPolicies),
            Self::GetPolicies(request) => Answer {
                response: Response::GetPolicies(get_policies(state, request)),
                changed: false,
            },
        }
    }
}

/// A response of one of the three services. It is written as the response message itself
/// (rosbridge's `values`), with nothing around it.
#[derive(Clone, PartialEq, Eq, Debug, Serialize)]
#[serde(untagged)]
pub enum Response {
    /// A `set_commands` response.
    SetCommands(SetCooperationCommandsResponse),
    /// A `set_policies` response.
    SetPolicies(SetCooperationPoliciesResponse),
    /// A `get_policies` response.
    GetPolicies(GetCooperationPoliciesResponse),
}

impl Response {
    /// The response's status.
    #[must_use]
    pub const fn status(&self) -> &ResponseStatus {
        match self {
            Self::SetCommands(response) => &response.status,
            Self::SetPolicies(response) => &response.status,
            Self::GetPolicies(response) => &response.status,
        }
    }
}

/// A service's response, and whether the call changed the state: an operator decision or a
/// policy that is now other than it was. A refused or empty call, or one that sets what was
/// already set, changes nothing.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Answer<R> {
    /// The response to send.
    pub response: R,
    /// Whether the state changed.
    pub changed: bool,
}

impl<R> Answer<R> {
    /// A refusal: `status`, nothing changed.
    fn refused(status: ResponseStatus) -> Self
    where
        R: From<ResponseStatus>,
    {
        Self {
            response: R::from(status),
            changed: false,
        }
    }

    /// The same answer with its response converted.
    pub fn map<T>(self, convert: impl FnOnce(R) -> T) -> Answer<T> {
        Answer {
            response: convert(self.response),
            changed: self.changed,
        }
    }
}

impl From<ResponseStatus> for SetCooperationCommandsResponse {
    fn from(status: ResponseStatus) -> Self {
        Self { status }
    }
}

impl From<ResponseStatus> for SetCooperationPoliciesResponse {
    fn from(status: ResponseStatus) -> Self {
        Self { status }
    }
}
