//! Rejections: the typed, explained "no" for an input. A rejected input changes nothing.

use core::fmt;

use crate::{FactorKind, Module, Phase, Rule, SceneId};

/// Why an identifier retired. Retired identifiers never become live again (spec §5.1).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum RetireReason {
    /// The owner reported the scene completed.
    Succeeded,
    /// The owner reported the scene cancelled.
    Failed,
    /// The owner removed the scene.
    Removed,
    /// The owner stopped updating the scene for longer than the time-to-live.
    Expired,
}

impl RetireReason {
    /// The spec's word for the reason.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::Succeeded => "succeeded",
            Self::Failed => "failed",
            Self::Removed => "removed",
            Self::Expired => "expired",
        }
    }
}

impl fmt::Display for RetireReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What the core remembers of a retired identifier.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Retirement {
    /// The module the scene belonged to.
    pub module: Module,
    /// Why it retired.
    pub reason: RetireReason,
}

/// Why one command of a rejected batch could not apply.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CommandFailure {
    /// No scene has this identifier (`[COOP-CMD-UNKNOWN.1]`).
    UnknownScene,
    /// The identifier is retired (`[COOP-CMD-RETIRED.1]`).
    RetiredScene(RetireReason),
    /// The scene is live but not cancellable in this phase (`[COOP-CMD-NOT-CANCELLABLE.1]`).
    NotCancellable(Phase),
    /// An earlier command of the batch names the same identifier: the command is invalid
    /// (`[COOP-CMD-DUPLICATE.1]`).
    DuplicateId,
}

impl CommandFailure {
    /// The rule that rejects a batch because of this failure.
    #[must_use]
    pub const fn rule(self) -> Rule {
        match self {
            Self::UnknownScene => Rule::CommandUnknown,
            Self::RetiredScene(_) => Rule::CommandRetired,
            Self::NotCancellable(_) => Rule::CommandNotCancellable,
            Self::DuplicateId => Rule::CommandDuplicate,
        }
    }
}

impl fmt::Display for CommandFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownScene => f.write_str("unknown scene"),
            Self::RetiredScene(reason) => write!(f, "retired scene ({reason})"),
            Self::NotCancellable(phase) => write!(f, "not cancellable while {phase}"),
            Self::DuplicateId => f.write_str("invalid: the batch names this scene twice"),
        }
    }
}

/// The outcome of one command of a rejected `SetCommands` batch ([`Rejection::Commands`]).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CommandOutcome {
    /// The command could have applied, but another command of the batch failed, so nothing was.
    Withheld,
    /// The command could not apply.
    Failed(CommandFailure),
}

/// Why an input was rejected. The state is left exactly as it was.
#[derive(Clone, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
#[non_exhaustive]
pub enum Rejection {
    /// `[COOP-REG-LIVE.1]`: the identifier is already a live scene of this module.
    AlreadyLive {
        /// The identifier.
        id: SceneId,
    },
    /// `[COOP-REG-RETIRED.1]`: the identifier is retired and can never be live again.
    Revival {
        /// The identifier.
        id: SceneId,
        /// What it retired as.
        retirement: Retirement,
    },
    /// `[COOP-REG-MODULE.1]`: the module has no cooperation policy, so it cannot have scenes.
    UnsupportedModule {
        /// The identifier that was to be registered.
        id: SceneId,
        /// The module.
        module: Module,
    },
    /// `[COOP-REG-FULL.1]`: the live-scene limit is reached.
    SceneLimit {
        /// The limit.
        limit: usize,
    },
    /// `[COOP-OWN-MODULE.1]`: the scene belongs to another module; identifiers never move.
    WrongModule {
        /// The identifier.
        id: SceneId,
        /// The module the scene belongs to.
        owner: Module,
        /// The module the input named.
        named: Module,
    },
    /// `[COOP-OWN-UNKNOWN.1]`: no scene has this identifier.
    OwnerUnknown {
        /// The identifier.
        id: SceneId,
    },
    /// `[COOP-OWN-RETIRED.1]`: the scene has retired.
    OwnerRetired {
        /// The identifier.
        id: SceneId,
        /// What it retired as.
        retirement: Retirement,
    },
    /// `[COOP-OWN-KIND.1]`: a scene's kind (velocity or steering) never changes.
    KindMismatch {
        /// The identifier.
        id: SceneId,
        /// The scene's kind.
        registered: FactorKind,
        /// The kind of the geometry given.
        given: FactorKind,
    },
    /// `[COOP-OWN-TRANSITION.1]`: the lifecycle table forbids this phase change.
    PhaseTransition {
        /// The identifier.
        id: SceneId,
        /// The scene's phase.
        from: Phase,
        /// The phase asked for.
        to: Phase,
    },
    /// `[COOP-CMD-UNKNOWN.1]` and its siblings: a command of the batch cannot apply, so none do.
    Commands {
        /// The position of the first failing command in the batch.
        index: usize,
        /// Why it fails; this decides the rule.
        failure: CommandFailure,
        /// Every command's outcome, in batch order.
        outcomes: Vec<CommandOutcome>,
        /// Every failing command's scene, in batch order.
        failed: Vec<SceneId>,
    },
    /// `[COOP-POL-UNKNOWN.1]`: the module has no cooperation policy.
    UnknownPolicyModule {
        /// The position of the setting in the batch.
        index: usize,
        /// The module.
        module: Module,
    },
    /// `[COOP-POL-DUPLICATE.1]`: an earlier setting of the batch names the same module.
    DuplicatePolicyModule {
        /// The position of the second setting in the batch.
        index: usize,
        /// The module.
        module: Module,
    },
    /// `[COOP-BATCH-LIMIT.1]`: the batch is longer than the limit.
    BatchLimit {
        /// The batch's length.
        len: usize,
        /// The limit.
        limit: usize,
    },
}

impl Rejection {
    /// The rule that rejected the input.
    #[must_use]
    pub const fn rule(&self) -> Rule {
        match self {
            Self::AlreadyLive { .. } => Rule::RegisterLive,
            Self::Revival { .. } => Rule::RegisterRetired,
            Self::UnsupportedModule { .. } => Rule::RegisterModule,
            Self::SceneLimit { .. } => Rule::RegisterFull,
            Self::WrongModule { .. } => Rule::OwnerModule,
            Self::OwnerUnknown { .. } => Rule::OwnerUnknown,
            Self::OwnerRetired { .. } => Rule::OwnerRetired,
            Self::KindMismatch { .. } => Rule::OwnerKind,
            Self::PhaseTransition { .. } => Rule::OwnerTransition,
            Self::Commands { failure, .. } => failure.rule(),
            Self::UnknownPolicyModule { .. } => Rule::PolicyUnknown,
            Self::DuplicatePolicyModule { .. } => Rule::PolicyDuplicate,
            Self::BatchLimit { .. } => Rule::BatchLimit,
        }
    }
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::AlreadyLive { id } => write!(f, "scene {id} is already registered"),
            Self::Revival { id, retirement } => write!(
                f,
                "scene {id} of {} retired ({}); its identifier cannot be registered again",
                retirement.module, retirement.reason
            ),
            Self::UnsupportedModule { id, module } => {
                write!(
                    f,
                    "cannot register scene {id}: module {module} has no cooperation policy"
                )
            }
            Self::SceneLimit { limit } => write!(f, "the limit of {limit} live scenes is reached"),
            Self::WrongModule { id, owner, named } => {
                write!(f, "scene {id} belongs to module {owner}, not {named}")
            }
            Self::OwnerUnknown { id } => write!(f, "no scene has identifier {id}"),
            Self::OwnerRetired { id, retirement } => {
                write!(
                    f,
                    "scene {id} of {} has retired ({})",
                    retirement.module, retirement.reason
                )
            }
            Self::KindMismatch {
                id,
                registered,
                given,
            } => write!(
                f,
                "scene {id} is a {registered:?} scene; a {given:?} geometry cannot update it"
            ),
            Self::PhaseTransition { id, from, to } => {
                write!(f, "scene {id} cannot go from {from} to {to}")
            }
            Self::Commands {
                outcomes, failed, ..
            } => {
                f.write_str("no command applied:")?;
                let failures =
                    outcomes
                        .iter()
                        .enumerate()
                        .filter_map(|(index, outcome)| match outcome {
                            CommandOutcome::Failed(failure) => Some((index, failure)),
                            CommandOutcome::Withheld => None,
                        });
                for (n, ((index, failure), id)) in failures.zip(failed).enumerate() {
                    let separator = if n == 0 { " " } else { "; " };
                    write!(f, "{separator}command {index} (scene {id}): {failure}")?;
                }
                Ok(())
            }
            Self::UnknownPolicyModule { index, module } => write!(
                f,
                "no policy applied: setting {index} names module {module}, which has no policy"
            ),
            Self::DuplicatePolicyModule { index, module } => write!(
                f,
                "no policy applied: setting {index} names module {module} a second time"
            ),
            Self::BatchLimit { len, limit } => {
                write!(
                    f,
                    "the batch has {len} entries; at most {limit} are accepted"
                )
            }
        }
    }
}

impl std::error::Error for Rejection {}
