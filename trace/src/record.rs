//! The records of a trace and their parsing: one JSON object per line.

use core::fmt;
use core::marker::PhantomData;
use std::collections::BTreeSet;

use cooperation::{
    Config, CooperationStatus, Decision, FactorKind, Input, Limits, Module, OperatorDecision,
    Phase, Policy, PolicySetting, SceneId,
};
use cooperation_adapters::wire;
use serde::de::{self, Unexpected, Visitor};
use serde::{Deserialize, Deserializer};

use crate::json::{from_json, json_error};
use crate::version::{upgrade_v1, Version};
use crate::{ErrorKind, TraceError, JSON_SPACE};

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
    /// `{"version": 2}`: the format's version, as the first record only; without one a trace
    /// is version 1 ([`Version`]).
    Version(Version),
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

/// A record as written; checked into a [`Record`] by [`parse_record`]. A field given as
/// `null` is refused, not taken as left out.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRecord {
    #[serde(default, deserialize_with = "present")]
    at_ms: Option<u64>,
    #[serde(default, deserialize_with = "present_input")]
    input: Option<Input>,
    #[serde(default, deserialize_with = "present")]
    observed: Option<Vec<RawStatus>>,
    #[serde(default, deserialize_with = "present_factors")]
    factors: Option<FactorKind>,
    #[serde(default, deserialize_with = "present")]
    config: Option<RawConfig>,
    #[serde(default, deserialize_with = "present")]
    version: Option<u64>,
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
    #[serde(default, deserialize_with = "present")]
    ttl_ms: Option<u64>,
    #[serde(default, deserialize_with = "present")]
    max_scenes: Option<usize>,
    #[serde(default, deserialize_with = "present")]
    retired_capacity: Option<usize>,
    #[serde(default, deserialize_with = "present")]
    max_batch: Option<usize>,
}

/// An observed status as written, in either form; [`RawStatus::check`] tells them apart by
/// `uuid` and refuses a field of one form in the other.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStatus {
    // The core's `CooperationStatus`.
    #[serde(default, deserialize_with = "present")]
    id: Option<SceneId>,
    #[serde(default, deserialize_with = "present")]
    module_decision: Option<Decision>,
    #[serde(default, deserialize_with = "present")]
    operator_decision: Option<OperatorDecision>,
    // The other fields of a replay's JSON scene: read (so checked), not compared.
    #[serde(default, deserialize_with = "present")]
    module: Option<Module>,
    #[serde(default, deserialize_with = "present")]
    phase: Option<Phase>,
    #[serde(default, deserialize_with = "present")]
    policy: Option<Option<Policy>>,
    #[serde(default, deserialize_with = "present")]
    merged_decision: Option<Option<Decision>>,
    #[serde(default, deserialize_with = "present")]
    force_activated: Option<bool>,
    #[serde(default, deserialize_with = "present")]
    force_deactivated: Option<bool>,
    // The AD API `CooperationStatus`.
    #[serde(default, deserialize_with = "present")]
    uuid: Option<wire::Uuid>,
    #[serde(default, deserialize_with = "present")]
    autonomous: Option<wire::CooperationDecision>,
    #[serde(default, deserialize_with = "present")]
    cooperator: Option<wire::CooperationDecision>,
    // Both.
    #[serde(default, deserialize_with = "present")]
    cancellable: Option<bool>,
}

/// An optional field that, when given, holds a value: `null` is refused as the field's type
/// refuses it, not read as a field left out.
fn present<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    deserializer: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(deserializer).map(Some)
}

/// [`present`] for `input`: serde_json explains `null` for an enumeration as "expected
/// value"; this says it is `null`.
fn present_input<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<Input>, D::Error> {
    deserializer.deserialize_option(NotNull::new("an input, an object with one key"))
}

/// [`present`] for `factors`, as [`present_input`].
fn present_factors<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Option<FactorKind>, D::Error> {
    deserializer.deserialize_option(NotNull::new("`Velocity` or `Steering`"))
}

/// A value that is not `null`, described as `expected` when it is.
struct NotNull<T> {
    expected: &'static str,
    value: PhantomData<T>,
}

impl<T> NotNull<T> {
    const fn new(expected: &'static str) -> Self {
        Self {
            expected,
            value: PhantomData,
        }
    }
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for NotNull<T> {
    type Value = Option<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.expected)
    }

    fn visit_none<E: de::Error>(self) -> Result<Option<T>, E> {
        Err(E::invalid_type(Unexpected::Unit, &self))
    }

    fn visit_some<D: Deserializer<'de>>(self, deserializer: D) -> Result<Option<T>, D::Error> {
        T::deserialize(deserializer).map(Some)
    }
}

impl RawStatus {
    /// The status, from the AD API form when `uuid` is given, else from the core's form.
    fn check(self) -> Result<CooperationStatus, ErrorKind> {
        let misplaced = |field: &str, form: &str| {
            json_error(
                field.to_owned(),
                &format!("a field of {form}, and this status is not in that form"),
            )
        };
        let Some(uuid) = self.uuid else {
            for (field, given) in [
                ("autonomous", self.autonomous.is_some()),
                ("cooperator", self.cooperator.is_some()),
            ] {
                if given {
                    return Err(misplaced(field, "the AD API form (with `uuid`)"));
                }
            }
            let missing =
                |field: &str| json_error(String::new(), &format!("missing field `{field}`"));
            return Ok(CooperationStatus {
                id: self.id.ok_or_else(|| missing("id"))?,
                module_decision: self
                    .module_decision
                    .ok_or_else(|| missing("module_decision"))?,
                operator_decision: self
                    .operator_decision
                    .ok_or_else(|| missing("operator_decision"))?,
                cancellable: self.cancellable.ok_or_else(|| missing("cancellable"))?,
            });
        };
        for (field, given) in [
            ("id", self.id.is_some()),
            ("module_decision", self.module_decision.is_some()),
            ("operator_decision", self.operator_decision.is_some()),
            ("module", self.module.is_some()),
            ("phase", self.phase.is_some()),
            ("policy", self.policy.is_some()),
            ("merged_decision", self.merged_decision.is_some()),
            ("force_activated", self.force_activated.is_some()),
            ("force_deactivated", self.force_deactivated.is_some()),
        ] {
            if given {
                return Err(misplaced(field, "the core's form (without `uuid`)"));
            }
        }
        // The AD API message's fields default as `cooperation_adapters::wire` reads them.
        let wire = wire::CooperationStatus {
            uuid,
            autonomous: self.autonomous.unwrap_or_default(),
            cooperator: self.cooperator.unwrap_or_default(),
            cancellable: self.cancellable.unwrap_or_default(),
        };
        CooperationStatus::try_from(&wire).map_err(|malformed| {
            let path = malformed.path().to_string();
            let shown = malformed.to_string();
            let message = shown.strip_prefix(&format!("{path}: ")).unwrap_or(&shown);
            json_error(path, message)
        })
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

/// Parses one record line (already trimmed, not blank, not a comment) of a trace of
/// `version`: a version-1 line is read in version 2's words ([`Version`]).
///
/// # Errors
/// A [`TraceError`] naming `line` and the field.
pub fn parse_record_of(version: Version, line: usize, text: &str) -> Result<Record, TraceError> {
    match version {
        Version::V2 => parse_record(line, text),
        // A version-1 line in version 2's words reads as it is, with the errors of its own
        // text; only a line with version-1 words is read upgraded.
        Version::V1 => parse_record(line, text).or_else(|error| match upgrade_v1(text) {
            Ok(Some(upgraded)) => parse_record(line, &upgraded),
            Ok(None) | Err(_) => Err(error),
        }),
    }
}

/// Parses one record line (already trimmed, not blank, not a comment) in the current
/// version's words.
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
    if let Some(number) = raw.version {
        let other = match (
            raw.at_ms,
            &raw.input,
            &raw.observed,
            raw.factors,
            &raw.config,
        ) {
            (None, None, None, None, None) => None,
            (Some(_), ..) => Some("at_ms"),
            (_, Some(_), ..) => Some("input"),
            (_, _, Some(_), ..) => Some("observed"),
            (.., Some(_), _) => Some("factors"),
            (.., Some(_)) => Some("config"),
        };
        if let Some(other) = other {
            return Err(ambiguous("version", other));
        }
        return Version::from_number(number)
            .map(Record::Version)
            .ok_or_else(|| at(ErrorKind::UnknownVersion { given: number }));
    }
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
        (None, Some(raw), factors) => Event::Observed(Observation {
            statuses: observed_statuses(raw).map_err(at)?,
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

fn observed_statuses(raw: Vec<RawStatus>) -> Result<Vec<CooperationStatus>, ErrorKind> {
    let mut seen = BTreeSet::new();
    let mut statuses = Vec::with_capacity(raw.len());
    for (index, raw) in raw.into_iter().enumerate() {
        let status = raw
            .check()
            .map_err(|kind| within(&format!("observed[{index}]"), kind))?;
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

/// Parses one observed status from its JSON text. Every form of status a trace accepts is
/// decoded as here. Two forms:
/// - the core's `CooperationStatus` in its serde form: `{"id": "<uuid>", "module_decision":
///   "Activate", "operator_decision": "Undecided", "cancellable": true}`; the other fields of
///   a replay's JSON scene (`module`, `phase`, `policy`, `merged_decision`,
///   `force_activated`, `force_deactivated`) are accepted and checked, not compared;
/// - the AD API message as rosbridge writes it (a status taken from a recorded factor's
///   `cooperation`): `{"uuid": {"uuid": [16 numbers] or "<base64>"}, "autonomous":
///   {"decision": 2}, "cooperator": {"decision": 4}, "cancellable": true}`, told apart by its
///   `uuid` field and converted by `cooperation_adapters::wire`.
///
/// Any other field, a field given twice, and an array in place of an object are refused.
///
/// # Errors
/// [`ErrorKind::Json`] naming the field, relative to the status.
pub fn parse_status(text: &str) -> Result<CooperationStatus, ErrorKind> {
    if !text.trim_start_matches(JSON_SPACE).starts_with('{') {
        return Err(json_error(
            String::new(),
            "a status is a JSON object (`{...}`)",
        ));
    }
    from_json::<RawStatus>(text, true)?.check()
}

/// Parses a configuration: the value of a `config` record, or a configuration file's whole
/// text. The errors name fields from `config`.
///
/// # Errors
/// A [`TraceError`] without a line (a file's JSON errors carry their line and column in the
/// message).
pub fn parse_config(text: &str) -> Result<Config, TraceError> {
    // A file may start with a byte-order mark, as a trace may.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if !text.trim_start_matches(JSON_SPACE).starts_with('{') {
        return Err(TraceError::nowhere(ErrorKind::NotAnObject));
    }
    let read = |text: &str| {
        from_json::<RawConfig>(text, false)
            .map_err(|kind| TraceError::nowhere(within("config", kind)))
    };
    // A configuration in version-1 words (`"LaneChange"`) is read upgraded, as a version-1
    // trace's lines are.
    let raw = read(text).or_else(|error| match upgrade_v1(text) {
        Ok(Some(upgraded)) => read(&upgraded),
        Ok(None) | Err(_) => Err(error),
    })?;
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
