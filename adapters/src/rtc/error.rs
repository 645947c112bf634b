//! The adapter's typed errors: a malformed field, an unknown interface, a scene of another
//! interface, or the core's own rejection.

use core::fmt;

use cooperation::{Module, Phase, Rejection, SceneId};

use super::ModuleType;
use crate::path::{FieldPath, PathSegment};

/// A message field whose value is not one its message defines (`[COOP-DEV-CONSTANTS.1]`).
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct FieldError {
    /// The field's path in the message, for example `commands[2].command.type`: the same
    /// paths the AD API messages' errors name ([`FieldPath`]).
    pub field: FieldPath,
    /// The value that was given.
    pub value: u8,
    /// What the field accepts, for example `DEACTIVATE (0) or ACTIVATE (1)`.
    pub expected: &'static str,
}

impl FieldError {
    pub(crate) fn new(field: &str, value: u8, expected: &'static str) -> Self {
        Self {
            field: FieldPath::field(field),
            value,
            expected,
        }
    }

    /// The same error, inside the field `outer` of the enclosing message.
    #[must_use]
    pub fn within(mut self, outer: &str) -> Self {
        self.field.prepend(PathSegment::Field(outer.to_owned()));
        self
    }

    /// The same error, inside entry `index` of the enclosing list.
    #[must_use]
    pub fn at_index(mut self, index: usize) -> Self {
        self.field.prepend(PathSegment::Index(index));
        self
    }
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} is {}, which is not {}",
            self.field, self.value, self.expected
        )
    }
}

impl std::error::Error for FieldError {}

/// Why the RTC adapter refused a call. A refused call changes nothing.
#[derive(Clone, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum RtcError {
    /// A field of a message or argument has a value its message does not define
    /// (`[COOP-DEV-CONSTANTS.1]`).
    Field(FieldError),
    /// No binding has this interface name (`[COOP-DEV-INTERFACE-NAME.1]`).
    UnknownInterface {
        /// The name asked for.
        name: String,
    },
    /// Two bindings have the same interface name.
    DuplicateInterface {
        /// The name.
        name: String,
    },
    /// A binding has no sequence, so its scenes could belong to no module.
    NoSequence {
        /// The interface name.
        name: String,
    },
    /// A module of the binding has no cooperation policy in the core, so its scenes could not
    /// register.
    Unconfigured {
        /// The interface name.
        name: String,
        /// The first of its modules without a policy.
        module: Module,
    },
    /// The owner stated a sequence the interface does not bind: its scenes cannot belong to that
    /// module (`[COOP-DEV-SEQUENCE.1]`). Nothing changed.
    UnboundSequence {
        /// The interface name.
        name: String,
        /// The module the stated sequence makes.
        module: Module,
        /// The modules the interface binds.
        bound: Vec<Module>,
    },
    /// A scene that is not registered reported without a sequence through an interface that
    /// binds several, so its module is unknown: the owner must state it
    /// (`[COOP-DEV-SEQUENCE.1]`). Nothing was registered.
    SequenceUnstated {
        /// The scene.
        id: SceneId,
        /// The interface name.
        name: String,
        /// The modules the interface binds.
        bound: Vec<Module>,
    },
    /// No interface reports this module type, so an auto-mode request for it reaches nothing
    /// (`[COOP-DEV-ROUTING.1]`).
    NoInterface {
        /// The module type asked for.
        module: ModuleType,
    },
    /// The scene is live, but not one of this interface's (`[COOP-DEV-ID-REUSE.1]`).
    ForeignScene {
        /// The scene.
        id: SceneId,
        /// The interface that was asked.
        interface: String,
        /// The interface the scene belongs to, if it registered through this adapter.
        owner: Option<String>,
    },
    /// A scene that is not registered cannot start in this phase: it registers waiting, and
    /// the lifecycle does not allow waiting to become this phase; nothing was registered
    /// (`[COOP-DEV-REGISTER-PHASE.1]`).
    InitialPhase {
        /// The scene.
        id: SceneId,
        /// The phase asked for.
        phase: Phase,
        /// The core's rejection of the move from waiting (boxed: it is rare, and keeps every
        /// other error small).
        rejection: Box<Rejection>,
    },
    /// A new scene reported through an interface that holds its quota of live scenes
    /// ([`Rtc::with_scene_quota`](super::Rtc::with_scene_quota)); nothing was registered.
    SceneQuota {
        /// The scene.
        id: SceneId,
        /// The interface.
        interface: String,
        /// Its quota.
        quota: usize,
    },
    /// The core refused the input (`[COOP-DEV-SILENT-DROP.1]`).
    Core(Rejection),
}

impl RtcError {
    /// The core's rejection, if the core refused the call.
    #[must_use]
    pub fn rejection(&self) -> Option<&Rejection> {
        match self {
            Self::Core(rejection) => Some(rejection),
            Self::InitialPhase { rejection, .. } => Some(rejection),
            _ => None,
        }
    }
}

impl From<Rejection> for RtcError {
    fn from(rejection: Rejection) -> Self {
        Self::Core(rejection)
    }
}

impl From<FieldError> for RtcError {
    fn from(error: FieldError) -> Self {
        Self::Field(error)
    }
}

impl fmt::Display for RtcError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Field(error) => error.fmt(f),
            Self::UnknownInterface { name } => {
                write!(f, "no RTC interface is bound to the name {name:?}")
            }
            Self::DuplicateInterface { name } => {
                write!(f, "the RTC interface name {name:?} is bound twice")
            }
            Self::NoSequence { name } => {
                write!(f, "the RTC interface {name:?} is bound to no sequence")
            }
            Self::Unconfigured { name, module } => write!(
                f,
                "RTC interface {name:?} is bound to module {module}, which has no cooperation policy"
            ),
            Self::UnboundSequence {
                name,
                module,
                bound,
            } => write!(
                f,
                "RTC interface {name:?} has no scenes of {module}, only of {}",
                Modules(bound)
            ),
            Self::SequenceUnstated { id, name, bound } => write!(
                f,
                "scene {id} is not registered, and RTC interface {name:?} has scenes of {}: \
                 state its sequence",
                Modules(bound)
            ),
            Self::NoInterface { module } => {
                write!(f, "no RTC interface reports module type {module}")
            }
            Self::ForeignScene {
                id,
                interface,
                owner: Some(owner),
            } => write!(
                f,
                "scene {id} belongs to RTC interface {owner:?}, not {interface:?}"
            ),
            Self::ForeignScene {
                id,
                interface,
                owner: None,
            } => write!(
                f,
                "scene {id} did not register through RTC interface {interface:?}"
            ),
            Self::InitialPhase {
                id,
                phase,
                rejection,
            } => write!(
                f,
                "scene {id} is not registered and cannot start {phase}: {rejection}"
            ),
            Self::SceneQuota {
                id,
                interface,
                quota,
            } => write!(
                f,
                "scene {id} is not registered, and RTC interface {interface:?} already has \
                 {quota} live scenes, the most it may have"
            ),
            Self::Core(rejection) => rejection.fmt(f),
        }
    }
}

/// A list of modules in words: `a`, `a or b`, `a, b or c`.
struct Modules<'a>(&'a [Module]);

impl fmt::Display for Modules<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let last = self.0.len().saturating_sub(1);
        for (at, module) in self.0.iter().enumerate() {
            if at > 0 {
                f.write_str(if at == last { " or " } else { ", " })?;
            }
            module.fmt(f)?;
        }
        Ok(())
    }
}

impl std::error::Error for RtcError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Field(error) => Some(error),
            Self::Core(rejection) => Some(rejection),
            Self::InitialPhase { rejection, .. } => Some(rejection.as_ref()),
            _ => None,
        }
    }
}
