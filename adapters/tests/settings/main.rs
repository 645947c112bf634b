//! Settings files (`cooperation_adapters::settings`): the layouts read, every error with its line,
//! column, key and message, the example file, the documentation, and round trips.

mod errors;
mod errors_values;
mod example;
mod interfaces;
mod layouts;
mod properties;

use cooperation::{Behavior, Config, Module, Policy, Sequence};
use cooperation_adapters::settings::{self, SettingsError, SettingsErrorKind};

/// Lines joined into a file.
fn lines(lines: &[&str]) -> String {
    let mut text = lines.join("\n");
    text.push('\n');
    text
}

/// A file whose `cooperation` map holds `body` (lines already indented by six spaces for
/// `policies:` and `limits:`); its first line of `body` is line 4.
fn cooperation(body: &[&str]) -> String {
    let mut all = vec!["/**:", "  ros__parameters:", "    cooperation:"];
    all.extend_from_slice(body);
    lines(&all)
}

/// A file with `policies` holding `entries` (indented by eight spaces), whose first entry is
/// line 5.
fn policies(entries: &[&str]) -> String {
    let mut body = vec!["      policies:"];
    body.extend_from_slice(entries);
    cooperation(&body)
}

/// Parses `text`, expecting it refused at `line` and `column`, at `key`, with `kind` and the
/// message `message` (what `Display` writes after the place and key).
fn refused(
    text: &str,
    (line, column): (usize, usize),
    key: &str,
    kind: &SettingsErrorKind,
    message: &str,
) -> SettingsError {
    let error = settings::parse(text).expect_err(text);
    assert_eq!(
        (error.line, error.column),
        (line, column),
        "{text}\n{error}"
    );
    assert_eq!(error.key, key, "{text}");
    assert_eq!(&error.kind, kind, "{text}");
    let place = format!("line {line}, column {column}: ");
    let shown = if key.is_empty() {
        format!("{place}{message}")
    } else {
        format!("{place}{key}: {message}")
    };
    assert_eq!(error.to_string(), shown, "{text}");
    error
}

fn module(behavior: Behavior) -> Module {
    Module::new(behavior)
}

fn sequence(behavior: Behavior, sequence: Sequence) -> Module {
    Module::with_sequence(behavior, sequence)
}

/// The configuration with these policies and the default limits.
fn config(policies: &[(Module, Policy)]) -> Config {
    Config::new(policies.iter().cloned())
}

const POLICIES: &str = "/**.ros__parameters.cooperation.policies";
const LIMITS: &str = "/**.ros__parameters.cooperation.limits";
