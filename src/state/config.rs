//! How a state starts: the configured modules and policies, and the limits.

use std::collections::BTreeMap;

use crate::{Module, Policy};

/// How to start: the modules that support cooperation, with their default policies, and the
/// limits.
#[derive(Clone, PartialEq, Eq, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Config {
    /// Every module that supports cooperation, with its default policy. Only these modules can
    /// have scenes (`[COOP-REG-MODULE.1]`) and policies (`[COOP-POL-UNKNOWN.1]`).
    pub policies: BTreeMap<Module, Policy>,
    /// The limits.
    pub limits: Limits,
}

impl Config {
    /// A configuration with these default policies and [`Limits::default`]. The methods below
    /// change one limit each:
    ///
    /// ```
    /// use cooperation::{Behavior, Config, Module, Policy, State};
    ///
    /// let config = Config::new([(Module::new(Behavior::Crosswalk), Policy::Required)])
    ///     .ttl_ms(2_000)
    ///     .max_scenes(64);
    /// assert_eq!((config.limits.ttl_ms, config.limits.max_scenes), (2_000, 64));
    /// assert_eq!(config.limits.max_batch, 1_024); // the default
    /// // A limit that cannot work is refused when the state is made.
    /// assert!(State::new(config.max_batch(0)).is_err());
    /// ```
    pub fn new(policies: impl IntoIterator<Item = (Module, Policy)>) -> Self {
        Self {
            policies: policies.into_iter().collect(),
            limits: Limits::default(),
        }
    }

    /// This configuration with `limits`.
    #[must_use]
    pub fn with_limits(self, limits: Limits) -> Self {
        Self { limits, ..self }
    }

    /// This configuration with [`Limits::ttl_ms`] set.
    #[must_use]
    pub fn ttl_ms(mut self, ttl_ms: u64) -> Self {
        self.limits.ttl_ms = ttl_ms;
        self
    }

    /// This configuration with [`Limits::max_scenes`] set.
    #[must_use]
    pub fn max_scenes(mut self, max_scenes: usize) -> Self {
        self.limits.max_scenes = max_scenes;
        self
    }

    /// This configuration with [`Limits::retired_capacity`] set.
    #[must_use]
    pub fn retired_capacity(mut self, retired_capacity: usize) -> Self {
        self.limits.retired_capacity = retired_capacity;
        self
    }

    /// This configuration with [`Limits::max_batch`] set.
    #[must_use]
    pub fn max_batch(mut self, max_batch: usize) -> Self {
        self.limits.max_batch = max_batch;
        self
    }
}

/// The bounds that keep memory and work finite.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Limits {
    /// A scene whose owner has not updated it for longer than this expires
    /// (`[COOP-TIME-EXPIRE.1]`). Default 10 000 ms.
    pub ttl_ms: u64,
    /// At most this many live scenes (`[COOP-REG-FULL.1]`). Default 4 096.
    pub max_scenes: usize,
    /// At most this many retired identifiers are remembered; beyond it the oldest is forgotten
    /// (`[COOP-RETIRE.1]`). Default 65 536.
    pub retired_capacity: usize,
    /// At most this many entries in one batch (`[COOP-BATCH-LIMIT.1]`). Default 1 024.
    pub max_batch: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            ttl_ms: 10_000,
            max_scenes: 4_096,
            retired_capacity: 65_536,
            max_batch: 1_024,
        }
    }
}

impl Limits {
    /// Whether these limits can work: every one that bounds a count is at least 1.
    pub(super) fn check(&self) -> Result<(), ConfigError> {
        if self.max_scenes == 0 {
            return Err(ConfigError::NoScenes);
        }
        if self.retired_capacity == 0 {
            return Err(ConfigError::NoRetiredCapacity);
        }
        if self.max_batch == 0 {
            return Err(ConfigError::NoBatch);
        }
        Ok(())
    }
}

/// A configuration that cannot work.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ConfigError {
    /// `max_scenes` is zero: no scene could ever register.
    NoScenes,
    /// `retired_capacity` is zero: identifiers would be reusable the moment they retire.
    NoRetiredCapacity,
    /// `max_batch` is zero: no command or policy could ever be set.
    NoBatch,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NoScenes => "max_scenes must be at least 1",
            Self::NoRetiredCapacity => "retired_capacity must be at least 1",
            Self::NoBatch => "max_batch must be at least 1",
        })
    }
}

impl std::error::Error for ConfigError {}
