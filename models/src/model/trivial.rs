//! A model that does nothing but count, for the checker's raw throughput: its state is as many
//! bytes as the sequential model's, its actions are as cheap as an action can be, so the
//! difference in states per second between the two is the cost of the library's transition
//! function and state representation.

use std::time::{Duration, Instant};

use stateright::{Checker, Model, Property};

/// `digits` counters, each `0..base`, padded with zero bytes to `bytes` in all. Every state has
/// two actions per digit (up and down); the space is `base ^ digits` states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrivialModel {
    /// Counters.
    pub digits: usize,
    /// Values per counter.
    pub base: u8,
    /// The state's size in bytes (at least `digits`).
    pub bytes: usize,
}

impl TrivialModel {
    /// The trivial model the reach table measures: 7^8 = 5,764,801 states, about as many as
    /// the CI configuration, each a 2 KiB state, about a core state's heap size with two live
    /// scenes.
    pub const REACH: Self = Self {
        digits: 8,
        base: 7,
        bytes: 2048,
    };

    /// The number of states the model has.
    #[must_use]
    pub fn states(&self) -> u128 {
        u128::from(self.base).saturating_pow(u32::try_from(self.digits).unwrap_or(u32::MAX))
    }
}

impl Model for TrivialModel {
    type State = Vec<u8>;
    type Action = (usize, bool);

    fn init_states(&self) -> Vec<Vec<u8>> {
        vec![vec![0; self.bytes.max(self.digits)]]
    }

    fn actions(&self, _: &Vec<u8>, actions: &mut Vec<(usize, bool)>) {
        for digit in 0..self.digits {
            actions.push((digit, true));
            actions.push((digit, false));
        }
    }

    fn next_state(&self, state: &Vec<u8>, (digit, up): (usize, bool)) -> Option<Vec<u8>> {
        let value = *state.get(digit)?;
        let next = if up {
            value.checked_add(1).filter(|v| *v < self.base)?
        } else {
            value.checked_sub(1)?
        };
        let mut state = state.clone();
        *state.get_mut(digit)? = next;
        Some(state)
    }

    /// One property, evaluated in every state as the sequential model's are, so that the
    /// checker does comparable work per state. It is workload, not a check: `next_state` keeps
    /// every counter in range by construction. What a run checks is that it visits exactly
    /// `base ^ digits` states (see `run_trivial` in the checker command).
    fn properties(&self) -> Vec<Property<Self>> {
        vec![Property::always(
            "in range",
            |model: &Self, state: &Vec<u8>| {
                state.iter().take(model.digits).all(|d| *d < model.base)
            },
        )]
    }
}

/// What a run of the trivial model came to.
#[derive(Clone, Copy, Debug)]
pub struct Throughput {
    /// Distinct states.
    pub unique: usize,
    /// States generated, duplicates included.
    pub generated: usize,
    /// Wall time.
    pub elapsed: Duration,
    /// Whether the search completed.
    pub complete: bool,
}

/// Checks the trivial model breadth first with `threads` threads.
#[must_use]
pub fn run(model: TrivialModel, threads: usize) -> Throughput {
    let start = Instant::now();
    let checker = model.checker().threads(threads.max(1)).spawn_bfs().join();
    Throughput {
        unique: checker.unique_state_count(),
        generated: checker.state_count(),
        elapsed: start.elapsed(),
        complete: checker.is_done(),
    }
}
