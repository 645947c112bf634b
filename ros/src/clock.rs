//! The node's clock: the one place it reads time.
//!
//! The core reads no clock; the node tells it how much time passed (`Tick`), measured on the
//! monotonic clock, so a wall-clock jump neither expires scenes early nor keeps them alive.
//! The streams' header stamps are the wall time at start plus monotonic time since, so they
//! never go backwards either.

use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::Time;

/// Monotonic time since the node started, and header stamps derived from it.
#[derive(Clone, Copy, Debug)]
pub struct Clock {
    start: Instant,
    /// The wall time at `start`, since the Unix epoch.
    wall_at_start: Duration,
}

impl Clock {
    /// A clock starting now.
    #[must_use]
    pub fn start() -> Self {
        Self {
            start: Instant::now(),
            wall_at_start: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .unwrap_or_default(),
        }
    }

    /// Monotonic time since the start, in whole milliseconds.
    #[must_use]
    pub fn elapsed_ms(&self) -> u64 {
        u64::try_from(self.start.elapsed().as_millis()).unwrap_or(u64::MAX)
    }

    /// A header stamp for now: the wall time at start plus the monotonic time since.
    #[must_use]
    pub fn stamp(&self) -> Time {
        let now = self.wall_at_start.saturating_add(self.start.elapsed());
        Time {
            sec: i32::try_from(now.as_secs()).unwrap_or(i32::MAX),
            nanosec: now.subsec_nanos(),
        }
    }
}
