//! `cooperation.interfaces`: RTC interfaces besides the standard ones, for planning modules
//! whose interface names the standard bindings do not know (`dynamic_obstacle_avoidance`,
//! `sampling_planner`, a plugin of one's own). Each binds one module of the file.

use cooperation::{Behavior, Direction, Module, Sequence};

use super::Expected;
use crate::rtc::{Binding, Kind, ModuleType};

/// The keys of an interface's map.
pub(super) const KEYS: &[&str] = &["behavior", "sequence", "kind", "module_type"];

/// The values of `kind`.
pub(super) const KINDS: &[&str] = &["velocity", "steering", "steering-left", "steering-right"];

/// The longest interface name read, in bytes.
pub(super) const MAX_NAME: usize = 128;

/// A key of an interface's map.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Field {
    /// The behaviour its scenes belong to.
    Behavior,
    /// Their sequence (the behaviour alone unless given).
    Sequence,
    /// How they are reported: `velocity`, or `steering` with its direction.
    Kind,
    /// The `Module.type` its statuses carry (`NONE`, 0, unless given: what upstream reports for
    /// an interface name it does not know).
    ModuleType,
}

impl Field {
    /// The field named `key`.
    pub(super) fn from_key(key: &str) -> Option<Self> {
        match key {
            "behavior" => Some(Self::Behavior),
            "sequence" => Some(Self::Sequence),
            "kind" => Some(Self::Kind),
            "module_type" => Some(Self::ModuleType),
            _ => None,
        }
    }

    /// Its key.
    pub(super) const fn key(self) -> &'static str {
        match self {
            Self::Behavior => "behavior",
            Self::Sequence => "sequence",
            Self::Kind => "kind",
            Self::ModuleType => "module_type",
        }
    }

    /// What its value must be.
    pub(super) const fn expected(self) -> Expected {
        match self {
            Self::Behavior => Expected::Behavior,
            Self::Sequence => Expected::Sequence,
            Self::Kind => Expected::Kind,
            Self::ModuleType => Expected::Integer,
        }
    }
}

/// Whether `name` can be an interface's name, the last element of its topics and services: an
/// ASCII letter, then ASCII letters, digits and `_`, at most [`MAX_NAME`] bytes.
pub(super) fn valid_name(name: &str) -> bool {
    name.len() <= MAX_NAME
        && name.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Whether a standard binding has this name.
pub(super) fn standard(name: &str) -> bool {
    Binding::standard()
        .iter()
        .any(|binding| binding.name == name)
}

/// The kind `text` names.
pub(super) fn kind(text: &str) -> Option<Kind> {
    match text {
        "velocity" => Some(Kind::Velocity),
        "steering" => Some(Kind::Steering(Direction::Unknown)),
        "steering-left" => Some(Kind::Steering(Direction::Left)),
        "steering-right" => Some(Kind::Steering(Direction::Right)),
        _ => None,
    }
}

/// One interface, as read so far.
#[derive(Clone, Default, Debug)]
pub(super) struct Draft {
    pub(super) behavior: Option<Behavior>,
    pub(super) sequence: Option<Sequence>,
    pub(super) kind: Option<Kind>,
    pub(super) module_type: Option<ModuleType>,
}

impl Draft {
    /// Whether `field` was set.
    pub(super) const fn has(&self, field: Field) -> bool {
        match field {
            Field::Behavior => self.behavior.is_some(),
            Field::Sequence => self.sequence.is_some(),
            Field::Kind => self.kind.is_some(),
            Field::ModuleType => self.module_type.is_some(),
        }
    }

    /// The binding named `name`, or the first field it needs and lacks.
    pub(super) fn binding(&self, name: &str) -> Result<Binding, Field> {
        let behavior = self.behavior.ok_or(Field::Behavior)?;
        let kind = self.kind.ok_or(Field::Kind)?;
        let module = Module::with_sequence(behavior, self.sequence.unwrap_or(Sequence::Empty));
        Ok(Binding::new(
            name,
            self.module_type.unwrap_or(ModuleType::None),
            module,
            kind,
        ))
    }
}
