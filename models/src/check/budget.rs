//! What a check may spend: a memory and a state budget, watched while the search runs, and the
//! switch that stops a search that would outgrow them.
//!
//! stateright has no way to cancel a running search. A model therefore carries a [`Halt`]:
//! once it is set, the model offers no action in any state and counts every state outside its
//! boundary, so the search drains at once and ends, and the run reports what it found. Once the
//! search has ended, the switch is released, so that the checker can replay the paths of what
//! it found.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The switch a model reads to stop offering actions. Every clone of a model shares it; a run
/// gives the model a fresh one (so a search after a halted one is not halted too).
#[derive(Clone, Debug, Default)]
pub struct Halt(Arc<AtomicBool>);

impl Halt {
    /// A switch not yet set.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Stops every search of the models that share this switch.
    pub fn set(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Releases the switch: for after the search has ended, to replay its paths.
    pub fn release(&self) {
        self.0.store(false, Ordering::Relaxed);
    }

    /// Whether the switch is set.
    #[must_use]
    pub fn is_set(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// How much a check may use before it stops and reports itself incomplete.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// The most resident memory of the process, in bytes.
    pub memory_bytes: u64,
    /// The most distinct states.
    pub states: usize,
}

/// One GiB.
pub const GIB: u64 = 1 << 30;

impl Default for Budget {
    /// 16 GiB and 400 million distinct states: room on a 24 GiB machine for the
    /// counterexample searches that follow a violation, and for the operating system.
    fn default() -> Self {
        Self {
            memory_bytes: 16 * GIB,
            states: 400_000_000,
        }
    }
}

/// Which part of a budget a run used up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exceeded {
    /// Resident memory reached the budget (the bytes measured).
    Memory(u64),
    /// The distinct states reached the budget (the count).
    States(usize),
    /// The time limit passed.
    Time,
}

impl core::fmt::Display for Exceeded {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Memory(bytes) => write!(
                f,
                "the memory budget: {:.1} GiB resident",
                *bytes as f64 / GIB as f64
            ),
            Self::States(count) => write!(f, "the state budget: {count} distinct states"),
            Self::Time => f.write_str("the time limit"),
        }
    }
}

impl Budget {
    /// The first limit these figures reach, if any.
    #[must_use]
    pub fn exceeded(&self, resident_bytes: Option<u64>, states: usize) -> Option<Exceeded> {
        match resident_bytes {
            Some(bytes) if bytes >= self.memory_bytes => Some(Exceeded::Memory(bytes)),
            _ if states >= self.states => Some(Exceeded::States(states)),
            _ => None,
        }
    }
}

/// A line of `/proc/self/status` in bytes (`VmRSS` for the resident memory now, `VmHWM` for
/// its peak); `None` where the system has no such file.
#[must_use]
pub fn status_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
