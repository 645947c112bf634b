//! The reader: YAML events, read in the settings' layout, into a configuration.
//!
//! It follows the layout as it reads, so it descends only into maps the layout has: a key the
//! layout does not have is refused before its value is read, so recursion is never deeper than
//! the layout's six maps, whatever the text.
//!
//! Errors are refused where they are written, but one is only known at the end: an interface
//! without a key it needs, or whose module has no policy, is refused at its key.

use std::collections::btree_map::Entry;
use std::collections::BTreeMap;

use saphyr_parser::{Event, Parser, ScanError, StrInput};

use super::interfaces::{self, Draft, Field};
use super::limit::Limit;
use super::scalar::kind;
use super::{Expected, Found, Settings, SettingsError, SettingsErrorKind, Unsupported};
use cooperation::{Behavior, Config, Limits, Module, Policy, Sequence, State};

/// The only key of a node's map.
const ROS_PARAMETERS: &str = "ros__parameters";

/// The keys under `ros__parameters`, `cooperation` and `limits`.
const COOPERATION: &[&str] = &["cooperation"];
const SECTIONS: &[&str] = &["policies", "limits", "interfaces"];
const LIMITS: &[&str] = &["ttl_ms", "max_scenes", "retired_capacity", "max_batch"];

/// A place in the text: line and column, both from 1.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
struct Mark {
    line: usize,
    column: usize,
}

impl Mark {
    /// The place `line` (from 1) and `col` (from 0) name, no further than `end`: the parser
    /// places the end of a text without a final line break on the line after it.
    fn at(line: usize, col: usize, end: Self) -> Self {
        let mark = Self {
            line,
            column: col.saturating_add(1),
        };
        if (mark.line, mark.column) > (end.line, end.column) {
            end
        } else {
            mark
        }
    }

    /// Where `text` ends: after its last character, line breaks counted as YAML counts them
    /// (`\r\n`, `\r` or `\n`).
    fn end(text: &str) -> Self {
        let mut end = Self { line: 1, column: 1 };
        let mut chars = text.chars().peekable();
        while let Some(c) = chars.next() {
            if c == '\r' && chars.peek() == Some(&'\n') {
                continue;
            }
            if matches!(c, '\r' | '\n') {
                end = Self {
                    line: end.line.saturating_add(1),
                    column: 1,
                };
            } else {
                end.column = end.column.saturating_add(1);
            }
        }
        end
    }
}

/// Where in the layout a key leads.
#[derive(Clone, PartialEq, Eq, Debug)]
enum Place {
    /// `ros__parameters`: the parameters.
    Parameters,
    /// `cooperation`.
    Cooperation,
    /// `cooperation.policies`: behaviours.
    Policies,
    /// A behaviour: its policy, or its sequences.
    Behavior(String),
    /// A behaviour's sequence: its policy.
    Sequence(String, String),
    /// `cooperation.limits`.
    Limits,
    /// One limit.
    Limit(Limit),
    /// `cooperation.interfaces`: interface names.
    Interfaces,
    /// An interface: its keys.
    Interface(String),
    /// One key of an interface.
    Field(String, Field),
}

impl Place {
    /// What a value here must be.
    const fn expected(&self) -> Expected {
        match self {
            Self::Parameters
            | Self::Cooperation
            | Self::Policies
            | Self::Limits
            | Self::Interfaces
            | Self::Interface(_) => Expected::Map,
            Self::Behavior(_) => Expected::PolicyOrSequences,
            Self::Sequence(..) => Expected::Policy,
            Self::Limit(_) => Expected::Integer,
            Self::Field(_, field) => field.expected(),
        }
    }

    /// The place the key `part` leads to from here.
    fn descend(&self, part: &str) -> Result<Self, SettingsErrorKind> {
        let unknown = |expected| SettingsErrorKind::UnknownKey {
            given: part.to_owned(),
            expected,
        };
        match self {
            Self::Parameters if part == "cooperation" => Ok(Self::Cooperation),
            Self::Parameters => Err(unknown(COOPERATION)),
            Self::Cooperation if part == "policies" => Ok(Self::Policies),
            Self::Cooperation if part == "limits" => Ok(Self::Limits),
            Self::Cooperation if part == "interfaces" => Ok(Self::Interfaces),
            Self::Cooperation => Err(unknown(SECTIONS)),
            Self::Policies => match part.parse::<Behavior>() {
                Ok(_) => Ok(Self::Behavior(part.to_owned())),
                Err(name) => Err(SettingsErrorKind::InvalidBehavior(name)),
            },
            Self::Behavior(behavior) => match part.parse::<Sequence>() {
                Ok(_) => Ok(Self::Sequence(behavior.clone(), part.to_owned())),
                Err(name) => Err(SettingsErrorKind::InvalidSequence(name)),
            },
            Self::Limits => Limit::ALL
                .into_iter()
                .find(|limit| limit.key() == part)
                .map(Self::Limit)
                .ok_or_else(|| unknown(LIMITS)),
            Self::Interfaces if !interfaces::valid_name(part) => {
                Err(SettingsErrorKind::InvalidInterface {
                    given: part.to_owned(),
                })
            }
            Self::Interfaces if interfaces::standard(part) => {
                Err(SettingsErrorKind::StandardInterface {
                    given: part.to_owned(),
                })
            }
            Self::Interfaces => Ok(Self::Interface(part.to_owned())),
            Self::Interface(name) => Field::from_key(part)
                .map(|field| Self::Field(name.clone(), field))
                .ok_or_else(|| unknown(interfaces::KEYS)),
            // A key below a value: the value would be a map.
            Self::Sequence(..) | Self::Limit(_) | Self::Field(..) => {
                Err(SettingsErrorKind::WrongType {
                    expected: self.expected(),
                    found: Found::Map,
                })
            }
        }
    }

    /// Whether an empty map here names no module where one is needed.
    const fn lists_modules(&self) -> bool {
        matches!(self, Self::Policies | Self::Behavior(_))
    }
}

/// The reader's state: the events, the key path so far, and what was read.
pub(super) struct Reader<'t> {
    events: Parser<'t, StrInput<'t>>,
    /// The key path down to where the reader is.
    path: Vec<String>,
    /// The node key, once read.
    node: String,
    /// Every module's policy, and where it was set.
    policies: BTreeMap<Module, (Policy, Mark)>,
    /// The limits so far.
    limits: Limits,
    /// Where each limit was set, by key.
    limits_set: BTreeMap<&'static str, Mark>,
    /// The interfaces, each with where it was first named.
    interfaces: BTreeMap<String, (Draft, Mark)>,
    /// Where each interface's keys were set.
    fields_set: BTreeMap<(String, &'static str), Mark>,
    /// The most the caller allows.
    max: Limits,
    /// Where the text ends.
    end: Mark,
}

type Read<T> = Result<T, SettingsError>;

mod set;

impl<'t> Reader<'t> {
    pub(super) fn new(text: &'t str, max: &Limits) -> Self {
        Self {
            events: Parser::new_from_str(text),
            path: Vec::new(),
            node: String::new(),
            policies: BTreeMap::new(),
            limits: Limits::default(),
            limits_set: BTreeMap::new(),
            interfaces: BTreeMap::new(),
            fields_set: BTreeMap::new(),
            max: *max,
            end: Mark::end(text),
        }
    }

    /// An error at `mark`, at the current key path.
    fn error(&self, mark: Mark, kind: SettingsErrorKind) -> SettingsError {
        SettingsError {
            line: mark.line,
            column: mark.column,
            key: self.path.join("."),
            kind,
        }
    }

    /// The next event. A syntax error is at its own place.
    fn next(&mut self) -> Read<(Event<'t>, Mark)> {
        match self.events.next_event() {
            Some(Ok((event, span))) => {
                let start = span.start;
                Ok((event, Mark::at(start.line(), start.col(), self.end)))
            }
            Some(Err(error)) => Err(self.syntax(&error)),
            // The parser ends every stream with `StreamEnd`, after which nothing is read.
            None => Err(self.error(
                self.end,
                SettingsErrorKind::Syntax {
                    message: "the text ends early".to_owned(),
                },
            )),
        }
    }

    fn syntax(&self, error: &ScanError) -> SettingsError {
        let marker = error.marker();
        let mark = Mark::at(marker.line(), marker.col(), self.end);
        self.error(
            mark,
            SettingsErrorKind::Syntax {
                message: error.info().to_owned(),
            },
        )
    }

    /// The next node's event, refusing anchors, tags and aliases.
    fn node(&mut self) -> Read<(Event<'t>, Mark)> {
        let (event, mark) = self.next()?;
        let (anchor, tagged) = match &event {
            Event::Scalar(_, _, anchor, tag)
            | Event::MappingStart(anchor, tag)
            | Event::SequenceStart(anchor, tag) => (*anchor, tag.is_some()),
            // Never reached: the anchor an alias names was refused before it.
            Event::Alias(_) => {
                return Err(self.error(mark, SettingsErrorKind::Unsupported(Unsupported::Anchor)))
            }
            _ => (0, false),
        };
        if anchor != 0 {
            return Err(self.error(mark, SettingsErrorKind::Unsupported(Unsupported::Anchor)));
        }
        if tagged {
            return Err(self.error(mark, SettingsErrorKind::Unsupported(Unsupported::Tag)));
        }
        Ok((event, mark))
    }

    /// The next key of a map, or `None` at its end. `seen` holds the map's keys so far.
    fn key(&mut self, seen: &mut BTreeMap<String, Mark>) -> Read<Option<(String, Mark)>> {
        let (event, mark) = self.node()?;
        let key = match event {
            Event::MappingEnd => return Ok(None),
            // A key YAML reads as another type (`true`, `null`, `1`) is not a name; an empty
            // one is refused as empty where a name is read.
            Event::Scalar(text, style, ..) => match kind(&text, style) {
                Found::String => text.into_owned(),
                _ if text.is_empty() => String::new(),
                found => {
                    self.path.push(text.into_owned());
                    return Err(self.error(mark, SettingsErrorKind::KeyNotString { found }));
                }
            },
            _ => {
                return Err(self.error(
                    mark,
                    SettingsErrorKind::Unsupported(Unsupported::ComplexKey),
                ))
            }
        };
        match seen.entry(key.clone()) {
            Entry::Occupied(first) => {
                let first_line = first.get().line;
                self.path.push(key);
                Err(self.error(mark, SettingsErrorKind::DuplicateKey { first_line }))
            }
            Entry::Vacant(entry) => {
                entry.insert(mark);
                Ok(Some((key, mark)))
            }
        }
    }

    /// Reads the whole text.
    pub(super) fn read(mut self) -> Read<Settings> {
        // `StreamStart`, then a document or the end.
        self.next()?;
        let (event, mark) = self.next()?;
        if event == Event::StreamEnd {
            return Err(self.error(mark, SettingsErrorKind::NoNode));
        }
        let (event, mark) = self.node()?;
        let parameters = match event {
            Event::MappingStart(..) => self.top(mark)?,
            Event::Scalar(text, style, ..) if kind(&text, style) == Found::Null => {
                return Err(self.error(mark, SettingsErrorKind::NoNode))
            }
            other => return Err(self.wrong_type(mark, Expected::Map, &other)),
        };
        // `DocumentEnd`, then the end: a second document is refused.
        self.next()?;
        let (event, mark) = self.next()?;
        if event != Event::StreamEnd {
            return Err(self.error(
                mark,
                SettingsErrorKind::Unsupported(Unsupported::SecondDocument),
            ));
        }
        self.finish(parameters)
    }

    /// The top-level map, with one node key; returns where its `ros__parameters` key is.
    fn top(&mut self, start: Mark) -> Read<Mark> {
        let mut seen = BTreeMap::new();
        let Some((node, mark)) = self.key(&mut seen)? else {
            return Err(self.error(start, SettingsErrorKind::NoNode));
        };
        self.path.push(node.clone());
        if node == ROS_PARAMETERS {
            return Err(self.error(mark, SettingsErrorKind::NoNodeKey));
        }
        let valid = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '/' | '*');
        if node.is_empty() || !node.chars().all(valid) {
            return Err(self.error(mark, SettingsErrorKind::BadNodeKey));
        }
        self.node = node;
        let parameters = self.node_map(mark)?;
        self.path.clear();
        if let Some((second, mark)) = self.key(&mut seen)? {
            self.path.push(second);
            return Err(self.error(mark, SettingsErrorKind::SecondNode));
        }
        Ok(parameters)
    }

    /// A node's map, holding `ros__parameters` only; returns where that key is.
    fn node_map(&mut self, node: Mark) -> Read<Mark> {
        let (event, mark) = self.node()?;
        if !matches!(event, Event::MappingStart(..)) {
            return Err(self.wrong_type(mark, Expected::Map, &event));
        }
        let mut seen = BTreeMap::new();
        let mut parameters = None;
        while let Some((key, mark)) = self.key(&mut seen)? {
            self.path.push(key.clone());
            if key != ROS_PARAMETERS {
                let kind = SettingsErrorKind::UnknownKey {
                    given: key,
                    expected: &[ROS_PARAMETERS],
                };
                return Err(self.error(mark, kind));
            }
            self.value(&Place::Parameters)?;
            self.path.pop();
            parameters = Some(mark);
        }
        parameters.ok_or_else(|| self.error(node, SettingsErrorKind::NoParameters))
    }

    /// The value at `place`, the key path ending at its key.
    fn value(&mut self, place: &Place) -> Read<()> {
        let (event, mark) = self.node()?;
        match (&event, place) {
            (Event::MappingStart(..), Place::Sequence(..) | Place::Limit(_) | Place::Field(..)) => {
                Err(self.wrong_type(mark, place.expected(), &event))
            }
            (Event::MappingStart(..), Place::Interface(name)) => {
                self.interfaces
                    .entry(name.clone())
                    .or_insert_with(|| (Draft::default(), mark));
                self.map(place, mark)
            }
            (Event::MappingStart(..), _) => self.map(place, mark),
            (Event::Scalar(text, style, ..), Place::Behavior(behavior)) => {
                let policy = self.policy(mark, text, *style, place)?;
                self.set_policy(behavior, None, policy, mark)
            }
            (Event::Scalar(text, style, ..), Place::Sequence(behavior, sequence)) => {
                let policy = self.policy(mark, text, *style, place)?;
                self.set_policy(behavior, Some(sequence), policy, mark)
            }
            (Event::Scalar(text, style, ..), Place::Limit(limit)) => {
                self.set_limit(*limit, mark, text, *style)
            }
            (Event::Scalar(text, style, ..), Place::Field(name, field)) => {
                self.set_field(name, *field, mark, text, *style)
            }
            _ => Err(self.wrong_type(mark, place.expected(), &event)),
        }
    }

    /// A map at `place`, which starts at `start`.
    fn map(&mut self, place: &Place, start: Mark) -> Read<()> {
        let mut seen = BTreeMap::new();
        let depth = self.path.len();
        while let Some((key, mark)) = self.key(&mut seen)? {
            // A dotted key is the nested keys it names, as in ROS 2.
            let mut here = place.clone();
            for part in key.split('.') {
                self.path.push(part.to_owned());
                if part.is_empty() {
                    return Err(self.error(mark, SettingsErrorKind::EmptyName));
                }
                here = here.descend(part).map_err(|kind| self.error(mark, kind))?;
            }
            self.value(&here)?;
            self.path.truncate(depth);
        }
        if seen.is_empty() && place.lists_modules() {
            return Err(self.error(start, SettingsErrorKind::EmptyMap));
        }
        Ok(())
    }

    fn wrong_type(&self, mark: Mark, expected: Expected, event: &Event<'_>) -> SettingsError {
        let found = match event {
            Event::Scalar(text, style, ..) => kind(text, *style),
            Event::SequenceStart(..) => Found::List,
            _ => Found::Map,
        };
        self.error(mark, SettingsErrorKind::WrongType { expected, found })
    }

    /// The configuration, once the text is read; `parameters` is where `ros__parameters` is.
    fn finish(mut self, parameters: Mark) -> Read<Settings> {
        self.path = vec![core::mem::take(&mut self.node), ROS_PARAMETERS.to_owned()];
        if self.policies.is_empty() {
            return Err(self.error(parameters, SettingsErrorKind::NoPolicies));
        }
        let config = Config::new(
            core::mem::take(&mut self.policies)
                .into_iter()
                .map(|(module, (policy, _))| (module, policy)),
        )
        .with_limits(self.limits);
        // Each limit passed on its own; the core sees them together too.
        let last = self
            .limits_set
            .values()
            .max_by_key(|mark| mark.line)
            .copied();
        if let Err(error) = State::new(config.clone()) {
            return Err(self.error(
                last.unwrap_or(parameters),
                SettingsErrorKind::Refused(error),
            ));
        }
        let mut bindings = Vec::with_capacity(self.interfaces.len());
        for (name, (draft, mark)) in core::mem::take(&mut self.interfaces) {
            let at = |reader: &mut Self, kind| {
                reader.path.extend([
                    "cooperation".to_owned(),
                    "interfaces".to_owned(),
                    name.clone(),
                ]);
                reader.error(mark, kind)
            };
            let binding = match draft.binding(&name) {
                Ok(binding) => binding,
                Err(field) => {
                    let field = field.key();
                    return Err(at(&mut self, SettingsErrorKind::MissingField { field }));
                }
            };
            if let Some(module) = binding
                .modules()
                .find(|module| !config.policies.contains_key(module))
            {
                let module = module.to_string();
                return Err(at(&mut self, SettingsErrorKind::Unbound { module }));
            }
            bindings.push(binding);
        }
        Ok(Settings {
            config,
            interfaces: bindings,
        })
    }
}
