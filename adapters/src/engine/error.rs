//! Why an engine cannot be built.

use core::fmt;

use cooperation::ConfigError;

/// A configuration the engine refuses, before it serves anything.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum EngineError {
    /// The settings file cannot be read or parsed: what went wrong, naming the file.
    Settings(String),
    /// The core refuses the configuration.
    Config(ConfigError),
    /// The interfaces' scene quotas together exceed the core's table (`[COOP-DEV-QUOTA.1]`):
    /// some interfaces could then fill it, and a module through another interface could not
    /// register a scene although its own interface is under its quota.
    QuotaOverTable {
        /// The live scenes each interface may hold.
        quota: usize,
        /// The RTC interfaces.
        interfaces: usize,
        /// The core's table (`max_scenes`).
        max_scenes: usize,
    },
    /// A publication rate (publications a second, as written) that is not above 0 and at most
    /// [`MAX_PUBLICATION_RATE_HZ`](super::MAX_PUBLICATION_RATE_HZ).
    PublicationRate(String),
    /// The RTC interfaces refuse their bindings: two with one name, or one with no sequence.
    Interfaces(crate::rtc::RtcError),
}

impl fmt::Display for EngineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Settings(message) => f.write_str(message),
            Self::Config(error) => error.fmt(f),
            Self::QuotaOverTable {
                quota,
                interfaces,
                max_scenes,
            } => write!(
                f,
                "a scene quota of {quota} for each of the {interfaces} RTC interfaces comes to \
                 {} live scenes, more than the core's {max_scenes} (max_scenes): some \
                 interfaces could fill the table and keep the others' modules from registering; \
                 give a quota of at most {}, or more max_scenes",
                quota.saturating_mul(*interfaces),
                max_scenes / (*interfaces).max(1),
            ),
            Self::PublicationRate(rate) => write!(
                f,
                "a rate of {rate} publications a second: give a rate above 0 and at most {}",
                super::MAX_PUBLICATION_RATE_HZ
            ),
            Self::Interfaces(error) => write!(f, "the RTC interfaces: {error}"),
        }
    }
}

impl std::error::Error for EngineError {}

impl From<ConfigError> for EngineError {
    fn from(error: ConfigError) -> Self {
        Self::Config(error)
    }
}
