//! The messages in CDR, as ROS 2 sends them over DDS: the same message types as the rosbridge
//! JSON form ([`wire`](crate::wire), [`rtc`](crate::rtc)), written and read through their serde
//! implementations, so that both forms come from one definition.
//!
//! The form is OMG's plain CDR (XCDR version 1), little-endian, as `rmw_cyclonedds_cpp` and
//! `rmw_fastrtps_cpp` send ROS 2 messages: a four-byte encapsulation header (`00 01 00 00`),
//! then each field in order, each primitive aligned to its size (at most 8) from the start of
//! the data after the header; a reader ignores the padding's values. A string is a `u32` length counting a final NUL, its UTF-8 bytes
//! and the NUL; a sequence (`T[]`, `T[<=N]`) is a `u32` count and its elements; a fixed array
//! (`T[N]`, a Rust array) is its elements alone; a struct with no field (a service request
//! with no argument) is one zero byte, the member ROS 2 adds to it. A UUID
//! (`unique_identifier_msgs/UUID`, a `uint8[16]`) is its sixteen bytes.
//!
//! Reading is strict, for bytes that come from any peer: a truncated message, a boolean that is
//! neither 0 nor 1, a string without its final NUL, with another NUL or not UTF-8, an
//! unknown encapsulation, and more than three bytes left over are each a [`CdrError`] naming where it happened,
//! and so is a value its type refuses (a `nanosec` of 2e9, a name that is no sequence): at the
//! offset where that value starts;
//! a count is never trusted beyond the bytes that remain, so a short message cannot make the
//! reader allocate much. Nothing here panics on any input.
//!
//! Why this module and not the `cdr-encoding` crate (the one `rustdds` uses, so already in the
//! lock file): that reader accepts a string without its final NUL, or with another byte in its
//! place, logging a line and going on; it does not look for a NUL inside a string; its errors
//! say what went wrong but not at which offset; and the encapsulation header and the bytes left
//! over are the caller's. Bytes from any peer are refused here, each fault with its place, so the
//! reader is written out (about 350 lines each way) and fuzzed (`fuzz/fuzz_targets/cdr_decode.rs`) rather
//! than wrapped.
//!
//! ```
//! use cooperation_adapters::cdr;
//! use cooperation_adapters::wire::{CooperationDecision, CooperationCommand, SetCooperationCommandsRequest, Uuid};
//!
//! let request = SetCooperationCommandsRequest {
//!     commands: vec![CooperationCommand {
//!         uuid: Uuid { uuid: core::array::from_fn(|i| i as u8) },
//!         cooperator: CooperationDecision { decision: CooperationDecision::ACTIVATE },
//!     }],
//! };
//! let bytes = cdr::to_vec(&request)?;
//! assert_eq!(bytes.len(), 4 + 4 + 16 + 1);
//! assert_eq!(cdr::from_slice::<SetCooperationCommandsRequest>(&bytes)?, request);
//!
//! // Cut short, the bytes do not read.
//! assert!(cdr::from_slice::<SetCooperationCommandsRequest>(&bytes[..20]).is_err());
//! # Ok::<(), cdr::CdrError>(())
//! ```

mod de;
mod ser;

use core::fmt;

pub use de::from_slice;
pub use ser::to_vec;

/// The encapsulation header of little-endian plain CDR.
pub const CDR_LE: [u8; 4] = [0, 1, 0, 0];

/// Why a message could not be written or read.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct CdrError {
    /// What went wrong.
    pub message: String,
    /// The offset in the data (after the encapsulation header) where it did.
    pub offset: usize,
}

impl fmt::Display for CdrError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CDR at byte {}: {}", self.offset, self.message)
    }
}

impl std::error::Error for CdrError {}

impl serde::ser::Error for CdrError {
    fn custom<T: fmt::Display>(message: T) -> Self {
        Self {
            message: message.to_string(),
            offset: 0,
        }
    }
}

impl serde::de::Error for CdrError {
    /// An error a message type's own deserialisation raises (a value out of its range, a name
    /// that is no sequence), at no offset yet: the reader places it at the start of the value
    /// that was being read.
    fn custom<T: fmt::Display>(message: T) -> Self {
        Self {
            message: message.to_string(),
            offset: UNPLACED,
        }
    }
}

/// The offset of an error the reader has not placed yet.
const UNPLACED: usize = usize::MAX;

impl CdrError {
    /// This error, at `offset` if it was raised with none (by a type's own deserialisation).
    fn placed_at(self, offset: usize) -> Self {
        if self.offset == UNPLACED {
            Self { offset, ..self }
        } else {
            self
        }
    }
}
