//! Which rules follow which: the ordered pairs of consecutive rules (`r1` fired by one input,
//! `r2` by the next) over every reachable state of the sequential model, classed by the scene
//! identifiers the two inputs name: a common one ([`Scope::Same`]), only different ones
//! ([`Scope::Different`]), or none on one side ([`Scope::Unscoped`]: time, policies, an empty
//! batch).
//!
//! The pairs are measured, not stated: [`explore`] moves the model only with its own
//! `actions` and `next_step` (every successor, stalled or not), and reads the rule each step
//! fired from [`Step::last`]. How it covers every pair while keeping one state per class of
//! states equal up to renaming, and what the numbers show, is in `docs/verification.md`
//! (*Small scopes*).
//!
//! [`Step::last`]: crate::Step::last

use cooperation::{Input, Rule};

use crate::model::fault::Fault;
use crate::model::ids::index;
pub use crate::model::sequential::renamed_input;
use crate::model::sequential::Bounds;

mod explore;
mod progress;

pub use explore::explore;
pub use progress::{CoverageError, Found, Progress, MAX_COVERED_SCENES};

/// How two consecutive inputs relate through the scene identifiers they name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Scope {
    /// Both name scene identifiers, at least one of them in common.
    Same,
    /// Both name scene identifiers, none in common.
    Different,
    /// One of them names no scene identifier: time, a policy batch, an empty command batch.
    Unscoped,
}

impl Scope {
    /// Every scope, in this order.
    pub const ALL: [Self; 3] = [Self::Same, Self::Different, Self::Unscoped];

    /// The scope of two inputs naming the identifier sets `first` and `then` (bit `i` for
    /// identifier `i + 1`, as [`named`] gives them).
    #[must_use]
    pub const fn of(first: u64, then: u64) -> Self {
        if first == 0 || then == 0 {
            Self::Unscoped
        } else if first & then != 0 {
            Self::Same
        } else {
            Self::Different
        }
    }

    /// The scope in words.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Same => "same scene",
            Self::Different => "different scenes",
            Self::Unscoped => "not scene-specific",
        }
    }
}

/// The scene identifiers an input names, as a bit set (bit `i` for identifier `i + 1`):
/// an owner input's identifier, a command batch's identifiers, none for policies and time.
#[must_use]
pub fn named(input: &Input) -> u64 {
    let bit = |id| index(id).map_or(0, |i| 1_u64 << i);
    match input {
        Input::Register { id, .. } | Input::Update { id, .. } | Input::Remove { id, .. } => {
            bit(*id)
        }
        Input::SetCommands { commands } => commands.iter().fold(0, |set, c| set | bit(c.id)),
        Input::SetPolicies { .. } | Input::Tick { .. } => 0,
    }
}

const RULES: usize = Rule::ALL.len();
const SCOPES: usize = Scope::ALL.len();
const WORDS: usize = (RULES * RULES * SCOPES).div_ceil(64);

/// The position of a rule in [`Rule::ALL`] (its declaration order).
const fn rank(rule: Rule) -> usize {
    rule as usize
}

/// A set of rule pairs with their scopes.
#[derive(Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(into = "Listed", try_from = "Listed")]
pub struct Pairs([u64; WORDS]);

impl core::fmt::Debug for Pairs {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl Pairs {
    const fn bit(first: Rule, then: Rule, scope: Scope) -> usize {
        (rank(first) * RULES + rank(then)) * SCOPES + scope as usize
    }

    /// Adds `first` followed by `then` in `scope`.
    pub fn insert(&mut self, first: Rule, then: Rule, scope: Scope) {
        let bit = Self::bit(first, then, scope);
        if let Some(word) = self.0.get_mut(bit / 64) {
            *word |= 1 << (bit % 64);
        }
    }

    /// Whether `first` followed by `then` in `scope` is in the set.
    #[must_use]
    pub fn contains(&self, first: Rule, then: Rule, scope: Scope) -> bool {
        let bit = Self::bit(first, then, scope);
        self.0
            .get(bit / 64)
            .is_some_and(|word| word & (1 << (bit % 64)) != 0)
    }

    /// Every pair in the set: rules in spec order, then scope.
    pub fn iter(&self) -> impl Iterator<Item = (Rule, Rule, Scope)> + '_ {
        Rule::ALL.into_iter().flat_map(move |first| {
            Rule::ALL.into_iter().flat_map(move |then| {
                Scope::ALL
                    .into_iter()
                    .filter(move |scope| self.contains(first, then, *scope))
                    .map(move |scope| (first, then, scope))
            })
        })
    }

    /// How many pairs the set holds in `scope`.
    #[must_use]
    pub fn count(&self, scope: Scope) -> usize {
        self.iter().filter(|(_, _, s)| *s == scope).count()
    }

    /// How many pairs the set holds.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.iter().all(|w| *w == 0)
    }

    /// The pairs of this set that `other` lacks.
    #[must_use]
    pub fn without(&self, other: &Self) -> Self {
        let mut rest = *self;
        for (word, taken) in rest.0.iter_mut().zip(other.0) {
            *word &= !taken;
        }
        rest
    }

    /// Adds every pair of `other`; whether that added any.
    pub fn add(&mut self, other: &Self) -> bool {
        let mut grew = false;
        for (word, more) in self.0.iter_mut().zip(other.0) {
            grew |= more & !*word != 0;
            *word |= more;
        }
        grew
    }

    pub(crate) const fn words(&self) -> &[u64; WORDS] {
        &self.0
    }

    pub(crate) const fn from_words(words: [u64; WORDS]) -> Self {
        Self(words)
    }
}

/// [`Pairs`] as a file holds them: per scope, each pair as two rule tags.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Listed {
    same: Vec<[String; 2]>,
    different: Vec<[String; 2]>,
    unscoped: Vec<[String; 2]>,
}

impl From<Pairs> for Listed {
    fn from(pairs: Pairs) -> Self {
        let list = |scope| {
            pairs
                .iter()
                .filter(|(_, _, s)| *s == scope)
                .map(|(first, then, _)| [first.tag().to_owned(), then.tag().to_owned()])
                .collect()
        };
        Self {
            same: list(Scope::Same),
            different: list(Scope::Different),
            unscoped: list(Scope::Unscoped),
        }
    }
}

impl TryFrom<Listed> for Pairs {
    type Error = String;

    fn try_from(listed: Listed) -> Result<Self, String> {
        let rule = |tag: &str| {
            Rule::ALL
                .into_iter()
                .find(|r| r.tag() == tag)
                .ok_or_else(|| format!("no rule is tagged {tag:?}"))
        };
        let mut pairs = Self::default();
        for (scope, list) in [
            (Scope::Same, &listed.same),
            (Scope::Different, &listed.different),
            (Scope::Unscoped, &listed.unscoped),
        ] {
            for [first, then] in list {
                pairs.insert(rule(first)?, rule(then)?, scope);
            }
        }
        Ok(pairs)
    }
}

/// A measurement as `coverage --write` saves it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Record {
    /// The model's bounds.
    pub bounds: Bounds,
    /// Whether states equal up to renaming were explored once.
    pub symmetry: bool,
    /// The injected fault, if any.
    pub fault: Option<Fault>,
    /// Whether every reachable state was explored.
    pub complete: bool,
    /// What stopped an incomplete run.
    pub stopped: Option<String>,
    /// Distinct states expanded (stalled steps are never expanded: see [`explore`]); with
    /// symmetry, classes of states equal up to renaming.
    pub states: usize,
    /// The states those classes hold.
    pub concrete: usize,
    /// Distinct pairs of a state and the identifiers named by an input leading to it.
    pub arrivals: usize,
    /// Transitions computed from the states kept.
    pub transitions: u64,
    /// Transitions computed from their other renamings (inputs that are not symmetric only).
    pub renamed: u64,
    /// Breadth-first levels completed.
    pub levels: usize,
    /// Wall time, in seconds.
    pub seconds: f64,
    /// The process's peak resident memory, where the system tells it.
    pub peak_rss_bytes: Option<u64>,
    /// How many pairs in each scope: same, different, not scene-specific.
    pub counts: [usize; 3],
    /// The pairs.
    pub pairs: Pairs,
}
