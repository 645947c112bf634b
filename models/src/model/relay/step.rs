//! The relay model's state: the relay, the module, what is on its way, and the oracle's
//! records the properties read.

use std::collections::BTreeSet;

use cooperation::{Decision, OperatorDecision, SceneId};
use cooperation_adapters::engine::Now;
use cooperation_adapters::relay::{ModuleAnswer, Relay};
use stateright::Representative;

use super::peer::Upstream;
use super::INTERFACE;
use crate::model::engine::now_at;

/// Sticky flags of broken step properties.
pub mod broken {
    /// A call answered as a success although a command of it was not taken by the module.
    pub const SUCCESS: u8 = 1;
    /// A switch of the relay's own to the auto mode it was last told the module has.
    pub const NEEDLESS: u8 = 2;
}

/// A state of the relay model.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct RelayStep {
    /// The relay.
    pub relay: Relay,
    /// The module.
    pub module: Upstream,
    /// Identifiers the module has used.
    pub used: BTreeSet<SceneId>,
    /// The module changed since it last published.
    pub dirty: bool,
    /// Its newest array has reached the relay ahead of its auto-mode status
    /// ([`RelayAction::PublishArray`](super::RelayAction::PublishArray)).
    pub array_ahead: bool,
    /// The auto mode the module last published.
    pub published_auto: Option<bool>,
    /// The module as it was when it published last (for [`RelayFault::LateArrayRestamped`](super::RelayFault::LateArrayRestamped)).
    pub last_published: Option<Upstream>,
    /// Publications so far: the stamp of the next.
    pub publications: u32,
    /// Answers on their way back.
    pub answers: Vec<(cooperation_adapters::relay::CallId, ModuleAnswer)>,
    /// Each operator call's commands, until it is answered.
    pub asked: Vec<(u64, Vec<(SceneId, OperatorDecision)>)>,
    /// Every command the module took (oracle, from its answers).
    pub taken: BTreeSet<(SceneId, Decision)>,
    /// Calls sent whose call or answer was lost: the relay waits for their deadline.
    pub lost: u8,
    /// The clock, in milliseconds.
    pub clock_ms: u64,
    /// Budgets used: operator calls, module moves, losses.
    pub spent: (u8, u8, u8),
    /// Sticky flags ([`broken`]).
    pub broken: u8,
    /// The auto mode the relay was last told the module has (oracle): the module's at a
    /// publication, or the one a switch's answer says it took; unknown from when the relay
    /// hands out a switch until it is told again.
    pub told: Option<bool>,
    /// The auto mode each switch on its way asked for, until its answer is taken or lost.
    pub switching: Vec<(cooperation_adapters::relay::CallId, bool)>,
}

impl Representative for RelayStep {
    /// No reduction.
    fn representative(&self) -> Self {
        self.clone()
    }
}

impl RelayStep {
    /// Whether the module took the operator's `asked` for scene `id` (oracle): a module takes
    /// only activate or deactivate (upstream's `Command`), so never autonomous or none.
    #[must_use]
    pub fn took(&self, id: SceneId, asked: OperatorDecision) -> bool {
        let decision = match asked {
            OperatorDecision::Activate => Decision::Activate,
            OperatorDecision::Deactivate => Decision::Deactivate,
            OperatorDecision::Autonomous | OperatorDecision::Undecided => return false,
        };
        self.taken.contains(&(id, decision))
    }

    /// The clock's reading.
    #[must_use]
    pub fn now(&self) -> Now {
        now_at(self.clock_ms)
    }

    /// Nothing is on its way and the relay has taken what the module says now: the relay has
    /// done everything it will until something else moves.
    #[must_use]
    pub fn settled(&self) -> bool {
        self.answers.is_empty()
            && self.relay.is_idle()
            && !self.dirty
            && self
                .relay
                .link(INTERFACE)
                .is_some_and(|link| link.fresh && link.auto_mode == Some(self.module.auto_mode))
    }
}
