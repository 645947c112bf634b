//! The limits a settings file may set, by key.

use cooperation::Limits;

/// A limit, by its key.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Limit {
    TtlMs,
    MaxScenes,
    RetiredCapacity,
    MaxBatch,
}

impl Limit {
    pub(super) const ALL: [Self; 4] = [
        Self::TtlMs,
        Self::MaxScenes,
        Self::RetiredCapacity,
        Self::MaxBatch,
    ];

    pub(super) const fn key(self) -> &'static str {
        match self {
            Self::TtlMs => "ttl_ms",
            Self::MaxScenes => "max_scenes",
            Self::RetiredCapacity => "retired_capacity",
            Self::MaxBatch => "max_batch",
        }
    }

    /// This limit of `limits`, as a whole number.
    pub(super) fn get(self, limits: &Limits) -> u64 {
        let value = match self {
            Self::TtlMs => return limits.ttl_ms,
            Self::MaxScenes => limits.max_scenes,
            Self::RetiredCapacity => limits.retired_capacity,
            Self::MaxBatch => limits.max_batch,
        };
        u64::try_from(value).unwrap_or(u64::MAX)
    }

    /// `limits` with this limit set to `value`, or `None` if its type cannot hold it.
    pub(super) fn set(self, mut limits: Limits, value: u64) -> Option<Limits> {
        let count = usize::try_from(value).ok();
        match self {
            Self::TtlMs => limits.ttl_ms = value,
            Self::MaxScenes => limits.max_scenes = count?,
            Self::RetiredCapacity => limits.retired_capacity = count?,
            Self::MaxBatch => limits.max_batch = count?,
        }
        Some(limits)
    }

    /// The largest value this limit's type holds.
    pub(super) fn type_max(self) -> u64 {
        match self {
            Self::TtlMs => u64::MAX,
            _ => u64::try_from(usize::MAX).unwrap_or(u64::MAX),
        }
    }
}
