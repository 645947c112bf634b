// The module's documentation is `docs/settings.md`, attached where the module is declared.

mod error;
mod interfaces;
mod limit;
mod reader;
mod render;
mod scalar;
mod text;

pub use error::{Expected, Found, SettingsError, SettingsErrorKind, Unsupported};

use cooperation::{Config, Limits};

use crate::rtc::Binding;

/// What a settings file configures: the core, and the RTC interfaces it adds to the standard
/// ones (`cooperation.interfaces`, in name order).
#[derive(Clone, PartialEq, Debug)]
pub struct Settings {
    /// The core's configuration: the modules' policies and the limits.
    pub config: Config,
    /// The interfaces besides [`Binding::standard`], each binding one module of `config`.
    pub interfaces: Vec<Binding>,
}

/// The largest limits [`parse`] accepts: each as large as its type holds. [`parse_within`]
/// takes smaller ones.
pub const NO_MAXIMUM: Limits = Limits {
    ttl_ms: u64::MAX,
    max_scenes: usize::MAX,
    retired_capacity: usize::MAX,
    max_batch: usize::MAX,
};

/// The repository's settings file (`config/cooperation.param.yaml`), built in: the settings of a
/// node that is given no file.
pub const BUILT_IN: &str = include_str!("../config/cooperation.param.yaml");

/// The settings file at `path`, or [`BUILT_IN`] for `None`, read and parsed as [`read`] does.
///
/// # Errors
/// A message naming the file (or "the built-in settings") and why it could not be read or
/// parsed.
pub fn load(path: Option<&std::path::Path>) -> Result<Settings, String> {
    let (text, source) = match path {
        Some(path) => (
            std::fs::read_to_string(path)
                .map_err(|error| format!("{}: {error}", path.display()))?,
            path.display().to_string(),
        ),
        None => (BUILT_IN.to_owned(), "the built-in settings".to_owned()),
    };
    read(&text).map_err(|error| format!("{source}: {error}"))
}

/// Reads a settings file's text into a configuration that [`State::new`](cooperation::State::new)
/// accepts. The file's `interfaces` are read and checked too; [`read`] returns them.
///
/// # Errors
/// The first thing wrong, as a [`SettingsError`] naming its line, column and key.
pub fn parse(text: &str) -> Result<Config, SettingsError> {
    parse_within(text, &NO_MAXIMUM)
}

/// Reads a settings file's text: the configuration, as [`parse`] does, and the RTC interfaces
/// it adds.
///
/// # Errors
/// As [`parse`].
pub fn read(text: &str) -> Result<Settings, SettingsError> {
    read_within(text, &NO_MAXIMUM)
}

/// [`parse`], refusing any limit above the same limit of `max` (with
/// [`SettingsErrorKind::AboveMaximum`]): for a program that bounds its memory more tightly
/// than the core does.
///
/// # Errors
/// As [`parse`], and a limit above `max`'s.
pub fn parse_within(text: &str, max: &Limits) -> Result<Config, SettingsError> {
    read_within(text, max).map(|settings| settings.config)
}

/// [`read`], refusing any limit above `max`'s, as [`parse_within`] does.
fn read_within(text: &str, max: &Limits) -> Result<Settings, SettingsError> {
    // A file may start with a byte-order mark.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some((at, character)) = text::unprintable(text) {
        return Err(SettingsError {
            line: at.line,
            column: at.column,
            key: String::new(),
            kind: SettingsErrorKind::Unprintable { character },
        });
    }
    reader::Reader::new(text, max).read().map_err(|error| {
        // The parser reads a key too long for one line as a value, or stops after it: the
        // key, at or before where the error is, is the problem to name.
        let misread = matches!(
            error.kind,
            SettingsErrorKind::Syntax { .. } | SettingsErrorKind::WrongType { .. }
        );
        match text::long_key(text) {
            Some((at, chars)) if misread && at.line <= error.line => SettingsError {
                line: at.line,
                column: at.column,
                kind: SettingsErrorKind::KeyTooLong { chars },
                ..error
            },
            _ => error,
        }
    })
}

/// Writes `config` as a settings file that [`parse`] reads back as `config`, when `config`
/// has at least one module and limits `State::new` accepts. The node key is `/**` and every
/// limit is written out.
#[must_use]
pub fn to_yaml(config: &Config) -> String {
    render::to_yaml(config)
}
