//! A configuration written as a settings file.

use core::fmt::Write as _;
use std::collections::BTreeMap;

use cooperation::{Config, Policy};
use saphyr_parser::ScalarStyle;

use super::scalar::kind;
use super::Found;

/// The node key [`to_yaml`](super::to_yaml) writes: every node.
const NODE: &str = "/**";

/// Writes `config` as a settings file, node key `/**`, every limit written out. Behaviours
/// come in the order of their strings; a behaviour with one policy is written `behaviour:
/// policy`, one with sequences only as a map of its sequences, and one with both as flat keys
/// (`avoidance: required`, then `avoidance.change: optional`).
pub(super) fn to_yaml(config: &Config) -> String {
    // Behaviour → (sequence, policy), the empty sequence as "". The strings are the module's
    // own (`avoidance/change`), so the file says what the AD API says.
    let mut behaviors: BTreeMap<String, Vec<(String, Policy)>> = BTreeMap::new();
    for (module, policy) in &config.policies {
        let name = module.to_string();
        let (behavior, sequence) = name.split_once('/').unwrap_or((&name, ""));
        behaviors
            .entry(behavior.to_owned())
            .or_default()
            .push((sequence.to_owned(), *policy));
    }
    let mut out = format!("{NODE}:\n  ros__parameters:\n    cooperation:\n      policies:");
    if behaviors.is_empty() {
        out.push_str(" {}");
    }
    out.push('\n');
    let indent = "        ";
    for (name, mut sequences) in behaviors {
        sequences.sort();
        let behavior = key(&name);
        match sequences.as_slice() {
            [(alone, policy)] if alone.is_empty() => {
                let _ = writeln!(out, "{indent}{behavior}: {policy}");
            }
            [(first, _), ..] if !first.is_empty() => {
                let _ = writeln!(out, "{indent}{behavior}:");
                for (sequence, policy) in &sequences {
                    let _ = writeln!(out, "{indent}  {}: {policy}", key(sequence));
                }
            }
            _ => {
                for (sequence, policy) in &sequences {
                    if sequence.is_empty() {
                        let _ = writeln!(out, "{indent}{behavior}: {policy}");
                    } else {
                        let _ = writeln!(
                            out,
                            "{indent}{}: {policy}",
                            key(&format!("{name}.{sequence}"))
                        );
                    }
                }
            }
        }
    }
    let limits = &config.limits;
    let _ = write!(
        out,
        "      limits:\n{indent}ttl_ms: {}\n{indent}max_scenes: {}\n{indent}retired_capacity: {}\n\
         {indent}max_batch: {}\n",
        limits.ttl_ms, limits.max_scenes, limits.retired_capacity, limits.max_batch
    );
    out
}

/// Words that YAML 1.1 readers (PyYAML, and so launch files) take for booleans, though YAML
/// 1.2 and this reader take them for strings: written quoted, every reader sees the name.
const YAML_1_1_BOOLEANS: [&str; 8] = ["y", "n", "yes", "no", "on", "off", "Y", "N"];

/// A key as written: plain when it is a name of ASCII letters, digits, `-`, `_` and `.`
/// starting with a letter (as every behaviour and sequence is) that YAML reads as a string,
/// else double-quoted (`"null"`, `"true"`: the reader refuses a key of another type; `"yes"`,
/// `"off"`: YAML 1.1's booleans).
fn key(name: &str) -> String {
    let plain = name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
        && kind(name, ScalarStyle::Plain) == Found::String
        && !YAML_1_1_BOOLEANS.contains(&name);
    if plain {
        return name.to_owned();
    }
    let mut quoted = String::with_capacity(name.len() + 2);
    quoted.push('"');
    for c in name.chars() {
        match c {
            '"' => quoted.push_str("\\\""),
            '\\' => quoted.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(quoted, "\\u{:04X}", u32::from(c));
            }
            c => quoted.push(c),
        }
    }
    quoted.push('"');
    quoted
}
