//! Why the relay refuses a module's message or an operator's call.

use core::fmt;

use cooperation::{OperatorDecision, SceneId};

use crate::rtc::{FieldError, RtcError};
use crate::Time;

/// A status array the relay did not take: nothing of it reached the core
/// (`[COOP-RELAY-REPORT.1]`).
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum ArrayError {
    /// The interface is not one the relay serves.
    UnknownInterface {
        /// The name.
        name: String,
    },
    /// A constant of the array is undefined.
    Constant {
        /// The interface.
        interface: String,
        /// The field and its value.
        error: FieldError,
    },
    /// The array is not newer than one already taken: it arrived late, or twice.
    Late {
        /// The interface.
        interface: String,
        /// The array's stamp.
        stamp: Time,
        /// The newest stamp taken.
        newest: Time,
    },
}

/// What a status array the relay took did: each scene that could not be reported, with the
/// adapter's reason (the others were), and each scene it removed because the array no longer
/// lists it.
#[derive(Clone, PartialEq, Debug, Default)]
pub struct ArrayTaken {
    /// Scenes the adapter refused, each with its reason.
    pub refused: Vec<(SceneId, RtcError)>,
    /// Scenes removed: live, the interface's, and absent from the array.
    pub removed: Vec<SceneId>,
}

/// An operator's call the relay refuses before forwarding anything.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum RelayRefusal {
    /// A command an upstream RTC interface cannot take for one scene.
    Inexpressible {
        /// The command's place.
        index: usize,
        /// Its scene.
        id: SceneId,
        /// Its decision.
        decision: OperatorDecision,
    },
    /// A command for a scene no relayed module reported (a core the host fed itself).
    NoModule {
        /// The command's place.
        index: usize,
        /// Its scene.
        id: SceneId,
    },
    /// Policies that would give the modules of one interface different policies.
    MixedPolicies {
        /// The interface.
        interface: String,
    },
}

/// A stamp as seconds with nanoseconds.
struct Stamp(Time);

impl fmt::Display for Stamp {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{:09} s", self.0.sec, self.0.nanosec)
    }
}

impl fmt::Display for ArrayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownInterface { name } => {
                write!(f, "no RTC interface named {name} is relayed")
            }
            Self::Constant { interface, error } => {
                write!(f, "the status array of {interface} is refused: {error}")
            }
            Self::Late {
                interface,
                stamp,
                newest,
            } => write!(
                f,
                "the status array of {interface} stamped {} is not newer than the one taken, \
                 stamped {}: late or repeated, not taken",
                Stamp(*stamp),
                Stamp(*newest)
            ),
        }
    }
}

impl std::error::Error for ArrayError {}

impl fmt::Display for RelayRefusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Inexpressible {
                index,
                id,
                decision,
            } => write!(
                f,
                "commands[{index}] sets scene {id} to {decision}, which a planning module's RTC \
                 interface cannot take for one scene (it takes activate or deactivate)"
            ),
            Self::NoModule { index, id } => write!(
                f,
                "commands[{index}] names scene {id}, which no relayed planning module reported: \
                 there is no module to forward it to"
            ),
            Self::MixedPolicies { interface } => write!(
                f,
                "the policies would differ between the modules of {interface}, which has one \
                 auto-mode switch for all of them"
            ),
        }
    }
}

impl std::error::Error for RelayRefusal {}
