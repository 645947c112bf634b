//! `autoware_adapi_v1_msgs/ResponseStatus`: the AD API's answer to every call, and how the
//! core's results map onto it (`[COOP-API-STATUS.1]`).

use cooperation::{Rejection, Transition};
use serde::{Deserialize, Serialize};

/// The AD API `ResponseStatus`: success, a code and a message (`[COOP-API-STATUS.1]`). Code 0
/// is plain success; the constants are errors (5xxxx) and warnings (6xxxx).
///
/// Read as rosbridge reads a message: a field left out takes its default, and a field it does
/// not have is refused.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ResponseStatus {
    /// Whether the call did what was asked.
    pub success: bool,
    /// `0` on plain success; otherwise one of the constants below.
    pub code: u16,
    /// Empty on plain success; otherwise what went wrong or what to know.
    pub message: String,
}

impl ResponseStatus {
    /// An error of no more specific kind.
    pub const UNKNOWN: u16 = 50_000;
    /// The service is not ready.
    pub const SERVICE_UNREADY: u16 = 50_001;
    /// The service timed out.
    pub const SERVICE_TIMEOUT: u16 = 50_002;
    /// A transform failed.
    pub const TRANSFORM_ERROR: u16 = 50_003;
    /// The request's parameters were refused: every rejection of a call.
    pub const PARAMETER_ERROR: u16 = 50_004;
    /// Warning: the call is deprecated.
    pub const DEPRECATED: u16 = 60_000;
    /// Warning: the call succeeded but changed nothing (an empty batch).
    pub const NO_EFFECT: u16 = 60_001;

    /// Plain success: `success = true`, `code = 0`, empty message.
    #[must_use]
    pub const fn success() -> Self {
        Self {
            success: true,
            code: 0,
            message: String::new(),
        }
    }

    /// The status of a batch call of `len` entries with this result from the core: a rejection
    /// is a `PARAMETER_ERROR` carrying its explanation; an accepted empty batch is a success
    /// with the `NO_EFFECT` warning.
    #[must_use]
    pub fn for_batch(len: usize, result: &Result<Transition, Rejection>) -> Self {
        match result {
            // [COOP-API-STATUS.1]
            Err(rejection) => Self {
                success: false,
                code: Self::PARAMETER_ERROR,
                message: rejection.to_string(),
            },
            Ok(_) if len == 0 => Self {
                success: true,
                code: Self::NO_EFFECT,
                message: "the batch is empty".into(),
            },
            Ok(_) => Self::success(),
        }
    }
}
