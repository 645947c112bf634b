//! The scene lifecycle.

use core::fmt;

/// Where a scene is in its lifecycle, as its owner reports it.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Phase {
    /// Registered, not yet executing. Every scene starts here.
    Waiting,
    /// Executing.
    Running,
    /// Being abandoned; the operator can no longer change the decision.
    Aborting,
    /// Completed. Terminal: the scene retires.
    Succeeded,
    /// Cancelled. Terminal: the scene retires.
    Failed,
}

impl Phase {
    /// Every phase, in lifecycle order.
    pub const ALL: [Self; 5] = [
        Self::Waiting,
        Self::Running,
        Self::Aborting,
        Self::Succeeded,
        Self::Failed,
    ];

    /// The spec's name for the phase.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Waiting => "waiting",
            Self::Running => "running",
            Self::Aborting => "aborting",
            Self::Succeeded => "succeeded",
            Self::Failed => "failed",
        }
    }

    /// Whether the phase ends the scene (spec `[COOP-OWN-FINISH.1]`).
    #[must_use]
    pub const fn is_terminal(self) -> bool {
        matches!(self, Self::Succeeded | Self::Failed)
    }

    /// Whether operator commands are accepted in this phase (spec `[COOP-CANCELLABLE.1]`).
    #[must_use]
    pub const fn is_cancellable(self) -> bool {
        matches!(self, Self::Waiting | Self::Running)
    }

    /// Whether an owner may move a scene from `self` to `to`: the lifecycle table (spec §7).
    #[must_use]
    pub const fn may_become(self, to: Self) -> bool {
        use Phase::{Aborting, Failed, Running, Succeeded, Waiting};
        matches!(
            (self, to),
            (Waiting, Waiting | Running | Failed)
                | (Running, Running | Aborting | Succeeded | Failed)
                | (Aborting, Aborting | Failed)
        )
    }
}

impl fmt::Display for Phase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}
