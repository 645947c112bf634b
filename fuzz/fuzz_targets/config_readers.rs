//! Hostile bytes into every reader of settings: the core's `Config`, `Limits`, policy settings
//! and module names in their serde (and string) forms, the RTC bindings and module types in
//! theirs, and the trace tool's `parse_config`, `parse_record` and `parse_status`. No reader may
//! panic, and every failure is a typed error. Whatever decodes writes JSON that decodes to the
//! same value. A `Config` starts a `State` (and a trace `Replayer`) exactly when `State::new`'s
//! documented checks pass, else is refused with the `ConfigError` of the first zero limit, and
//! the state holds the configured policies and limits. Bindings make an `Rtc` exactly when no
//! name is bound twice and each has a sequence, and every binding is then found by its name. A
//! configuration the trace tool accepts is an object within its limits that the core accepts,
//! and reads the same as a `config` line; a refused one names no line, a refused record its
//! own. An accepted record is an object, never an explicit tick, observes no scene twice, and
//! its `config` reads the same from a file. A status reads back from its own serde form and, in
//! the core's form, takes a replay's other scene fields without change and refuses any other
//! field. A settings file (`cooperation_adapters::settings`) that reads gives a configuration with a
//! module that the core accepts, written back by `to_yaml` as text that reads the same; one
//! within the trace tool's limits reads the same under them, and any other is refused there
//! with a line and column.
#![no_main]

use std::collections::BTreeMap;

use cooperation::{
    Behavior, Config, ConfigError, Limits, Module, Policy, PolicySetting, Sequence, State,
};
use cooperation_adapters::rtc::{self, policy_for_auto_mode, Binding, Kind, ModuleType, Rtc, RtcError};
use cooperation_trace::{
    parse_config, parse_record, parse_status, ErrorKind, Event, Record, Replayer, MAX_LIMITS,
};
use libfuzzer_sys::fuzz_target;
use serde::{de::DeserializeOwned, Serialize};

/// The line number `parse_record` is told it reads.
const LINE: usize = 7;

/// Decodes `data` as a `T`; if it writes, checks that it reads back to the same value.
fn fixpoint<T: DeserializeOwned + Serialize + PartialEq + core::fmt::Debug>(
    data: &[u8],
) -> Option<T> {
    let value: T = serde_json::from_slice(data).ok()?;
    // A `Config` whose policies are not empty does not write: a JSON object's keys are strings,
    // and a module is a struct. That is serde_json's typed error, not a panic.
    if let Ok(first) = serde_json::to_vec(&value) {
        let Ok(again) = serde_json::from_slice::<T>(&first) else {
            panic!("written JSON does not read back")
        };
        assert_eq!(again, value, "not a fixpoint");
    }
    Some(value)
}

/// What `State::new` documents: refused with the first zero limit, in the order of its checks.
fn expected(limits: Limits) -> Result<(), ConfigError> {
    if limits.max_scenes == 0 {
        Err(ConfigError::NoScenes)
    } else if limits.retired_capacity == 0 {
        Err(ConfigError::NoRetiredCapacity)
    } else if limits.max_batch == 0 {
        Err(ConfigError::NoBatch)
    } else {
        Ok(())
    }
}

/// A configuration starts a state exactly as documented, holding what was configured.
fn check_config(config: &Config) {
    let started = State::new(config.clone());
    assert_eq!(
        started.as_ref().map(|_| ()).map_err(|e| *e),
        expected(config.limits)
    );
    // The trace tool's replayer starts from it exactly when the core does.
    match (Replayer::new(Some(config.clone())), &started) {
        (Ok(replayer), Ok(state)) => assert_eq!(replayer.state(), Some(state)),
        (Err(error), Err(refused)) => {
            assert_eq!(error.line, None);
            assert_eq!(error.kind, ErrorKind::InvalidConfig(*refused));
        }
        (replayer, state) => panic!("the replayer says {replayer:?}, the core {state:?}"),
    }
    let Ok(state) = started else {
        return;
    };
    assert_eq!(state.limits(), config.limits);
    let policies: BTreeMap<Module, Policy> = state
        .policies()
        .map(|setting| (setting.module, setting.policy))
        .collect();
    assert_eq!(policies, config.policies);
    assert_eq!(
        (state.scene_count(), state.retired_oldest_first().count()),
        (0, 0)
    );
    assert_eq!(state.check_invariants(), Ok(()));
    let Ok(json) = serde_json::to_vec(&state) else {
        panic!("a new state does not write")
    };
    assert_eq!(serde_json::from_slice::<State>(&json).ok(), Some(state));
}

/// Policy settings configure each module with the last policy given for it.
fn check_settings(settings: &[PolicySetting]) {
    let config = Config::new(settings.iter().map(|s| (s.module, s.policy)));
    check_config(&config);
    for setting in settings {
        let last = settings.iter().rev().find(|s| s.module == setting.module);
        assert_eq!(
            config.policies.get(&setting.module),
            last.map(|s| &s.policy)
        );
    }
}

/// Bindings make an adapter exactly when no name is bound twice and each has a sequence; else
/// the first binding that repeats a name or has no sequence is named.
fn check_bindings(bindings: &[Binding]) {
    let wrong = bindings.iter().enumerate().find(|(at, binding)| {
        bindings.iter().take(*at).any(|b| b.name == binding.name) || binding.sequences.is_empty()
    });
    let made = Rtc::new(bindings.iter().cloned());
    let rtc = match (made, wrong) {
        (Ok(rtc), None) => rtc,
        (Err(RtcError::DuplicateInterface { name }), Some((at, binding))) => {
            assert_eq!(name, binding.name);
            assert!(bindings.iter().take(at).any(|b| b.name == name));
            return;
        }
        (Err(RtcError::NoSequence { name }), Some((_, binding))) => {
            assert_eq!(name, binding.name);
            assert!(binding.sequences.is_empty());
            return;
        }
        (made, wrong) => panic!("made {made:?}, with {wrong:?} wrong"),
    };
    assert_eq!(rtc.bindings(), bindings);
    for enable_rtc in [false, true] {
        let policies = rtc.policies(enable_rtc);
        assert!(bindings
            .iter()
            .flat_map(Binding::modules)
            .all(|m| policies.get(&m) == Some(&policy_for_auto_mode(!enable_rtc))));
        assert_eq!(
            policies.len(),
            bindings
                .iter()
                .flat_map(Binding::modules)
                .collect::<std::collections::BTreeSet<_>>()
                .len()
        );
    }
    let Ok(state) = State::new(Config::new(rtc.policies(true))) else {
        panic!("the bindings' own policies are refused")
    };
    let unconfigured = State::new(Config::new([])).ok();
    for binding in bindings {
        let Ok(view) = rtc.view(&state, &binding.name) else {
            panic!("interface {:?} not found", binding.name)
        };
        assert_eq!(view.binding(), binding);
        assert!(!view.auto_mode_status().is_auto_mode);
        if let Some(unconfigured) = &unconfigured {
            assert!(matches!(
                rtc.view(unconfigured, &binding.name),
                Err(RtcError::Unconfigured { .. })
            ));
        }
    }
    let unknown = format!(
        "{}?",
        bindings.iter().map(|b| b.name.as_str()).collect::<String>()
    );
    assert!(matches!(
        rtc.view(&state, &unknown),
        Err(RtcError::UnknownInterface { .. })
    ));
    let statuses = rtc
        .auto_mode_status_array(&state, cooperation_adapters::Time::default())
        .statuses;
    assert_eq!(statuses.len(), bindings.len());
}

fn check_module_type(module_type: ModuleType) {
    assert_eq!(
        ModuleType::from_value(module_type.value()),
        Some(module_type)
    );
    assert_eq!(
        rtc::Module::from(module_type).module_type(),
        Ok(module_type)
    );
    match module_type.legacy_value() {
        Some(legacy) => assert_eq!(ModuleType::from_legacy_value(legacy), Some(module_type)),
        None => assert_eq!(module_type, ModuleType::Roundabout),
    }
    assert!(!module_type.constant().is_empty());
}

/// The white space JSON allows between tokens.
const JSON_SPACE: [char; 4] = [' ', '\t', '\r', '\n'];

/// The trace tool's readers.
fn check_trace(text: &str) {
    // A configuration file may start with a byte-order mark.
    let file = text.strip_prefix('\u{feff}').unwrap_or(text);
    match parse_config(text) {
        Ok(config) => {
            let object = file.trim_start_matches(JSON_SPACE).starts_with('{');
            assert!(object, "a configuration that is not an object");
            let limits = config.limits;
            assert!(limits.max_scenes <= MAX_LIMITS.max_scenes);
            assert!(limits.retired_capacity <= MAX_LIMITS.retired_capacity);
            assert!(limits.max_batch <= MAX_LIMITS.max_batch);
            assert_eq!(expected(limits), Ok(()));
            check_config(&config);
            // The same object as a trace's `config` line.
            let line = format!("{{\"config\": {file}}}");
            assert_eq!(parse_record(LINE, &line), Ok(Record::Config(config)));
        }
        Err(error) => assert_eq!(error.line, None, "{error}"),
    }
    match parse_record(LINE, text) {
        Ok(record) => {
            assert!(text.starts_with('{'), "a record that is not an object");
            check_record(text, record);
        }
        Err(error) => assert_eq!(error.line, Some(LINE), "{error}"),
    }
    check_status(text);
    if let Ok(value) = serde_json::from_str::<serde_json::Value>(text) {
        // The items of a list, and those of a record's `observed`.
        let items = value.as_array().into_iter().flatten();
        let observed = value.get("observed").and_then(|o| o.as_array());
        for status in items.chain(observed.into_iter().flatten()) {
            check_status(&status.to_string());
        }
    }
}

fn check_record(text: &str, record: Record) {
    match record {
        Record::Config(config) => {
            check_config(&config);
            // The same object from a configuration file.
            let Ok(value) = serde_json::from_str::<serde_json::Value>(text) else {
                panic!("an accepted record is not JSON")
            };
            let file = value["config"].to_string();
            assert_eq!(parse_config(&file).ok(), Some(config), "as a file: {file}");
        }
        Record::Version(version) => {
            let Ok(value) = serde_json::from_str::<serde_json::Value>(text) else {
                panic!("an accepted record is not JSON")
            };
            assert_eq!(value["version"].as_u64(), Some(version.number()));
        }
        Record::At { at_ms, event } => match event {
            Event::Time => assert!(at_ms.is_some()),
            Event::Input(input) => {
                assert!(!matches!(input, cooperation::Input::Tick { .. }));
            }
            Event::Observed(observation) => {
                let ids: std::collections::BTreeSet<_> =
                    observation.statuses.iter().map(|s| s.id).collect();
                assert_eq!(ids.len(), observation.statuses.len());
            }
        },
    }
}

/// A status reads back from its own serde form. In the core's form (without `uuid`), the other
/// fields of a replay's JSON scene are accepted and change nothing, and any other field is
/// refused.
fn check_status(text: &str) {
    let Ok(status) = parse_status(text) else {
        return;
    };
    let Ok(own) = serde_json::to_string(&status) else {
        panic!("a status does not write")
    };
    assert_eq!(parse_status(&own), Ok(status));
    let Ok(serde_json::Value::Object(fields)) = serde_json::from_str(text) else {
        panic!("an accepted status is not a JSON object")
    };
    if fields.contains_key("uuid") {
        return;
    }
    let with = |field: &str, value: serde_json::Value| {
        let mut more = fields.clone();
        more.insert(field.to_owned(), value);
        parse_status(&serde_json::Value::Object(more).to_string())
    };
    if !fields.contains_key("merged_decision") {
        assert_eq!(with("merged_decision", "activate".into()), Ok(status));
    }
    assert!(
        with("merged", "activate".into()).is_err(),
        "another field is read"
    );
}

fuzz_target!(|data: &[u8]| {
    // The core's configuration.
    if let Some(config) = fixpoint::<Config>(data) {
        check_config(&config);
    }
    if let Some(limits) = fixpoint::<Limits>(data) {
        check_config(&Config {
            policies: BTreeMap::new(),
            limits,
        });
    }
    if let Some(settings) = fixpoint::<Vec<PolicySetting>>(data) {
        check_settings(&settings);
    }
    if let Some(setting) = fixpoint::<PolicySetting>(data) {
        check_settings(&[setting]);
    }
    let _ = fixpoint::<Module>(data);
    let _ = fixpoint::<Policy>(data);
    let _ = fixpoint::<Behavior>(data);
    let _ = fixpoint::<Sequence>(data);

    // The RTC bindings.
    if let Some(bindings) = fixpoint::<Vec<Binding>>(data) {
        check_bindings(&bindings);
    }
    if let Some(binding) = fixpoint::<Binding>(data) {
        check_bindings(&[binding]);
    }
    let _ = fixpoint::<Kind>(data);
    if let Some(module_type) = fixpoint::<ModuleType>(data) {
        check_module_type(module_type);
    }

    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // The names of behaviours and sequences, as the AD API writes them.
    if let Ok(behavior) = text.parse::<Behavior>() {
        assert_eq!(behavior.as_str(), text);
    }
    if let Ok(sequence) = text.parse::<Sequence>() {
        assert_eq!(sequence.as_str(), text);
    }
    check_trace(text);
    check_settings_file(text);
});

/// A settings file: read, it is a configuration the core accepts, and it round-trips.
fn check_settings_file(text: &str) {
    use cooperation_adapters::settings;
    let within = settings::parse_within(text, &MAX_LIMITS);
    let Ok(config) = settings::parse(text) else {
        let Err(error) = within else {
            panic!("parse_within accepts what parse refuses")
        };
        assert!(error.line >= 1 && error.column >= 1, "{error}");
        return;
    };
    assert!(!config.policies.is_empty());
    check_config(&config);
    assert_eq!(
        settings::parse(&settings::to_yaml(&config)),
        Ok(config.clone())
    );
    match within {
        Ok(bounded) => assert_eq!(bounded, config),
        Err(error) => assert!(
            matches!(error.kind, settings::SettingsErrorKind::AboveMaximum { .. }),
            "{error}"
        ),
    }
}
