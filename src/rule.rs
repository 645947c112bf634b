//! The spec's transition rules, as data.

use core::fmt;

/// A rule of the specification's §5: every transition and every rejection names one.
///
/// [`Rule::tag`] is the rule's stable tag in `spec/cooperation.md`; a test keeps the two sets
/// equal.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Rule {
    /// A new identifier becomes a live scene.
    RegisterNew,
    /// Registering a live identifier again is rejected.
    RegisterLive,
    /// Registering a retired identifier is rejected.
    RegisterRetired,
    /// Registering a scene for a module without a policy is rejected.
    RegisterModule,
    /// Registering beyond the live-scene limit is rejected.
    RegisterFull,
    /// An owner input naming a live scene under another module is rejected.
    OwnerModule,
    /// An owner update or removal for an unknown identifier is rejected.
    OwnerUnknown,
    /// An owner update or removal for a retired identifier is rejected.
    OwnerRetired,
    /// An owner update whose geometry is of the other kind is rejected.
    OwnerKind,
    /// An owner update to a phase the lifecycle table forbids is rejected.
    OwnerTransition,
    /// An owner update to a non-terminal phase is applied.
    OwnerUpdate,
    /// An owner update to a terminal phase retires the scene.
    OwnerFinish,
    /// An owner removal retires the scene.
    OwnerRemove,
    /// Time passes and no scene outlives the time-to-live.
    TimeAge,
    /// Time passes and scenes that outlive the time-to-live retire.
    TimeExpire,
    /// A batch of commands in which every command can apply is applied.
    CommandApply,
    /// A batch with a command for an unknown identifier is rejected.
    CommandUnknown,
    /// A batch with a command for a retired identifier is rejected.
    CommandRetired,
    /// A batch with a command for a scene that is not cancellable is rejected.
    CommandNotCancellable,
    /// A batch naming an identifier twice is rejected.
    CommandDuplicate,
    /// A batch of policies for known modules is applied.
    PolicySet,
    /// A batch with a policy for a module without a policy is rejected.
    PolicyUnknown,
    /// A batch naming a module twice is rejected.
    PolicyDuplicate,
    /// A batch longer than the batch limit is rejected.
    BatchLimit,
}

impl Rule {
    /// Every rule, in spec order.
    pub const ALL: [Self; 24] = [
        Self::RegisterNew,
        Self::RegisterLive,
        Self::RegisterRetired,
        Self::RegisterModule,
        Self::RegisterFull,
        Self::OwnerModule,
        Self::OwnerUnknown,
        Self::OwnerRetired,
        Self::OwnerKind,
        Self::OwnerTransition,
        Self::OwnerUpdate,
        Self::OwnerFinish,
        Self::OwnerRemove,
        Self::TimeAge,
        Self::TimeExpire,
        Self::CommandApply,
        Self::CommandUnknown,
        Self::CommandRetired,
        Self::CommandNotCancellable,
        Self::CommandDuplicate,
        Self::PolicySet,
        Self::PolicyUnknown,
        Self::PolicyDuplicate,
        Self::BatchLimit,
    ];

    /// The rule's tag in the specification, with its version.
    #[must_use]
    pub const fn tag(self) -> &'static str {
        match self {
            Self::RegisterNew => "COOP-REG-NEW.1",
            Self::RegisterLive => "COOP-REG-LIVE.1",
            Self::RegisterRetired => "COOP-REG-RETIRED.1",
            Self::RegisterModule => "COOP-REG-MODULE.1",
            Self::RegisterFull => "COOP-REG-FULL.1",
            Self::OwnerModule => "COOP-OWN-MODULE.1",
            Self::OwnerUnknown => "COOP-OWN-UNKNOWN.1",
            Self::OwnerRetired => "COOP-OWN-RETIRED.1",
            Self::OwnerKind => "COOP-OWN-KIND.1",
            Self::OwnerTransition => "COOP-OWN-TRANSITION.1",
            Self::OwnerUpdate => "COOP-OWN-UPDATE.1",
            Self::OwnerFinish => "COOP-OWN-FINISH.1",
            Self::OwnerRemove => "COOP-OWN-REMOVE.1",
            Self::TimeAge => "COOP-TIME-AGE.1",
            Self::TimeExpire => "COOP-TIME-EXPIRE.1",
            Self::CommandApply => "COOP-CMD-APPLY.1",
            Self::CommandUnknown => "COOP-CMD-UNKNOWN.1",
            Self::CommandRetired => "COOP-CMD-RETIRED.1",
            Self::CommandNotCancellable => "COOP-CMD-NOT-CANCELLABLE.1",
            Self::CommandDuplicate => "COOP-CMD-DUPLICATE.1",
            Self::PolicySet => "COOP-POL-SET.1",
            Self::PolicyUnknown => "COOP-POL-UNKNOWN.1",
            Self::PolicyDuplicate => "COOP-POL-DUPLICATE.1",
            Self::BatchLimit => "COOP-BATCH-LIMIT.1",
        }
    }

    /// Whether the rule rejects its input (and so leaves the state unchanged).
    #[must_use]
    pub const fn is_rejection(self) -> bool {
        !matches!(
            self,
            Self::RegisterNew
                | Self::OwnerUpdate
                | Self::OwnerFinish
                | Self::OwnerRemove
                | Self::TimeAge
                | Self::TimeExpire
                | Self::CommandApply
                | Self::PolicySet
        )
    }
}

impl fmt::Display for Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.tag())
    }
}
