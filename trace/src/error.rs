//! What can be wrong with a trace: every error names its line (when it has one) and the field.

use core::fmt;

use cooperation::{ConfigError, Module, SceneId};

/// A trace that cannot be read, or output that cannot be written. Replay and validation stop
/// at the first one; nothing in this crate panics instead.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct TraceError {
    /// The trace's line (1-based, counting every line, blank and comment lines included), or
    /// `None` when the error concerns no line (a configuration file, the output).
    pub line: Option<usize>,
    /// What is wrong.
    pub kind: ErrorKind,
}

impl TraceError {
    pub(crate) const fn at(line: usize, kind: ErrorKind) -> Self {
        Self {
            line: Some(line),
            kind,
        }
    }

    pub(crate) const fn nowhere(kind: ErrorKind) -> Self {
        Self { line: None, kind }
    }
}

/// What is wrong with a trace.
#[derive(Clone, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum ErrorKind {
    /// Reading the trace failed.
    Read {
        /// The I/O error's message.
        message: String,
    },
    /// Writing the output failed.
    Write {
        /// The I/O error's message.
        message: String,
    },
    /// The line is longer than [`ReadLimits::max_line_bytes`](crate::ReadLimits).
    LineTooLong {
        /// The limit, in bytes.
        limit: usize,
    },
    /// The trace has more lines than [`ReadLimits::max_lines`](crate::ReadLimits).
    TooManyLines {
        /// The limit.
        limit: usize,
    },
    /// The line is not UTF-8.
    NotUtf8 {
        /// Where in the line the first byte that is not UTF-8 is, counted in bytes from 0
        /// (a byte-order mark included).
        offset: usize,
    },
    /// The line is not the JSON the format asks for. `field` is the path to the offending
    /// value (`input.Register.geometry`, `observed[2].cancellable`), empty for the whole line.
    Json {
        /// Where in the record.
        field: String,
        /// serde_json's explanation, with its column.
        message: String,
    },
    /// The line (or configuration file) is not a JSON object.
    NotAnObject,
    /// A version record with a version this reader does not know.
    UnknownVersion {
        /// The version given.
        given: u64,
    },
    /// A version record that is not the trace's first record.
    MisplacedVersion,
    /// A record with none of `at_ms`, `input`, `observed` and `config`.
    EmptyRecord,
    /// A record with two of `input`, `observed` and `config`, or `config` with another field.
    Ambiguous {
        /// The first field.
        first: &'static str,
        /// The field that cannot go with it.
        second: &'static str,
    },
    /// A record with `factors` but no `observed`.
    FactorsWithoutObserved,
    /// An explicit `Tick` input: the trace's time is `at_ms`, and the replayer makes the ticks.
    TickInput,
    /// `at_ms` is smaller than an earlier record's.
    TimeBackwards {
        /// The trace's time so far.
        previous_ms: u64,
        /// This record's time.
        at_ms: u64,
    },
    /// A record before any configuration (neither a first `config` line nor `--config`).
    MissingConfig,
    /// A `config` line that is not the trace's first record, or one given as well as a
    /// configuration file.
    MisplacedConfig,
    /// The core refuses the configuration's limits.
    InvalidConfig(ConfigError),
    /// A configuration limit above what this tool accepts ([`MAX_LIMITS`](crate::MAX_LIMITS)).
    LimitTooLarge {
        /// The limit's field.
        field: &'static str,
        /// The value given.
        given: u64,
        /// The largest value accepted.
        max: u64,
    },
    /// The configuration names a module twice.
    DuplicateModule {
        /// The position in `config.policies`.
        index: usize,
        /// The module.
        module: Module,
    },
    /// An observation lists a scene twice.
    DuplicateObserved {
        /// The position of the second entry in `observed`.
        index: usize,
        /// The scene.
        id: SceneId,
    },
}

impl fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Read { message } => write!(f, "cannot read the trace: {message}"),
            Self::Write { message } => write!(f, "cannot write the output: {message}"),
            Self::LineTooLong { limit } => {
                write!(f, "the line is longer than {limit} bytes")
            }
            Self::TooManyLines { limit } => write!(f, "the trace has more than {limit} lines"),
            Self::NotUtf8 { offset } => write!(
                f,
                "the line is not UTF-8 at byte {offset} (column {})",
                offset.saturating_add(1)
            ),
            Self::Json { field, message } if field.is_empty() => f.write_str(message),
            Self::Json { field, message } => write!(f, "field `{field}`: {message}"),
            Self::NotAnObject => f.write_str("not a JSON object (`{...}`)"),
            Self::UnknownVersion { given } => write!(
                f,
                "trace format version {given} is not known; this reader knows versions 1 and 2"
            ),
            Self::MisplacedVersion => {
                f.write_str("a `version` record goes only on the trace's first record")
            }
            Self::EmptyRecord => {
                f.write_str("the record has none of `at_ms`, `input`, `observed` and `config`")
            }
            Self::Ambiguous { first, second } => {
                write!(f, "field `{second}` cannot go with `{first}` in one record")
            }
            Self::FactorsWithoutObserved => {
                f.write_str("field `factors` goes only with `observed`")
            }
            Self::TickInput => f.write_str(
                "field `input`: a `Tick` input is not accepted; time is given by `at_ms`",
            ),
            Self::TimeBackwards { previous_ms, at_ms } => write!(
                f,
                "field `at_ms`: time goes backwards, from {previous_ms} ms to {at_ms} ms"
            ),
            Self::MissingConfig => f.write_str(
                "no configuration: the first record must be a `config` line, or use --config",
            ),
            Self::MisplacedConfig => f.write_str(
                "field `config`: a configuration is accepted only as the first record, and \
                 not together with --config",
            ),
            Self::InvalidConfig(error) => write!(f, "field `config.limits`: {error}"),
            Self::LimitTooLarge { field, given, max } => write!(
                f,
                "field `config.limits.{field}`: {given} is larger than the {max} this tool accepts"
            ),
            Self::DuplicateModule { index, module } => write!(
                f,
                "field `config.policies[{index}]`: module {module} is configured twice"
            ),
            Self::DuplicateObserved { index, id } => {
                write!(f, "field `observed[{index}]`: scene {id} is listed twice")
            }
        }
    }
}

impl fmt::Display for TraceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line}: {}", self.kind),
            None => self.kind.fmt(f),
        }
    }
}

impl std::error::Error for TraceError {}
