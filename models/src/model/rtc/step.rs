//! The RTC model's state: the core's state and the adapter's, what the last call answered, and
//! the history the step properties need.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use cooperation::{Retirement, Rule, Scene, SceneId, State};
use cooperation_adapters::rtc::{Rtc, RtcError};

use crate::model::ids::{index, MAX_SMALL_SCENES};

use super::call::Order;

/// The kind of call.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// `update_cooperate_status`.
    Update,
    /// `remove_cooperate_status`.
    Remove,
    /// `clear_cooperate_status`.
    Clear,
    /// An interface's `cooperate_commands`.
    Commands,
    /// The external API's `cooperate_commands`.
    ExternalCommands,
    /// An interface's `auto_mode`.
    AutoMode,
    /// The external API's `auto_mode_with_module`.
    AutoModeWithModule,
    /// `Rtc::tick`.
    Tick,
    /// The AD API's `set_policies` for one module.
    SetPolicy,
}

/// Why the adapter refused a call, without identifiers (so renaming leaves it alone).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Refusal {
    /// `RtcError::Field`.
    Field,
    /// `RtcError::UnknownInterface` or `RtcError::Unconfigured` (never, with the model's
    /// bindings).
    Interface,
    /// `RtcError::NoInterface`.
    NoInterface,
    /// `RtcError::ForeignScene`.
    ForeignScene,
    /// `RtcError::UnboundSequence`.
    UnboundSequence,
    /// `RtcError::SequenceUnstated`.
    SequenceUnstated,
    /// `RtcError::InitialPhase`, with the core's rule.
    InitialPhase(Rule),
    /// `RtcError::Core`, with the core's rule.
    Core(Rule),
    /// `RtcError::SceneQuota`.
    Quota,
    /// An error this model does not know.
    Other,
}

impl Refusal {
    /// The refusal an error stands for.
    #[must_use]
    pub fn of(error: &RtcError) -> Self {
        match error {
            RtcError::Field(_) => Self::Field,
            RtcError::UnknownInterface { .. } | RtcError::Unconfigured { .. } => Self::Interface,
            RtcError::NoInterface { .. } => Self::NoInterface,
            RtcError::ForeignScene { .. } => Self::ForeignScene,
            RtcError::UnboundSequence { .. } => Self::UnboundSequence,
            RtcError::SequenceUnstated { .. } => Self::SequenceUnstated,
            RtcError::InitialPhase { rejection, .. } => Self::InitialPhase(rejection.rule()),
            RtcError::Core(rejection) => Self::Core(rejection.rule()),
            RtcError::SceneQuota { .. } => Self::Quota,
            _ => Self::Other,
        }
    }
}

/// What a call answered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Answer {
    /// Accepted, with the rules of the first two core transitions it reported (a clear
    /// reports none, an update one or two, the other calls one).
    Accepted(Option<Rule>, Option<Rule>),
    /// A clear, accepted: how many scenes it answered.
    Cleared(u8),
    /// Refused.
    Refused(Refusal),
}

/// The last call's kind and answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Outcome {
    /// The call.
    pub kind: Kind,
    /// Its answer.
    pub answer: Answer,
}

impl Outcome {
    /// Whether the call registered or retired an identifier: an answer that only a step that
    /// changes the state can give. Every other answer is also given by some call that changes
    /// nothing (the same report again, the same command again, a switch to the policy in force,
    /// a tick with no live scene).
    #[must_use]
    pub const fn registers_or_retires(&self) -> bool {
        match self.answer {
            Answer::Accepted(Some(rule), _) => matches!(
                rule,
                Rule::RegisterNew | Rule::OwnerFinish | Rule::OwnerRemove | Rule::TimeExpire
            ),
            Answer::Cleared(n) => n > 0,
            Answer::Accepted(None, _) | Answer::Refused(_) => false,
        }
    }
}

/// A set of broken step properties: sticky flags, set only when a step breaks one, so in a
/// correct run they add no state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Broken(pub u16);

impl Broken {
    /// A refused call changed the core's state or the adapter's.
    pub const REFUSAL_CHANGED: Self = Self(1);
    /// A command or auto-mode response does not answer its request as the call's result says.
    pub const UNANSWERED: Self = Self(1 << 1);
    /// An accepted status update or removal did not leave the scene as reported.
    pub const NOT_AS_REPORTED: Self = Self(1 << 2);
    /// An interface's call changed a scene registered through another interface.
    pub const FOREIGN_TOUCHED: Self = Self(1 << 3);
    /// An operator decision changed other than by an applied command naming its scene.
    pub const OPERATOR_BY_OTHER: Self = Self(1 << 4);
    /// A scene became live with an operator decision.
    pub const NEW_SCENE_DECIDED: Self = Self(1 << 5);
    /// An applied command batch left a named scene without the command's decision.
    pub const COMMAND_MISSED: Self = Self(1 << 6);
    /// An auto-mode switch changed a scene, a retirement or a route.
    pub const AUTO_MODE_CLOBBERED: Self = Self(1 << 7);
    /// An accepted auto-mode switch did not switch exactly the interfaces of its modules.
    pub const AUTO_MODE_MISSED: Self = Self(1 << 8);
    /// A retired identifier became live again.
    pub const REVIVED: Self = Self(1 << 9);
    /// A tick's answer does not list exactly the scenes that expired.
    pub const EXPIRY_UNREPORTED: Self = Self(1 << 10);
    /// A clear did not retire exactly the interface's live scenes, or answered others.
    pub const CLEAR_WRONG: Self = Self(1 << 11);
    /// A refusal for an undefined constant named another field or value than the call's first
    /// undefined one, or a call carrying one was not refused for it, or one without was.
    pub const FIELD_MISNAMED: Self = Self(1 << 12);
    /// A status update was refused for its sequence other than exactly when it stated one its
    /// interface is not bound to, stated none for a new scene of an interface bound to several,
    /// or stated another than its live scene's; or another call was refused by the module rule.
    pub const SEQUENCE_WRONG: Self = Self(1 << 13);
    /// A new scene registered through an interface already holding its quota of live scenes, or
    /// a report was refused for the quota other than a new scene's through an interface holding
    /// its quota.
    pub const QUOTA_WRONG: Self = Self(1 << 14);

    /// Every flag with a short name, for traces.
    pub const NAMED: [(Self, &'static str); 15] = [
        (Self::REFUSAL_CHANGED, "refusal changed the state"),
        (Self::UNANSWERED, "request not answered as it went"),
        (
            Self::NOT_AS_REPORTED,
            "accepted report not applied as reported",
        ),
        (Self::FOREIGN_TOUCHED, "another interface's scene changed"),
        (
            Self::OPERATOR_BY_OTHER,
            "operator decision changed without its command",
        ),
        (Self::NEW_SCENE_DECIDED, "new scene already decided"),
        (Self::COMMAND_MISSED, "applied command not in effect"),
        (
            Self::AUTO_MODE_CLOBBERED,
            "auto-mode switch changed a scene",
        ),
        (
            Self::AUTO_MODE_MISSED,
            "auto-mode switch reached the wrong interfaces",
        ),
        (Self::REVIVED, "retired identifier live again"),
        (Self::EXPIRY_UNREPORTED, "expiry not reported"),
        (Self::CLEAR_WRONG, "clear did not retire exactly its scenes"),
        (
            Self::FIELD_MISNAMED,
            "refusal did not name the undefined field",
        ),
        (
            Self::SEQUENCE_WRONG,
            "sequence refused other than as documented",
        ),
        (Self::QUOTA_WRONG, "quota applied other than as documented"),
    ];

    /// The names of the flags among these.
    #[must_use]
    pub fn names(self) -> Vec<&'static str> {
        Self::NAMED
            .iter()
            .filter(|(flag, _)| self.contains(*flag))
            .map(|(_, name)| *name)
            .collect()
    }

    /// Whether `flag` is among these.
    #[must_use]
    pub const fn contains(self, flag: Self) -> bool {
        self.0 & flag.0 != 0
    }

    /// Adds `flag` when `broken`.
    pub fn set(&mut self, flag: Self, broken: bool) {
        if broken {
            self.0 |= flag.0;
        }
    }
}

/// An interface, by its position in the model's bindings (at most a few).
pub type Interface = u8;

/// One state of the RTC model.
///
/// Equality is exact. The hash (and so the checker's fingerprint) reads the core's policies,
/// live scenes and retirements, each identifier's route as [`Rtc::owner`] answers it, the last
/// outcome (where [`shows_last`](Self::shows_last)), the history and the fault's memory; a
/// digest of the core's and the adapter's parts is computed once per step, with a fixed-seed
/// foldhash (several times cheaper than the checker's own hasher, and as deterministic). The
/// order in which identifiers retired is left out while the retired set remembers every
/// identifier (nothing is ever forgotten, so the order never matters). Routes the adapter keeps
/// for identifiers the core has forgotten are invisible to every query and call (each looks a
/// route up only for an identifier the core remembers), but they are memory the adapter must
/// bound: where the core forgets, the hash reads how many routes the adapter keeps, so that a
/// state reached with more of them is checked too.
#[derive(Clone, Debug)]
pub struct RtcStep {
    /// The core's state.
    pub core: Arc<State>,
    /// The adapter's state (bindings and routes).
    pub rtc: Arc<Rtc>,
    /// The last call and its answer; `None` initially.
    pub last: Option<Outcome>,
    /// The last call changed nothing: the step is its predecessor's state with `last`, and is
    /// not expanded again.
    pub stalled: bool,
    /// The interface whose status update registered each remembered identifier, as the model
    /// saw it (by identifier number minus one).
    pub registrar: [Option<Interface>; MAX_SMALL_SCENES],
    /// Sticky flags of broken step properties.
    pub broken: Broken,
    /// An injected fault's memory (upstream's stored commands); `None` without that fault.
    pub stash: Option<Arc<Vec<Order>>>,
    /// Each identifier's route, from [`Rtc::owner`]: derived from `core` and `rtc`.
    owners: [Option<Interface>; MAX_SMALL_SCENES],
    /// Whether the retirement order is part of the state (the retired set can forget).
    order_matters: bool,
    /// Set on a representative only: hash the identifiers' signatures sorted, so every
    /// renaming of a state hashes alike.
    sorted: bool,
    /// The digest of the core's and the adapter's parts, once the step is settled.
    digest: Digest,
}

/// A step's core and adapter parts, hashed: the part no identifier names, and each identifier's
/// signature (by identifier number minus one).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Digest {
    rest: u64,
    ids: [u64; MAX_SMALL_SCENES],
}

fn digest_of(value: &impl Hash) -> u64 {
    use std::hash::BuildHasher;
    foldhash::quality::FixedState::with_seed(0x0072_7463).hash_one(value)
}

/// Everything known of one identifier.
type Signature<'a> = (
    Option<&'a Scene>,
    Option<Retirement>,
    Option<Interface>,
    Option<Interface>,
);

impl RtcStep {
    /// A first step: no call made yet, no history.
    #[must_use]
    pub fn new(core: Arc<State>, rtc: Arc<Rtc>, order_matters: bool) -> Self {
        let owners = owners(&core, &rtc);
        let mut step = Self {
            core,
            rtc,
            last: None,
            stalled: false,
            registrar: [None; MAX_SMALL_SCENES],
            broken: Broken::default(),
            stash: None,
            owners,
            order_matters,
            sorted: false,
            digest: Digest::default(),
        };
        step.digest = step.digest();
        step
    }

    /// The step after a call that left these states and answered `outcome`, with this step's
    /// history (to be brought up to date by the caller). A state the call did not change is
    /// shared with this step.
    #[must_use]
    pub fn successor(
        &self,
        core: State,
        rtc: Rtc,
        stash: Option<Arc<Vec<Order>>>,
        outcome: Outcome,
    ) -> Self {
        let core = if core == *self.core {
            Arc::clone(&self.core)
        } else {
            Arc::new(core)
        };
        let rtc = if rtc == *self.rtc {
            Arc::clone(&self.rtc)
        } else {
            Arc::new(rtc)
        };
        let same = Arc::ptr_eq(&core, &self.core) && Arc::ptr_eq(&rtc, &self.rtc);
        let owners = if same {
            self.owners
        } else {
            owners(&core, &rtc)
        };
        Self {
            core,
            rtc,
            last: Some(outcome),
            stalled: false,
            registrar: self.registrar,
            broken: self.broken,
            stash,
            owners,
            order_matters: self.order_matters,
            sorted: false,
            digest: self.digest,
        }
    }

    /// Completes a successor of `from` once its history is up to date: whether it is stalled,
    /// and its digest.
    pub fn settle(&mut self, from: &Self) {
        self.stalled = self.same_as(from);
        let shared = Arc::ptr_eq(&self.core, &from.core)
            && Arc::ptr_eq(&self.rtc, &from.rtc)
            && self.registrar == from.registrar;
        if !shared {
            self.digest = self.digest();
        }
    }

    fn digest(&self) -> Digest {
        let policies: Vec<_> = self.core.policies().collect();
        // Where the core forgets, how many routes the adapter keeps (stale ones included) is
        // part of the state, so that its bound is checked on every way of reaching a state.
        let (order, routes): (Vec<SceneId>, usize) = if self.order_matters {
            let order = self.core.retired_oldest_first().map(|(id, _)| id).collect();
            (order, self.rtc.route_count())
        } else {
            (Vec::new(), 0)
        };
        Digest {
            rest: digest_of(&(policies, order, routes)),
            ids: self.signatures().map(|signature| digest_of(&signature)),
        }
    }

    /// Whether this step's states and history are `other`'s (only the last outcome may differ).
    #[must_use]
    pub fn same_as(&self, other: &Self) -> bool {
        self.core == other.core
            && self.rtc == other.rtc
            && self.registrar == other.registrar
            && self.broken == other.broken
            && self.stash == other.stash
    }

    /// Whether the last outcome is part of the state (hashed, and so safe for properties to
    /// read): on a stalled step, and on a step that registered or retired an identifier. Any
    /// other step's outcome is kept for traces only: the same state reached by another call is
    /// the same state, which keeps the model from expanding each state once per way into it.
    #[must_use]
    pub fn shows_last(&self) -> bool {
        self.stalled || self.last.is_some_and(|o| o.registers_or_retires())
    }

    /// The interface `id` registered through, as the adapter's routes say, while the core
    /// remembers it.
    #[must_use]
    pub fn owner(&self, id: SceneId) -> Option<Interface> {
        index(id).and_then(|i| self.owners.get(i).copied().flatten())
    }

    /// The interface whose update registered `id`, as the model saw it.
    #[must_use]
    pub fn registrar(&self, id: SceneId) -> Option<Interface> {
        index(id).and_then(|i| self.registrar.get(i).copied().flatten())
    }

    fn signatures(&self) -> [Signature<'_>; MAX_SMALL_SCENES] {
        core::array::from_fn(|i| {
            let id = SceneId::from_u128(i as u128 + 1);
            (
                self.core.scene(id),
                self.core.retirement(id),
                self.owners.get(i).copied().flatten(),
                self.registrar.get(i).copied().flatten(),
            )
        })
    }
}

/// Each model identifier's route.
fn owners(core: &State, rtc: &Rtc) -> [Option<Interface>; MAX_SMALL_SCENES] {
    core::array::from_fn(|i| {
        let binding = rtc.owner(core, SceneId::from_u128(i as u128 + 1))?;
        let at = rtc
            .bindings()
            .iter()
            .position(|b| core::ptr::eq(b, binding))?;
        Interface::try_from(at).ok()
    })
}

impl PartialEq for RtcStep {
    fn eq(&self, other: &Self) -> bool {
        self.core == other.core
            && self.rtc == other.rtc
            && self.last == other.last
            && self.stalled == other.stalled
            && self.registrar == other.registrar
            && self.broken == other.broken
            && self.stash == other.stash
            && self.sorted == other.sorted
    }
}

impl Eq for RtcStep {}

impl Hash for RtcStep {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.digest.rest.hash(state);
        let mut ids = self.digest.ids;
        if self.sorted {
            ids.sort_unstable();
        }
        ids.hash(state);
        if self.shows_last() {
            self.last.hash(state);
        }
        self.stalled.hash(state);
        self.broken.hash(state);
        self.stash.hash(state);
    }
}

impl stateright::Representative for RtcStep {
    /// The same state marked to hash its identifiers' signatures (their digests) sorted: every
    /// renaming of the identifiers then has one fingerprint, and the reduction is canonical (the
    /// same with any number of threads). Only the fingerprint of a representative is used (stateright's
    /// depth-first search goes on from the original state). No reduction while the retirement
    /// order matters or an injected fault remembers identifiers.
    fn representative(&self) -> Self {
        let mut canonical = self.clone();
        canonical.sorted = !self.order_matters && self.stash.is_none();
        canonical
    }
}
