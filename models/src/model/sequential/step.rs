//! A model state (`Step`): the core's state, the rule last fired and the history, with its
//! fingerprint and its canonical form under renaming of identifiers.

use std::hash::{Hash, Hasher};
use std::sync::atomic::{AtomicU16, Ordering};
use std::sync::{Arc, OnceLock};

use cooperation::{Module, Retirement, Rule, Scene, SceneId, State};
use stateright::Representative;

use super::Ghost;
use crate::model::ids::{index, MAX_SCENES};
use crate::model::spec::rules::Snapshot;

/// Each model state: the core's state plus history variables.
///
/// Fingerprinted by the core's content, the rule, the history and `stalled`, except that when
/// the retired capacity covers every identifier (`order_matters` is false) the order in which
/// identifiers retired is left out: no identifier is ever forgotten then, so the order is
/// unobservable.
///
/// A stalled step (an input that changed neither the core nor the history) is a leaf whose
/// core and history are its predecessor's, so every property but the rule's reachability has
/// the value it has in the predecessor, which the checker evaluated before expanding it. When
/// `merge_stalled` is set (the default), a stalled step is fingerprinted by its rule alone, so
/// all the stalled steps of one rule are one state: the first one found witnesses the rule, and
/// the others, which could only repeat what their predecessors showed, are not kept
/// (`docs/models.md`, *Reductions*).
#[derive(Clone, serde::Serialize)]
pub struct Step {
    /// The library's state.
    pub core: Arc<State>,
    /// The rule the last input fired or was rejected by; `None` initially.
    pub last: Option<Rule>,
    /// History the transition properties need.
    pub ghost: Ghost,
    /// The last input changed nothing (core and history are the predecessor's).
    pub stalled: bool,
    /// Whether the retirement order can matter (the retired set can fill up).
    pub order_matters: bool,
    /// Whether stalled steps are fingerprinted by their rule alone (see [`Step`]).
    pub merge_stalled: bool,
    /// Set on a representative only ([`Representative::representative`]): fingerprinted by
    /// what renaming identifiers keeps, so that every renaming of a step has one fingerprint.
    #[serde(skip)]
    symmetric: bool,
    /// Values derived from `core` and `ghost`, computed once and shared by every step with the
    /// same core and history (a stalled step shares its predecessor's).
    #[serde(skip)]
    derived: Arc<Derived>,
}

/// What is derived from a step's core and history, each computed when first asked for: the
/// core's fingerprint contribution, the fingerprint contribution of the core and history as
/// renaming keeps them, and the canonical renaming.
struct Derived {
    core_hash: OnceLock<u64>,
    /// See [`Step::symmetric_hash`].
    symmetric_hash: OnceLock<u64>,
    /// The canonical form, or `None` when the step is canonical already (a `Some(self)` would
    /// be a reference cycle).
    canonical: OnceLock<Option<Step>>,
    /// The core as the spec's rules read it, built once for all the step's successors.
    snapshot: OnceLock<Snapshot>,
    /// For each rule, the first input (its place in the alphabet) found so far whose stalled
    /// step the rule names; `u16::MAX` while none is (see [`Step::first_stall`]).
    first_stall: [AtomicU16; Rule::ALL.len()],
}

impl Step {
    pub(super) fn new(
        core: Arc<State>,
        last: Option<Rule>,
        ghost: Ghost,
        stalled: bool,
        (order_matters, merge_stalled): (bool, bool),
    ) -> Self {
        let derived = Arc::new(Derived {
            core_hash: OnceLock::new(),
            symmetric_hash: OnceLock::new(),
            canonical: OnceLock::new(),
            snapshot: OnceLock::new(),
            first_stall: core::array::from_fn(|_| AtomicU16::new(u16::MAX)),
        });
        Self {
            core,
            last,
            ghost,
            stalled,
            order_matters,
            merge_stalled,
            symmetric: false,
            derived,
        }
    }

    /// The core's fingerprint contribution (see [`core_hash`]).
    fn core_hash(&self) -> u64 {
        *self
            .derived
            .core_hash
            .get_or_init(|| core_hash(&self.core, self.order_matters))
    }

    /// The core and the history as renaming identifiers keeps them: the limits, the policies,
    /// and the signatures of the identifiers anything is known of ([`Signature`]: everything
    /// the core and the history hold of one identifier), each hashed, the digests summed. Two
    /// steps have the same signatures, in some order, exactly when one is the other renamed;
    /// the sum does not depend on the order, so this is the fingerprint contribution of their
    /// common representative, found without building it.
    fn symmetric_hash(&self) -> u64 {
        *self.derived.symmetric_hash.get_or_init(|| {
            use std::hash::BuildHasher;
            let core = &self.core;
            let mut state = foldhash::quality::FixedState::with_seed(0x7379_6d6d).build_hasher();
            core.limits().hash(&mut state);
            core.policies().for_each(|setting| setting.hash(&mut state));
            // Each signature as a digest, the digests summed with their number (a multiset's
            // hash, whatever order the identifiers come in): the identifiers nothing is known
            // of are left out (any renaming may name them differently).
            let (mut count, mut sum) = (0_u64, 0_u64);
            for ((unknown, signature), _) in self.signatures() {
                if !unknown {
                    let digest =
                        foldhash::quality::FixedState::with_seed(0x7369_676e).hash_one(signature);
                    sum = sum.wrapping_add(digest);
                    count += 1;
                }
            }
            (count, sum).hash(&mut state);
            state.finish()
        })
    }

    /// The core as the spec's rules read it.
    pub(super) fn snapshot(&self) -> &Snapshot {
        self.derived
            .snapshot
            .get_or_init(|| Snapshot::of(&self.core))
    }

    /// The settings a step passes on to its successors: whether the retirement order matters,
    /// and whether stalled steps are merged.
    pub(super) const fn settings(&self) -> (bool, bool) {
        (self.order_matters, self.merge_stalled)
    }

    /// Whether a stalled step of `rule`, given by input `action` (its place in the alphabet),
    /// is the first of its rule among this step's successors, the inputs taken in alphabet
    /// order. When stalled steps are merged, every stalled step of one rule is one state
    /// (fingerprinted by the rule alone), so the later ones are that state again: the model
    /// does not hand them to the checker.
    ///
    /// Kept as the least input found so far for each rule, so `false` always means an earlier
    /// input of this very step gave a stalled step of the same rule; a checker that takes the
    /// inputs in order (both of stateright's searches, each state expanded by one thread) sees
    /// exactly the first one of each rule, and one that does not (a path rebuilt from its
    /// inputs) at worst gets a duplicate more.
    pub(super) fn first_stall(&self, rule: Rule, action: usize) -> bool {
        let (Some(slot), Ok(action)) = (
            self.derived.first_stall.get(rule as usize),
            u16::try_from(action),
        ) else {
            return true;
        };
        slot.fetch_min(action, Ordering::Relaxed) >= action
    }

    /// The step for an input that changed nothing: same core and history, shared derivations.
    pub(super) fn stalled_after(from: &Self, rule: Rule) -> Self {
        Self {
            last: Some(rule),
            stalled: true,
            ..from.clone()
        }
    }
}

/// The core's content as the fingerprint sees it (see [`Step`]). A fixed-seed foldhash: about
/// five times cheaper per byte than the SipHash the checker fingerprints with, and as
/// deterministic, so a run's counts never depend on the process.
fn core_hash(core: &State, order_matters: bool) -> u64 {
    use std::hash::BuildHasher;
    let mut state = foldhash::quality::FixedState::with_seed(0x636f_6f70).build_hasher();
    core.limits().hash(&mut state);
    core.policies().for_each(|setting| setting.hash(&mut state));
    core.scene_count().hash(&mut state);
    core.scenes().for_each(|scene| scene.hash(&mut state));
    if order_matters {
        core.retired_oldest_first()
            .for_each(|retired| retired.hash(&mut state));
    } else {
        core.retired_by_id()
            .for_each(|retired| retired.hash(&mut state));
    }
    state.finish()
}

impl PartialEq for Step {
    fn eq(&self, other: &Self) -> bool {
        self.core == other.core
            && self.last == other.last
            && self.ghost == other.ghost
            && self.stalled == other.stalled
            && self.order_matters == other.order_matters
            && self.merge_stalled == other.merge_stalled
            && self.symmetric == other.symmetric
    }
}

impl Eq for Step {}

impl Hash for Step {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.stalled.hash(state);
        self.last.hash(state);
        if self.stalled && self.merge_stalled {
            return;
        }
        if self.symmetric {
            self.symmetric_hash().hash(state);
            self.ghost.broken.hash(state);
        } else {
            self.core_hash().hash(state);
            self.ghost.hash(state);
        }
    }
}

impl core::fmt::Debug for Step {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Step")
            .field("core", &self.core)
            .field("last", &self.last)
            .field("ghost", &self.ghost)
            .field("stalled", &self.stalled)
            .finish_non_exhaustive()
    }
}

impl Representative for Step {
    /// The same step marked to be fingerprinted as renaming keeps it (the limits, the
    /// policies, and the known identifiers' signatures, in any order): every renaming of it has
    /// the fingerprint of [`Step::canonical_step`], which is not built. The checker only
    /// fingerprints a representative (its depth-first search goes on from the step itself); a
    /// search that goes on from representatives takes [`Step::canonical_step`].
    fn representative(&self) -> Self {
        Self {
            symmetric: true,
            ..self.clone()
        }
    }
}

impl Step {
    /// Identifiers renamed `1, 2, …` in the order of everything known about them, so that all
    /// states equal up to renaming share one representative. The sort key is each identifier's
    /// whole signature, so the representative is canonical.
    #[must_use]
    pub fn canonical_step(&self) -> Self {
        if self.stalled && self.merge_stalled {
            // Fingerprinted by its rule alone: every renaming of it is the same state.
            return self.clone();
        }
        match self.derived.canonical.get_or_init(|| self.canonical()) {
            Some(canonical) => Self {
                last: self.last,
                stalled: self.stalled,
                ..canonical.clone()
            },
            None => self.clone(),
        }
    }
}

/// What is known of one identifier in a step, the key the canonical form sorts identifiers by:
/// its live scene, its retirement, its first module, whether it ever retired, and (when the
/// retirement order matters) its place in that order. Two identifiers with the same signature
/// can be swapped without changing the step.
type Signature<'a> = (
    Option<&'a Scene>,
    Option<Retirement>,
    Option<Module>,
    bool,
    Option<usize>,
);

/// Every identifier's index up to the last one anything is known of, sorted by whether nothing
/// is known of it, then by its signature, then by the index itself: the new name of the
/// identifier at position `p` is `p + 1`. The identifiers after them keep their names. (Only
/// that prefix is built: the whole array of `MAX_SCENES` signatures, built and moved for every
/// renaming, was the largest part of the check's time.)
type Signed<'a> = Vec<((bool, Signature<'a>), usize)>;

/// A renaming of identifiers: identifier `i + 1` becomes identifier `names[i] + 1`.
pub type Names = [usize; MAX_SCENES];

/// The renaming that keeps every name.
#[must_use]
pub fn identity() -> Names {
    core::array::from_fn(|i| i)
}

impl Step {
    /// Every identifier's signature, sorted (see [`Signed`]).
    fn signed(&self) -> Signed<'_> {
        let mut signed: Signed<'_> = self.signatures().collect();
        signed.sort_unstable();
        signed
    }

    /// The signature of every identifier up to the last one anything is known of, unsorted
    /// (see [`Signed`]).
    fn signatures(&self) -> impl Iterator<Item = ((bool, Signature<'_>), usize)> + '_ {
        let core = &self.core;
        let position = |id: SceneId| {
            if self.order_matters {
                core.retired_oldest_first().position(|(o, _)| o == id)
            } else {
                None
            }
        };
        // Every identifier's signature; identifiers nothing is known of sort last. Those past the
        // last one known of are all unknown and already last, in order: they keep their names.
        let known = core
            .scenes()
            .map(|(id, _)| id)
            .chain(core.retired_oldest_first().map(|(id, _)| id))
            .filter_map(index)
            .map(|i| i + 1)
            .fold(self.ghost.known(), usize::max);
        (0..known.min(MAX_SCENES)).map(move |i| {
            let id = SceneId::from_u128(i as u128 + 1);
            let signature = (
                core.scene(id),
                core.retirement(id),
                self.ghost.owner(id),
                self.ghost.was_retired(id),
                position(id),
            );
            let unknown = signature == (None, None, None, false, None);
            ((unknown, signature), i)
        })
    }

    /// The renaming that sorts identifiers by their signatures (see [`Signed`]).
    fn names(&self) -> Names {
        let mut names = identity();
        for (new, (_, old)) in self.signed().iter().enumerate() {
            if let Some(name) = names.get_mut(*old) {
                *name = new;
            }
        }
        names
    }

    /// The renaming by which this step's canonical form ([`Step::canonical_step`]) is this
    /// step: identifier `i + 1` here is identifier `names[i] + 1` there.
    #[must_use]
    pub fn representative_names(&self) -> Names {
        if self.stalled && self.merge_stalled {
            // Its own canonical form (see `canonical_step`).
            return identity();
        }
        let names = self.names();
        if names == identity()
            || self
                .derived
                .canonical
                .get_or_init(|| self.canonical())
                .is_none()
        {
            // Already canonical, or the core refused the renaming: the representative is this
            // step, names unchanged.
            return identity();
        }
        names
    }

    fn canonical(&self) -> Option<Self> {
        let names = self.names();
        if names == identity() {
            return None;
        }
        self.renamed(&names)
    }

    /// This step with identifier `i + 1` renamed `names[i] + 1`, its history with it (`names` a
    /// permutation); `None` if the core refuses the renaming (two identifiers given one name).
    #[must_use]
    pub fn renamed(&self, names: &Names) -> Option<Self> {
        let rename = |id: SceneId| {
            index(id)
                .and_then(|i| names.get(i))
                .map_or(id, |n| SceneId::from_u128(*n as u128 + 1))
        };
        let core = self.core.relabel(rename)?;
        let mut ghost = Ghost {
            broken: self.ghost.broken,
            ..Ghost::default()
        };
        for (old, new) in names.iter().enumerate() {
            if let (Some(slot), Some(owner)) =
                (ghost.owners.get_mut(*new), self.ghost.owners.get(old))
            {
                *slot = *owner;
            }
            if self.ghost.retired_ever & (1_u64 << old) != 0 {
                ghost.retired_ever |= 1_u64 << new;
            }
        }
        Some(Self::new(
            Arc::new(core),
            self.last,
            ghost,
            self.stalled,
            (self.order_matters, self.merge_stalled),
        ))
    }
}
