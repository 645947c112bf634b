//! `builtin_interfaces/Time`, the stamp the RTC and AD API messages share.

/// A point in time (`builtin_interfaces/Time`): seconds, and nanoseconds within the second.
///
/// It is read as rosbridge reads a message: a field left out is 0,
/// a field it does not have is refused, and so is a `nanosec` of 1 000 000 000 or more, since
/// that time has another form.
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Debug,
    Default,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(try_from = "TimeFields")]
pub struct Time {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds within the second, below 1 000 000 000.
    pub nanosec: u32,
}

/// A [`Time`] as written, before its `nanosec` is checked.
#[derive(serde::Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
struct TimeFields {
    sec: i32,
    nanosec: u32,
}
impl TryFrom<TimeFields> for Time {
    type Error = String;

    /// Refuses a `nanosec` of a whole second or more: such a time has a second form.
    fn try_from(TimeFields { sec, nanosec }: TimeFields) -> Result<Self, String> {
        if nanosec >= 1_000_000_000 {
            return Err(format!(
                "field `nanosec`: {nanosec} is not below 1000000000 (a second)"
            ));
        }
        Ok(Self { sec, nanosec })
    }
}

impl Time {
    /// A time from seconds and nanoseconds.
    #[must_use]
    pub const fn new(sec: i32, nanosec: u32) -> Self {
        Self { sec, nanosec }
    }

    /// This time moved back by `ms` milliseconds, saturating at the earliest representable
    /// time. A `nanosec` of a second or more (which no decoded message holds) counts as the
    /// seconds it makes, and a result past the latest representable time saturates there.
    #[must_use]
    pub fn before_ms(self, ms: u64) -> Self {
        const NANOS: i64 = 1_000_000_000;
        // Neither product nor sum can overflow: |sec| < 2^31 and nanosec < 2^32.
        let now = i64::from(self.sec) * NANOS + i64::from(self.nanosec);
        let back = i64::try_from(ms)
            .unwrap_or(i64::MAX)
            .saturating_mul(1_000_000);
        let earliest = i64::from(i32::MIN) * NANOS;
        let latest = i64::from(i32::MAX) * NANOS + (NANOS - 1);
        let then = now.saturating_sub(back).clamp(earliest, latest);
        Self {
            sec: i32::try_from(then.div_euclid(NANOS)).unwrap_or(i32::MAX),
            nanosec: u32::try_from(then.rem_euclid(NANOS)).unwrap_or(0),
        }
    }
}
