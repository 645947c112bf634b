//! What a coverage run reports while it runs and when it ends, and why it may not run.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering::Relaxed};
use std::time::Duration;

use super::{Pairs, WORDS};

/// The most scene identifiers [`explore`](super::explore) takes without symmetry (every set of them is a bit of
/// a `u64`) and with it (every renaming's sets too).
pub const MAX_COVERED_SCENES: (usize, usize) = (6, 3);

/// Why [`explore`](super::explore) could not run or finish.
#[derive(Debug)]
pub enum CoverageError {
    /// More identifiers than [`MAX_COVERED_SCENES`] allows.
    Scenes(usize),
    /// The model's initial state could not be built.
    Initial(String),
    /// A worker thread ended abnormally; what was found until then is in the [`Progress`].
    Worker,
    /// More distinct menus than a `u32` numbers.
    Menus,
    /// A table of states or a renaming the search made is missing (never).
    Internal,
}

impl core::fmt::Display for CoverageError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let (plain, symmetric) = MAX_COVERED_SCENES;
        match self {
            Self::Scenes(n) => write!(
                f,
                "coverage takes at most {symmetric} scene identifiers with symmetry and \
                 {plain} without, not {n}"
            ),
            Self::Initial(why) => write!(f, "no initial state: {why}"),
            Self::Worker => f.write_str("a worker thread ended abnormally"),
            Self::Menus => f.write_str("more distinct menus than can be numbered"),
            Self::Internal => f.write_str("a table of states or a renaming is missing"),
        }
    }
}

impl std::error::Error for CoverageError {}

/// What a run has found so far, shared with whoever watches it: counts, and every pair found
/// (each worker adds its pairs after every few hundred states).
#[derive(Debug, Default)]
pub struct Progress {
    /// Distinct states reached (classes of states equal up to renaming, with symmetry).
    pub states: AtomicUsize,
    /// The states those classes hold, once expanded: each class's distinct renamings.
    pub concrete: AtomicUsize,
    /// Distinct arrivals: a state with the identifiers of an input reaching it.
    pub arrivals: AtomicUsize,
    /// Transitions computed from the states kept.
    pub transitions: AtomicU64,
    /// Transitions computed from their other renamings (inputs that are not symmetric only).
    pub renamed: AtomicU64,
    /// Levels completed.
    pub levels: AtomicUsize,
    /// States in the level being expanded.
    pub frontier: AtomicUsize,
    pairs: [AtomicU64; WORDS],
}

impl Progress {
    /// Every pair found so far.
    #[must_use]
    pub fn pairs(&self) -> Pairs {
        let mut words = [0; WORDS];
        for (word, shared) in words.iter_mut().zip(&self.pairs) {
            *word = shared.load(Relaxed);
        }
        Pairs::from_words(words)
    }

    pub(super) fn record(&self, pairs: &Pairs) {
        for (shared, word) in self.pairs.iter().zip(pairs.words()) {
            if shared.load(Relaxed) & word != *word {
                shared.fetch_or(*word, Relaxed);
            }
        }
    }

    /// What it holds, as a result: complete if `complete`.
    #[must_use]
    pub fn found(&self, complete: bool, elapsed: Duration) -> Found {
        Found {
            pairs: self.pairs(),
            states: self.states.load(Relaxed),
            concrete: self.concrete.load(Relaxed),
            arrivals: self.arrivals.load(Relaxed),
            transitions: self.transitions.load(Relaxed),
            renamed: self.renamed.load(Relaxed),
            levels: self.levels.load(Relaxed),
            complete,
            elapsed,
        }
    }
}

/// A finished or stopped run.
#[derive(Clone, Debug)]
pub struct Found {
    /// Every pair found.
    pub pairs: Pairs,
    /// Distinct states reached, stalled steps not counted (classes, with symmetry).
    pub states: usize,
    /// The states those classes hold (equal to `states` without symmetry).
    pub concrete: usize,
    /// Distinct arrivals: a state with the identifiers of an input reaching it.
    pub arrivals: usize,
    /// Transitions computed from the states kept: the alphabet's size times `states`.
    pub transitions: u64,
    /// Transitions computed from other renamings of the states kept.
    pub renamed: u64,
    /// Levels completed.
    pub levels: usize,
    /// Whether every reachable state was expanded (false when halted).
    pub complete: bool,
    /// Wall time.
    pub elapsed: Duration,
}
