//! The reader's values: a policy, a limit, an interface's key, each set where it is written.

use std::collections::btree_map::Entry;

use saphyr_parser::ScalarStyle;

use super::{Mark, Place, Read, Reader};
use crate::rtc::ModuleType;
use crate::settings::interfaces::{self, Draft, Field};
use crate::settings::limit::Limit;
use crate::settings::scalar::{kind, unsigned_integer};
use crate::settings::{Expected, Found, SettingsErrorKind};
use cooperation::{Behavior, Config, Limits, Module, Policy, Sequence, State};

impl Reader<'_> {
    /// A policy, from a string, for a key at `place`.
    pub(super) fn policy(
        &self,
        mark: Mark,
        text: &str,
        style: ScalarStyle,
        place: &Place,
    ) -> Read<Policy> {
        match kind(text, style) {
            Found::String => Policy::ALL
                .into_iter()
                .find(|policy| policy.as_str() == text)
                .ok_or_else(|| {
                    self.error(
                        mark,
                        SettingsErrorKind::UnknownPolicy {
                            given: text.to_owned(),
                        },
                    )
                }),
            found => Err(self.error(
                mark,
                SettingsErrorKind::WrongType {
                    expected: place.expected(),
                    found,
                },
            )),
        }
    }

    /// Sets a module's policy: a behaviour's alone, or one of its sequences'.
    pub(super) fn set_policy(
        &mut self,
        behavior: &str,
        sequence: Option<&str>,
        policy: Policy,
        mark: Mark,
    ) -> Read<()> {
        // The keys were parsed when read, and are parsed again here, as a place holds strings.
        let behavior = behavior
            .parse::<Behavior>()
            .map_err(|name| self.error(mark, SettingsErrorKind::InvalidBehavior(name)))?;
        let module = match sequence {
            None => Module::new(behavior),
            Some(sequence) => {
                let sequence = sequence
                    .parse::<Sequence>()
                    .map_err(|name| self.error(mark, SettingsErrorKind::InvalidSequence(name)))?;
                Module::with_sequence(behavior, sequence)
            }
        };
        match self.policies.entry(module) {
            Entry::Occupied(first) => {
                let first_line = first.get().1.line;
                Err(self.error(mark, SettingsErrorKind::Twice { first_line }))
            }
            Entry::Vacant(entry) => {
                entry.insert((policy, mark));
                Ok(())
            }
        }
    }

    pub(super) fn set_limit(
        &mut self,
        limit: Limit,
        mark: Mark,
        text: &str,
        style: ScalarStyle,
    ) -> Read<()> {
        let found = kind(text, style);
        if found != Found::Integer {
            let expected = Expected::Integer;
            return Err(self.error(mark, SettingsErrorKind::WrongType { expected, found }));
        }
        let out_of_range = || SettingsErrorKind::OutOfRange {
            given: text.to_owned(),
            max: limit.type_max(),
        };
        let value = unsigned_integer(text).ok_or_else(|| self.error(mark, out_of_range()))?;
        let limits = limit
            .set(self.limits, value)
            .ok_or_else(|| self.error(mark, out_of_range()))?;
        if let Some(first) = self.limits_set.get(limit.key()) {
            let first_line = first.line;
            return Err(self.error(mark, SettingsErrorKind::Twice { first_line }));
        }
        let max = limit.get(&self.max);
        if value > max {
            let kind = SettingsErrorKind::AboveMaximum { given: value, max };
            return Err(self.error(mark, kind));
        }
        // What the core refuses, found where the limit is written: this limit with the
        // defaults for the others.
        let alone = limit.set(Limits::default(), value).unwrap_or_default();
        State::new(Config::new([]).with_limits(alone))
            .map_err(|error| self.error(mark, SettingsErrorKind::Refused(error)))?;
        self.limits_set.insert(limit.key(), mark);
        self.limits = limits;
        Ok(())
    }

    /// Sets one key of interface `name`.
    pub(super) fn set_field(
        &mut self,
        name: &str,
        field: Field,
        mark: Mark,
        text: &str,
        style: ScalarStyle,
    ) -> Read<()> {
        let found = kind(text, style);
        let wanted = if field == Field::ModuleType {
            Found::Integer
        } else {
            Found::String
        };
        if found != wanted {
            let expected = field.expected();
            return Err(self.error(mark, SettingsErrorKind::WrongType { expected, found }));
        }
        let key = (name.to_owned(), field.key());
        if let Some(first) = self.fields_set.get(&key) {
            let first_line = first.line;
            return Err(self.error(mark, SettingsErrorKind::Twice { first_line }));
        }
        let mut draft = self
            .interfaces
            .get(name)
            .map_or_else(Draft::default, |(draft, _)| draft.clone());
        match field {
            Field::Behavior => {
                let behavior = text
                    .parse::<Behavior>()
                    .map_err(|name| self.error(mark, SettingsErrorKind::InvalidBehavior(name)))?;
                draft.behavior = Some(behavior);
            }
            Field::Sequence => {
                let sequence = text
                    .parse::<Sequence>()
                    .map_err(|name| self.error(mark, SettingsErrorKind::InvalidSequence(name)))?;
                draft.sequence = Some(sequence);
            }
            Field::Kind => {
                let given = text.to_owned();
                let kind = interfaces::kind(text)
                    .ok_or_else(|| self.error(mark, SettingsErrorKind::UnknownKind { given }))?;
                draft.kind = Some(kind);
            }
            Field::ModuleType => {
                let module_type = unsigned_integer(text)
                    .and_then(|value| u8::try_from(value).ok())
                    .and_then(ModuleType::from_value)
                    .ok_or_else(|| {
                        let given = text.to_owned();
                        self.error(mark, SettingsErrorKind::UnknownModuleType { given })
                    })?;
                draft.module_type = Some(module_type);
            }
        }
        debug_assert!(draft.has(field));
        self.fields_set.insert(key, mark);
        let first = self.interfaces.get(name).map_or(mark, |(_, first)| *first);
        self.interfaces.insert(name.to_owned(), (draft, first));
        Ok(())
    }
}
