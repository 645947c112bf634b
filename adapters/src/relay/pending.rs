//! An operator's call while the modules it was forwarded to have not all answered, and the
//! answer it gets when they have (`[COOP-RELAY-SUCCESS.1]`).

use std::collections::BTreeSet;
use std::fmt::Write as _;

use cooperation::{Command, PolicySetting, SceneId};

use super::CallId;
use crate::wire::ResponseStatus;

/// What became of one forwarded part of an operator's call.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub(super) enum Outcome {
    /// Not answered yet.
    Awaited,
    /// The module took it.
    Accepted,
    /// The module answered that it did not take it.
    Refused,
    /// The module did not answer within the deadline.
    Unanswered,
}

/// One command of an operator's `set_commands`, and the interface it went to.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub(super) struct Part<T> {
    /// What was asked.
    pub(super) item: T,
    /// The interface it was forwarded to.
    pub(super) interface: String,
    /// The call that carried it.
    pub(super) call: CallId,
    /// Its outcome so far.
    pub(super) outcome: Outcome,
}

/// An operator's call awaiting the modules.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub(super) enum Pending {
    /// A `set_commands`: one part per command.
    Commands(Vec<Part<Command>>),
    /// A `set_policies`: the settings, and one part per interface switched.
    Policies(Vec<PolicySetting>, Vec<Part<bool>>),
}

impl Pending {
    /// Whether any part went to `interface` and is not answered.
    pub(super) fn awaits(&self, interface: &str) -> bool {
        match self {
            Self::Commands(parts) => awaits(parts, interface),
            Self::Policies(_, parts) => awaits(parts, interface),
        }
    }

    /// Whether every part is answered or ran out of time.
    pub(super) fn is_done(&self) -> bool {
        match self {
            Self::Commands(parts) => parts.iter().all(|p| p.outcome != Outcome::Awaited),
            Self::Policies(_, parts) => parts.iter().all(|p| p.outcome != Outcome::Awaited),
        }
    }

    /// `call` ran out of time: its parts are unanswered.
    pub(super) fn expire(&mut self, call: CallId) {
        let unanswered = |_: usize| Outcome::Unanswered;
        match self {
            Self::Commands(parts) => settle(parts, call, unanswered),
            Self::Policies(_, parts) => settle(parts, call, unanswered),
        }
    }

    /// The module's answer to a commands call: each part's success, by its place in the call.
    pub(super) fn commands_answered(&mut self, call: CallId, successes: &[(SceneId, bool)]) {
        if let Self::Commands(parts) = self {
            for part in parts.iter_mut().filter(|p| p.call == call) {
                let accepted = successes
                    .iter()
                    .any(|&(id, success)| id == part.item.id && success);
                part.outcome = if accepted {
                    Outcome::Accepted
                } else {
                    Outcome::Refused
                };
            }
        }
    }

    /// The module's answer to an auto-mode call.
    pub(super) fn auto_mode_answered(&mut self, call: CallId, success: bool) {
        let outcome = |_: usize| {
            if success {
                Outcome::Accepted
            } else {
                Outcome::Refused
            }
        };
        match self {
            Self::Commands(parts) => settle(parts, call, outcome),
            Self::Policies(_, parts) => settle(parts, call, outcome),
        }
    }
}

fn awaits<T>(parts: &[Part<T>], interface: &str) -> bool {
    parts
        .iter()
        .any(|p| p.interface == interface && p.outcome == Outcome::Awaited)
}

fn settle<T>(parts: &mut [Part<T>], call: CallId, outcome: impl Fn(usize) -> Outcome) {
    for (at, part) in parts.iter_mut().enumerate() {
        if part.call == call && part.outcome == Outcome::Awaited {
            part.outcome = outcome(at);
        }
    }
}

/// The status of an operator's call whose parts are settled: success only if every part was
/// accepted and applied; otherwise what happened to each part that was not, a timeout's code if
/// a module did not answer, else a refusal's. `failures` are the core's refusals of parts the
/// modules accepted.
pub(super) fn status<T>(
    parts: &[Part<T>],
    failures: &[String],
    deadline_ms: u64,
    name: impl Fn(&T) -> String,
) -> ResponseStatus {
    let taken = parts
        .iter()
        .filter(|p| p.outcome == Outcome::Accepted)
        .count()
        .saturating_sub(failures.len());
    if taken == parts.len() {
        return ResponseStatus::success();
    }
    let mut message = format!("{taken} of {} applied", parts.len());
    let mut unanswered = BTreeSet::new();
    for part in parts {
        match part.outcome {
            Outcome::Refused => {
                let _ = write!(message, "; {} refused {}", part.interface, name(&part.item));
            }
            Outcome::Unanswered => {
                unanswered.insert(part.interface.as_str());
                let _ = write!(
                    message,
                    "; {} did not answer within {deadline_ms} ms ({})",
                    part.interface,
                    name(&part.item)
                );
            }
            Outcome::Accepted | Outcome::Awaited => {}
        }
    }
    for failure in failures {
        let _ = write!(message, "; {failure}");
    }
    ResponseStatus {
        success: false,
        code: if unanswered.is_empty() {
            ResponseStatus::PARAMETER_ERROR
        } else {
            ResponseStatus::SERVICE_TIMEOUT
        },
        message,
    }
}
