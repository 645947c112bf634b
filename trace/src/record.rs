//! The records of a trace and their parsing: one JSON object per line.

use std::collections::BTreeSet;

use cooperation::{Config, CooperationStatus, FactorKind, Input, Limits, PolicySetting};
use serde::Deserialize;

use crate::{ErrorKind, TraceError};

/// The largest limits a trace's configuration may ask for. They bound the replayer's memory:
/// the core holds at most `max_scenes` live scenes and `retired_capacity` retired identifiers,
/// and the replayer's record of which rule last touched each scene is bounded by their sum
/// plus one batch.
pub const MAX_LIMITS: Limits = Limits {
    ttl_ms: u64::MAX,
    max_scenes: 65_536,
    retired_capacity: 1_048_576,
    max_batch: 65_536,
};

/// One record of a trace.
#[derive(Clone, PartialEq, Debug)]
pub enum Record {
    /// `{"config": …}`: the modules, their default policies and the limits. Only as the first
    /// record.
    Config(Config),
    /// A record at a time: an input, an observation, or only the time passing.
    At {
        /// `at_ms`: the record's time; `None` is "at the time of the record before".
        at_ms: Option<u64>,
        /// What happens at that time.
        event: Event,
    },
}

/// What happens at a record's time.
#[derive(Clone, PartialEq, Debug)]
pub enum Event {
    /// Only time passes (a record with `at_ms` alone).
    Time,
    /// `input`: one input to the core (never a `Tick`: time comes from `at_ms`).
    Input(Input),
    /// `observed`: the statuses the real system reported, for `validate`.
    Observed(Observation),
}

/// What the real system reported: the statuses of every live scene, or of every live scene
/// of one factor kind.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Observation {
    /// The statuses, in the order given; no scene twice.
    pub statuses: Vec<CooperationStatus>,
    /// `factors`: when given, the observation lists only the scenes of this kind (one
    /// factor topic); otherwise it lists every live scene.
    pub factors: Option<FactorKind>,
}

/// A record as written; checked into a [`Record`] by [`parse_record`].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRecord {
    #[serde(default)]
    at_ms: Option<u64>,
    #[serde(default)]
    input: Option<Input>,
    #[serde(default)]
    observed: Option<Vec<serde_json::Value>>,
    #[serde(default)]
    factors: Option<FactorKind>,
    #[serde(default)]
    config: Option<RawConfig>,
}

/// A configuration as written: policies as a list, limits optional one by one.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    policies: Vec<PolicySetting>,
    #[serde(default)]
    limits: RawLimits,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawLimits {
    #[serde(default)]
    ttl_ms: Option<u64>,
    #[serde(default)]
    max_scenes: Option<usize>,
    #[serde(default)]
    retired_capacity: Option<usize>,
    #[serde(default)]
    max_batch: Option<usize>,
}

/// Deserializes `text` as a `T`, naming the field that fails. For a single line (`one_line`),
/// positions are given as columns.
fn from_json<'de, T: Deserialize<'de>>(text: &'de str, one_line: bool) -> Result<T, ErrorKind> {
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut deserializer).map_err(|error| {
        let field = field_path(error.path());
        ErrorKind::Json {
            field,
            message: json_message(&error.into_inner(), one_line),
        }
    })?;
    deserializer.end().map_err(|error| ErrorKind::Json {
        field: String::new(),
        message: json_message(&error, one_line),
    })?;
    Ok(value)
}

/// The path of a failing field; empty for the whole value (the library writes `.`) or when
/// the error comes before any field is known (`?`, a key that is not a string).
fn field_path(path: &serde_path_to_error::Path) -> String {
    let path = path.to_string();
    if path == "." || path == "?" {
        String::new()
    } else {
        path
    }
}

/// serde_json's message; within one line, "at column N" rather than "at line 1 column N".
fn json_message(error: &serde_json::Error, one_line: bool) -> String {
    let message = error.to_string();
    let position = format!(" at line {} column {}", error.line(), error.column());
    match message.strip_suffix(&position) {
        Some(bare) if one_line => format!("{bare} (column {})", error.column()),
        _ => message,
    }
}

/// Prefixes a JSON error's field with `prefix` (the path of the value it was parsed from).
fn within(prefix: &str, kind: ErrorKind) -> ErrorKind {
    match kind {
        ErrorKind::Json { field, message } => ErrorKind::Json {
            field: if field.is_empty() {
                prefix.to_owned()
            } else if field.starts_with('[') {
                format!("{prefix}{field}")
            } else {
                format!("{prefix}.{field}")
            },
            message,
        },
        other => other,
    }
}

/// Parses one record line (already trimmed, not blank, not a comment).
///
/// # Errors
/// A [`TraceError`] naming `line` and the field.
pub fn parse_record(line: usize, text: &str) -> Result<Record, TraceError> {
    let at = |kind| TraceError::at(line, kind);
    // serde would also read a struct from an array of its fields in order; a record is an
    // object only.
    if !text.starts_with('{') {
        return Err(at(ErrorKind::NotAnObject));
    }
    let raw: RawRecord = from_json(text, true).map_err(at)?;
    let ambiguous = |first, second| at(ErrorKind::Ambiguous { first, second });
    if let Some(config) = raw.config {
        return match (raw.at_ms, &raw.input, &raw.observed, raw.factors) {
            (Some(_), ..) => Err(ambiguous("config", "at_ms")),
            (_, Some(_), ..) => Err(ambiguous("config", "input")),
            (_, _, Some(_), _) => Err(ambiguous("config", "observed")),
            (.., Some(_)) => Err(ambiguous("config", "factors")),
            (None, None, None, None) => check_config(config).map(Record::Config).map_err(at),
        };
    }
    let event = match (raw.input, raw.observed, raw.factors) {
        (Some(_), Some(_), _) => return Err(ambiguous("input", "observed")),
        (_, None, Some(_)) => return Err(at(ErrorKind::FactorsWithoutObserved)),
        (Some(Input::Tick { .. }), None, None) => return Err(at(ErrorKind::TickInput)),
        (Some(input), None, None) => Event::Input(input),
        (None, Some(values), factors) => Event::Observed(Observation {
            statuses: observed_statuses(&values).map_err(at)?,
            factors,
        }),
        (None, None, None) if raw.at_ms.is_some() => Event::Time,
        (None, None, None) => return Err(at(ErrorKind::EmptyRecord)),
    };
    Ok(Record::At {
        at_ms: raw.at_ms,
        event,
    })
}

fn observed_statuses(values: &[serde_json::Value]) -> Result<Vec<CooperationStatus>, ErrorKind> {
    let mut seen = BTreeSet::new();
    let mut statuses = Vec::with_capacity(values.len());
    for (index, value) in values.iter().enumerate() {
        let status =
            parse_status(value).map_err(|kind| within(&format!("observed[{index}]"), kind))?;
        if !seen.insert(status.id) {
            return Err(ErrorKind::DuplicateObserved {
                index,
                id: status.id,
            });
        }
        statuses.push(status);
    }
    Ok(statuses)
}

/// Parses one observed status. Every form of status a trace accepts is decoded here and
/// nowhere else. Two forms:
/// - the core's `CooperationStatus` in its serde form: `{"id": "<uuid>", "module_decision":
///   "Activate", "operator_decision": "Undecided", "cancellable": true}` (other fields, such as
///   those of a replay's JSON output, are ignored);
/// - the AD API message as rosbridge writes it (a status taken from a recorded factor's
///   `cooperation`): `{"uuid": {"uuid": [16 numbers] or "<base64>"}, "autonomous":
///   {"decision": 2}, "cooperator": {"decision": 4}, "cancellable": true}`, told apart by its
///   `uuid` field and parsed by `cooperation::wire`.
///
/// # Errors
/// [`ErrorKind::Json`] naming the field, relative to the status.
pub fn parse_status(value: &serde_json::Value) -> Result<CooperationStatus, ErrorKind> {
    if value.get("uuid").is_some() {
        let wire: cooperation::wire::CooperationStatus = serde_path_to_error::deserialize(value)
            .map_err(|error| ErrorKind::Json {
                field: field_path(error.path()),
                message: error.into_inner().to_string(),
            })?;
        return CooperationStatus::try_from(&wire).map_err(|malformed| ErrorKind::Json {
            field: String::new(),
            message: malformed.to_string(),
        });
    }
    serde_path_to_error::deserialize(value).map_err(|error| ErrorKind::Json {
        field: field_path(error.path()),
        message: error.into_inner().to_string(),
    })
}

/// Parses a configuration: the value of a `config` record, or a configuration file's whole
/// text. The errors name fields from `config`.
///
/// # Errors
/// A [`TraceError`] without a line (a file's JSON errors carry their line and column in the
/// message).
pub fn parse_config(text: &str) -> Result<Config, TraceError> {
    if !text.trim_start().starts_with('{') {
        return Err(TraceError::nowhere(ErrorKind::NotAnObject));
    }
    let raw: RawConfig =
        from_json(text, false).map_err(|kind| TraceError::nowhere(within("config", kind)))?;
    check_config(raw).map_err(TraceError::nowhere)
}

fn check_config(raw: RawConfig) -> Result<Config, ErrorKind> {
    let mut config = Config::new([]);
    for (index, setting) in raw.policies.into_iter().enumerate() {
        if config
            .policies
            .insert(setting.module, setting.policy)
            .is_some()
        {
            return Err(ErrorKind::DuplicateModule {
                index,
                module: setting.module,
            });
        }
    }
    let defaults = Limits::default();
    let limits = Limits {
        ttl_ms: raw.limits.ttl_ms.unwrap_or(defaults.ttl_ms),
        max_scenes: raw.limits.max_scenes.unwrap_or(defaults.max_scenes),
        retired_capacity: raw
            .limits
            .retired_capacity
            .unwrap_or(defaults.retired_capacity),
        max_batch: raw.limits.max_batch.unwrap_or(defaults.max_batch),
    };
    for (field, given, max) in [
        ("max_scenes", limits.max_scenes, MAX_LIMITS.max_scenes),
        (
            "retired_capacity",
            limits.retired_capacity,
            MAX_LIMITS.retired_capacity,
        ),
        ("max_batch", limits.max_batch, MAX_LIMITS.max_batch),
    ] {
        if given > max {
            return Err(ErrorKind::LimitTooLarge {
                field,
                given: u64::try_from(given).unwrap_or(u64::MAX),
                max: u64::try_from(max).unwrap_or(u64::MAX),
            });
        }
    }
    config.limits = limits;
    // The core's own checks (no zero limits), so that the error is found at the config line.
    cooperation::State::new(config.clone()).map_err(ErrorKind::InvalidConfig)?;
    Ok(config)
}
