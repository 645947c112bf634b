//! Percentiles, and how the tables show durations and shares.

use std::time::Duration;

/// Percentiles of a set of durations.
pub(super) struct Summary {
    pub(super) count: usize,
    pub(super) p50: Duration,
    pub(super) p99: Duration,
    pub(super) max: Duration,
    pub(super) mean: Duration,
}

impl Summary {
    pub(super) fn of(mut samples: Vec<Duration>) -> Self {
        samples.sort_unstable();
        let count = samples.len();
        let at = |fraction: f64| -> Duration {
            if count == 0 {
                return Duration::ZERO;
            }
            let rank = ((fraction * count as f64).ceil() as usize).clamp(1, count);
            samples[rank - 1]
        };
        let total: Duration = samples.iter().sum();
        Self {
            count,
            p50: at(0.50),
            p99: at(0.99),
            max: samples.last().copied().unwrap_or_default(),
            mean: if count == 0 {
                Duration::ZERO
            } else {
                total / u32::try_from(count).unwrap_or(u32::MAX)
            },
        }
    }
}

/// A duration for a table: ns below 1 µs, µs below 10 ms, ms above.
pub(super) fn show(duration: Duration) -> String {
    let micros = duration.as_secs_f64() * 1e6;
    if micros < 1.0 {
        format!("{:.0} ns", micros * 1_000.0)
    } else if micros < 10.0 {
        format!("{micros:.2} µs")
    } else if micros < 10_000.0 {
        format!("{micros:.0} µs")
    } else {
        format!("{:.1} ms", micros / 1_000.0)
    }
}

/// `part` as a percentage of `whole`, to two significant digits below 10 %.
pub(super) fn share(part: Duration, whole: Duration) -> String {
    if whole.is_zero() {
        return "–".to_owned();
    }
    let percent = 100.0 * part.as_secs_f64() / whole.as_secs_f64();
    if percent >= 10.0 || percent <= 0.0 {
        return format!("{percent:.1} %");
    }
    let decimals = (1.0 - percent.log10().floor()).max(1.0) as usize;
    format!("{percent:.decimals$} %")
}
