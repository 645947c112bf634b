//! What can be wrong with a settings file: every error names its line, column and key.

use core::fmt;

use cooperation::{ConfigError, InvalidName};

/// A settings file that cannot be read as a configuration. Reading stops at the first one.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct SettingsError {
    /// The line, from 1.
    pub line: usize,
    /// The column, from 1, counted in characters.
    pub column: usize,
    /// The key the error is at, from the node key down, joined by dots, as ROS 2 names a
    /// parameter: `/**.ros__parameters.cooperation.policies.lane-change`. Empty when the error
    /// is before the first key.
    pub key: String,
    /// What is wrong.
    pub kind: SettingsErrorKind,
}

impl fmt::Display for SettingsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}, column {}: ", self.line, self.column)?;
        if !self.key.is_empty() {
            write!(f, "{}: ", self.key)?;
        }
        write!(f, "{}", self.kind)
    }
}

impl std::error::Error for SettingsError {}

/// What is wrong with a settings file.
#[derive(Clone, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum SettingsErrorKind {
    /// The text is not YAML.
    Syntax {
        /// The YAML parser's explanation.
        message: String,
    },
    /// YAML that a settings file does not use.
    Unsupported(Unsupported),
    /// The file sets nothing: it is empty, or its top level is null or an empty map.
    NoNode,
    /// The top-level key is `ros__parameters`: the node key above it is missing.
    NoNodeKey,
    /// The top-level key is not a node key: `/**`, or a node's name of ASCII letters, digits,
    /// `_`, `/` and `*`.
    BadNodeKey,
    /// A second top-level key: a settings file configures one node.
    SecondNode,
    /// The node's map has no `ros__parameters`.
    NoParameters,
    /// A value of the wrong type.
    WrongType {
        /// What the key takes.
        expected: Expected,
        /// What was given.
        found: Found,
    },
    /// The same key twice in one map.
    DuplicateKey {
        /// The line of the first.
        first_line: usize,
    },
    /// One parameter set twice by two spellings of its key (`avoidance.change` beside
    /// `avoidance:` → `change:`): a module's policy or a limit given twice.
    Twice {
        /// The line of the first.
        first_line: usize,
    },
    /// An empty key, or an empty part of a dotted key (`policies..lane-change`, `""`).
    EmptyName,
    /// A character YAML does not allow in a text: a control character other than tab and the
    /// line breaks (NUL among them), DEL, U+FFFE or U+FFFF.
    Unprintable {
        /// The character.
        character: char,
    },
    /// A key on one line longer than YAML allows (1,024 characters).
    KeyTooLong {
        /// Its length in characters.
        chars: usize,
    },
    /// A key that YAML reads as another type than a string (`true`, `null`, `1`, `2.5`): a
    /// YAML reader other than ROS 2's would not see the name written.
    KeyNotString {
        /// What YAML reads it as.
        found: Found,
    },
    /// A key the settings do not have.
    UnknownKey {
        /// The key as given.
        given: String,
        /// The keys accepted there.
        expected: &'static [&'static str],
    },
    /// A key under `policies` that is no behaviour: neither a built-in name nor a valid
    /// user-extension name ([`cooperation::Behavior`]'s `FromStr`).
    InvalidBehavior(InvalidName),
    /// A key under a behaviour that is no sequence ([`cooperation::Sequence`]'s `FromStr`).
    InvalidSequence(InvalidName),
    /// A policy that is neither `optional` nor `required`.
    UnknownPolicy {
        /// The string given.
        given: String,
    },
    /// An empty map where modules are listed: under `policies`, or under a behaviour.
    EmptyMap,
    /// No module has a policy: the file has no `cooperation.policies`.
    NoPolicies,
    /// A whole number that the limit's type cannot hold: negative, or too large.
    OutOfRange {
        /// The number as written.
        given: String,
        /// The largest the limit's type holds.
        max: u64,
    },
    /// A limit above the most the caller allows ([`parse_within`](super::parse_within)).
    AboveMaximum {
        /// The limit given.
        given: u64,
        /// The most allowed.
        max: u64,
    },
    /// A limit the core refuses: [`State::new`](cooperation::State::new) would fail with this.
    Refused(ConfigError),
    /// A key under `interfaces` that cannot be an interface's name.
    InvalidInterface {
        /// The name given.
        given: String,
    },
    /// A key under `interfaces` that names a standard interface, which is bound already.
    StandardInterface {
        /// The name given.
        given: String,
    },
    /// An interface's `kind` that is none of `velocity`, `steering`, `steering-left`,
    /// `steering-right`.
    UnknownKind {
        /// The string given.
        given: String,
    },
    /// An interface's `module_type` that is no `tier4_rtc_msgs/Module` constant.
    UnknownModuleType {
        /// The number as written.
        given: String,
    },
    /// An interface without a key it needs (`behavior`, `kind`).
    MissingField {
        /// The key.
        field: &'static str,
    },
    /// An interface whose module has no policy in the file: its scenes could not register.
    Unbound {
        /// The module, as the AD API names it (`behavior` or `behavior/sequence`).
        module: String,
    },
}

impl fmt::Display for SettingsErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Syntax { message } => write!(f, "not YAML: {message}"),
            Self::Unsupported(what) => write!(f, "{what}"),
            Self::NoNode => f.write_str(
                "the file sets nothing: it starts with a node key such as `/**`, then \
                 `ros__parameters`",
            ),
            Self::NoNodeKey => f.write_str(
                "`ros__parameters` sits under a node key: write `/**:` (or the node's name) \
                 above it",
            ),
            Self::BadNodeKey => f.write_str(
                "not a node key: write `/**`, or a node's name of ASCII letters, digits, `_`, \
                 `/` and `*`",
            ),
            Self::SecondNode => {
                f.write_str("a second node key: a settings file configures one node")
            }
            Self::NoParameters => f.write_str("the node has no `ros__parameters`"),
            Self::WrongType { expected, found } => write!(f, "expected {expected}, found {found}"),
            Self::DuplicateKey { first_line } => {
                write!(
                    f,
                    "the key is given twice in one map (first on line {first_line})"
                )
            }
            Self::Twice { first_line } => write!(
                f,
                "set twice, by two spellings of the key (first on line {first_line})"
            ),
            Self::EmptyName => f.write_str("an empty key, or an empty part of a dotted key"),
            Self::Unprintable { character } => write!(
                f,
                "U+{:04X} is a character YAML does not allow in a file",
                u32::from(*character)
            ),
            Self::KeyTooLong { chars } => write!(
                f,
                "a key of {chars} characters: YAML allows a key on one line at most {}",
                super::text::MAX_KEY_CHARS
            ),
            Self::KeyNotString { found } => write!(
                f,
                "the key is {found} in YAML, not a name; quote it if the name is meant"
            ),
            Self::UnknownKey { given, expected } => {
                write!(f, "unknown key {given:?}")?;
                match expected {
                    [] => Ok(()),
                    [only] => write!(f, "; expected `{only}`"),
                    keys => {
                        f.write_str("; expected one of ")?;
                        for (index, key) in keys.iter().enumerate() {
                            if index > 0 {
                                f.write_str(", ")?;
                            }
                            write!(f, "`{key}`")?;
                        }
                        Ok(())
                    }
                }
            }
            Self::InvalidBehavior(name) | Self::InvalidSequence(name) => write!(f, "{name}"),
            Self::UnknownPolicy { given } => {
                write!(
                    f,
                    "unknown policy {given:?}; expected `optional` or `required`"
                )
            }
            Self::EmptyMap => f.write_str("an empty map names no module"),
            Self::NoPolicies => f.write_str(
                "no module has a policy: `cooperation.policies` names every module that \
                 supports cooperation",
            ),
            Self::OutOfRange { given, max } => {
                write!(f, "{given} is not a whole number from 0 to {max}")
            }
            Self::AboveMaximum { given, max } => {
                write!(f, "{given} is more than the {max} allowed here")
            }
            Self::Refused(error) => write!(f, "{error}"),
            Self::InvalidInterface { given } => write!(
                f,
                "{given:?} is not an interface name: an ASCII letter, then ASCII letters, digits \
                 and `_`, at most {} bytes",
                super::interfaces::MAX_NAME
            ),
            Self::StandardInterface { given } => write!(
                f,
                "{given:?} is a standard interface, bound already; `interfaces` adds others"
            ),
            Self::UnknownKind { given } => {
                write!(f, "unknown kind {given:?}; expected one of ")?;
                for (index, kind) in super::interfaces::KINDS.iter().enumerate() {
                    if index > 0 {
                        f.write_str(", ")?;
                    }
                    write!(f, "`{kind}`")?;
                }
                Ok(())
            }
            Self::UnknownModuleType { given } => write!(
                f,
                "{given} is no `tier4_rtc_msgs/Module` constant (0, NONE, to 19, ROUNDABOUT)"
            ),
            Self::MissingField { field } => write!(f, "the interface has no `{field}`"),
            Self::Unbound { module } => write!(
                f,
                "module {module:?} has no policy in `cooperation.policies`: the interface's \
                 scenes could not register"
            ),
        }
    }
}

/// YAML that a settings file does not use.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum Unsupported {
    /// An anchor (`&name`). An alias (`*name`) can only refer to an anchor before it, so the
    /// anchor is refused first (an alias of no anchor is a syntax error).
    Anchor,
    /// A tag (`!!str`, `!name`).
    Tag,
    /// A key that is a map or a list.
    ComplexKey,
    /// A second document (`---` after a first).
    SecondDocument,
}

impl fmt::Display for Unsupported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Anchor => {
                "anchors (`&name`) and aliases (`*name`) are not read in a settings file"
            }
            Self::Tag => "tags (`!!str`, `!name`) are not read in a settings file",
            Self::ComplexKey => "a key is a string, not a map or a list",
            Self::SecondDocument => "a settings file is one YAML document",
        })
    }
}

/// What a key takes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum Expected {
    /// A map of keys.
    Map,
    /// A policy, `optional` or `required`.
    Policy,
    /// A policy (the behaviour's, sequence empty), or a map from sequences to policies.
    PolicyOrSequences,
    /// A whole number.
    Integer,
    /// A behaviour string.
    Behavior,
    /// A sequence string.
    Sequence,
    /// A kind: `velocity`, `steering`, `steering-left` or `steering-right`.
    Kind,
}

impl fmt::Display for Expected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Map => "a map",
            Self::Policy => "a policy (`optional` or `required`)",
            Self::PolicyOrSequences => {
                "a policy (`optional` or `required`), or a map from sequences to policies"
            }
            Self::Integer => "a whole number",
            Self::Behavior => "a behaviour",
            Self::Sequence => "a sequence",
            Self::Kind => "a kind (`velocity`, `steering`, `steering-left` or `steering-right`)",
        })
    }
}

/// What a value is, as YAML 1.2's core schema reads it (a quoted scalar is a string).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum Found {
    /// `~`, `null` or nothing.
    Null,
    /// `true` or `false`.
    Bool,
    /// A whole number.
    Integer,
    /// A floating-point number.
    Float,
    /// A string.
    String,
    /// A list.
    List,
    /// A map.
    Map,
}

impl fmt::Display for Found {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Null => "null",
            Self::Bool => "a boolean",
            Self::Integer => "a whole number",
            Self::Float => "a floating-point number",
            Self::String => "a string",
            Self::List => "a list",
            Self::Map => "a map",
        })
    }
}
