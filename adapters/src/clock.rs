//! The node's clock: the one place it reads time.
//!
//! The core reads no clock; the node tells it how much time passed (`Tick`), measured on the
//! monotonic clock, so a wall-clock jump neither expires scenes early nor keeps them alive.
//! The streams' header stamps are the wall time at start plus monotonic time since, so they
//! never go backwards either.

use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::engine::Now;
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

    /// Now, for the engine: the monotonic time since the start, and the stamp for it.
    #[must_use]
    pub fn now(&self) -> Now {
        let elapsed = self.start.elapsed();
        let wall = self.wall_at_start.saturating_add(elapsed);
        Now::new(
            i64::try_from(elapsed.as_nanos()).unwrap_or(i64::MAX),
            Time {
                sec: i32::try_from(wall.as_secs()).unwrap_or(i32::MAX),
                nanosec: wall.subsec_nanos(),
            },
        )
    }

    /// A header stamp for now: the wall time at start plus the monotonic time since.
    #[must_use]
    pub fn stamp(&self) -> Time {
        self.now().stamp
    }
}
