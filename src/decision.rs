//! Decisions, policies and the merged decision.

use core::fmt;

/// A module decision, or a merged decision: what the planner should do with a scene.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Decision {
    /// Plan with priority on safety (for example: stop, keep the lane). AD API `DEACTIVATE`.
    Deactivate,
    /// Plan with priority on driving (for example: pass, change lanes). AD API `ACTIVATE`.
    Activate,
}

impl Decision {
    /// Both decisions.
    pub const ALL: [Self; 2] = [Self::Deactivate, Self::Activate];

    /// The spec's word for the decision.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Deactivate => "deactivate",
            Self::Activate => "activate",
        }
    }
}

impl fmt::Display for Decision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// An operator decision. Every scene starts [`Undecided`](Self::Undecided) ("none").
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum OperatorDecision {
    /// The operator wants the scene planned with priority on safety. AD API `DEACTIVATE`.
    Deactivate,
    /// The operator wants the scene planned with priority on driving. AD API `ACTIVATE`.
    Activate,
    /// The operator wants the module decision followed. AD API `AUTONOMOUS`.
    Autonomous,
    /// "none": there is no operator decision, so the policy applies. AD API `UNDECIDED`.
    #[default]
    #[cfg_attr(feature = "serde", serde(rename = "none"))]
    Undecided,
}

impl OperatorDecision {
    /// Every operator decision, in the AD API's order.
    pub const ALL: [Self; 4] = [
        Self::Deactivate,
        Self::Activate,
        Self::Autonomous,
        Self::Undecided,
    ];

    /// The spec's word for the decision (`none` for [`Undecided`](Self::Undecided)).
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Deactivate => "deactivate",
            Self::Activate => "activate",
            Self::Autonomous => "autonomous",
            Self::Undecided => "none",
        }
    }
}

impl fmt::Display for OperatorDecision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A module's cooperation policy: what an undecided operator means.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Policy {
    /// The module's decision is followed without an operator decision. AD API `OPTIONAL`.
    Optional,
    /// Driving on needs an operator decision. AD API `REQUIRED`.
    Required,
}

impl Policy {
    /// Both policies.
    pub const ALL: [Self; 2] = [Self::Optional, Self::Required];

    /// The spec's word for the policy.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Optional => "optional",
            Self::Required => "required",
        }
    }
}

impl fmt::Display for Policy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The merged decision the planner drives with (spec `[COOP-MERGE.1]`).
///
/// An explicit operator decision wins; `autonomous` follows the module; with no operator
/// decision, `required` deactivates and `optional` follows the module.
///
/// ```
/// use cooperation::{merge, Decision, OperatorDecision, Policy};
/// assert_eq!(
///     merge(OperatorDecision::Activate, Policy::Required, Decision::Deactivate),
///     Decision::Activate,
/// );
/// assert_eq!(
///     merge(OperatorDecision::Undecided, Policy::Required, Decision::Activate),
///     Decision::Deactivate,
/// );
/// ```
#[must_use]
pub const fn merge(operator: OperatorDecision, policy: Policy, module: Decision) -> Decision {
    // [COOP-MERGE.1]
    match (operator, policy) {
        (OperatorDecision::Deactivate, _) => Decision::Deactivate,
        (OperatorDecision::Activate, _) => Decision::Activate,
        (OperatorDecision::Autonomous, _) => module,
        (OperatorDecision::Undecided, Policy::Required) => Decision::Deactivate,
        (OperatorDecision::Undecided, Policy::Optional) => module,
    }
}
