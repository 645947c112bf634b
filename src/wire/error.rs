//! What can be wrong with a message, and where.

use core::fmt;

/// One step of a [`FieldPath`]: a field by name, or a list entry by position.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
pub enum PathSegment {
    /// A field, by its name in the message definition.
    Field(String),
    /// An entry of a list, counted from 0.
    Index(usize),
}

/// Where in a message a value sits, outermost first: `commands[2].cooperator.decision`.
///
/// Paths are relative to the message that was read or converted: converting a
/// [`CooperationCommand`](super::CooperationCommand) names `cooperator.decision`, converting
/// the request that holds it names `commands[2].cooperator.decision`.
#[derive(Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct FieldPath(Vec<PathSegment>);

impl FieldPath {
    /// The path of the message itself.
    #[must_use]
    pub const fn root() -> Self {
        Self(Vec::new())
    }

    /// The path of one field of the message.
    #[must_use]
    pub fn field(name: &str) -> Self {
        Self(vec![PathSegment::Field(name.to_owned())])
    }

    /// The steps, outermost first.
    #[must_use]
    pub fn segments(&self) -> &[PathSegment] {
        &self.0
    }

    /// Whether this is the path of the message itself.
    #[must_use]
    pub fn is_root(&self) -> bool {
        self.0.is_empty()
    }

    fn prepend(&mut self, segment: PathSegment) {
        self.0.insert(0, segment);
    }
}

impl FromIterator<PathSegment> for FieldPath {
    fn from_iter<I: IntoIterator<Item = PathSegment>>(segments: I) -> Self {
        Self(segments.into_iter().collect())
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (n, segment) in self.0.iter().enumerate() {
            match segment {
                PathSegment::Field(name) => {
                    if n > 0 {
                        f.write_str(".")?;
                    }
                    // A field name can come from the input (an unknown field): keep it short.
                    match name.char_indices().nth(QUOTED) {
                        None => f.write_str(name)?,
                        Some((end, _)) => write!(f, "{}…", name.get(..end).unwrap_or_default())?,
                    }
                }
                PathSegment::Index(index) => write!(f, "[{index}]")?,
            }
        }
        Ok(())
    }
}

impl From<&serde_path_to_error::Path> for FieldPath {
    fn from(path: &serde_path_to_error::Path) -> Self {
        use serde_path_to_error::Segment;
        Self(
            path.iter()
                .map(|segment| match segment {
                    Segment::Seq { index } => PathSegment::Index(*index),
                    Segment::Map { key } => PathSegment::Field(key.clone()),
                    Segment::Enum { variant } => PathSegment::Field(variant.clone()),
                    // Not produced by this module's types; kept visible rather than dropped.
                    Segment::Unknown => PathSegment::Field("?".to_owned()),
                })
                .collect(),
        )
    }
}

/// Why a message cannot be read or converted into the core's types. Each variant names the
/// field at fault; [`Display`](fmt::Display) writes `path: explanation`.
///
/// Rules of the cooperation state machine (an unknown scene, a module without a policy, the
/// same scene twice in a batch, a batch over the limit) are not checked here: the core checks
/// them, and the service handlers turn its [`Rejection`](crate::Rejection) into the response.
#[derive(Clone, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum Malformed {
    /// The bytes are not JSON: bad syntax, or the text ends early.
    NotJson {
        /// Where the reader was.
        path: FieldPath,
        /// The JSON reader's explanation, with line and column.
        detail: String,
    },
    /// The JSON does not have the message's shape: a value of the wrong type, a field the
    /// message does not have or has once only, a number out of its field's range, a UUID
    /// string that is not base64.
    Shape {
        /// The field at fault.
        path: FieldPath,
        /// The JSON reader's explanation, with line and column.
        detail: String,
    },
    /// A constant field holds a number its message defines no constant for.
    UndefinedConstant {
        /// The field.
        path: FieldPath,
        /// The family of constants, e.g. `CooperationDecision` or `SteeringFactor status`.
        constants: &'static str,
        /// The number given.
        value: u16,
    },
    /// A constant field holds a defined constant that this field does not take: `UNKNOWN`,
    /// or an operator-only decision where a module decision belongs.
    UnacceptedConstant {
        /// The field.
        path: FieldPath,
        /// The constant's name, e.g. `CooperationDecision.UNKNOWN`.
        constant: &'static str,
        /// Its number.
        value: u16,
        /// The constants the field takes.
        expected: &'static str,
    },
    /// A UUID whose byte array is not 16 long.
    UuidLength {
        /// The byte array.
        path: FieldPath,
        /// Its length.
        len: usize,
    },
    /// A behaviour string that names no `PlanningBehavior` value (the empty `UNKNOWN`
    /// included).
    UnknownBehavior {
        /// The field.
        path: FieldPath,
        /// The string given.
        given: String,
    },
    /// A sequence string that is neither empty nor a `PlanningSequence` value.
    UnknownSequence {
        /// The field.
        path: FieldPath,
        /// The string given.
        given: String,
    },
    /// A factor's `cooperation` list has more than its one allowed entry.
    TooManyCooperation {
        /// The list.
        path: FieldPath,
        /// Its length.
        len: usize,
    },
    /// A factor without a cooperation status: the core's factors are its scenes, and every
    /// scene has one.
    NoCooperation {
        /// The list.
        path: FieldPath,
    },
    /// Factor poses in another frame than `map`, the frame of the core's poses.
    Frame {
        /// The header's `frame_id`.
        path: FieldPath,
        /// The frame given.
        given: String,
    },
}

impl Malformed {
    /// Where the fault is.
    #[must_use]
    pub const fn path(&self) -> &FieldPath {
        match self {
            Self::NotJson { path, .. }
            | Self::Shape { path, .. }
            | Self::UndefinedConstant { path, .. }
            | Self::UnacceptedConstant { path, .. }
            | Self::UuidLength { path, .. }
            | Self::UnknownBehavior { path, .. }
            | Self::UnknownSequence { path, .. }
            | Self::TooManyCooperation { path, .. }
            | Self::NoCooperation { path }
            | Self::Frame { path, .. } => path,
        }
    }

    fn path_mut(&mut self) -> &mut FieldPath {
        match self {
            Self::NotJson { path, .. }
            | Self::Shape { path, .. }
            | Self::UndefinedConstant { path, .. }
            | Self::UnacceptedConstant { path, .. }
            | Self::UuidLength { path, .. }
            | Self::UnknownBehavior { path, .. }
            | Self::UnknownSequence { path, .. }
            | Self::TooManyCooperation { path, .. }
            | Self::NoCooperation { path }
            | Self::Frame { path, .. } => path,
        }
    }

    /// The same fault, seen from the message that holds the faulty one in field `name`.
    #[must_use]
    pub(super) fn in_field(mut self, name: &str) -> Self {
        self.path_mut().prepend(PathSegment::Field(name.to_owned()));
        self
    }

    /// The same fault, seen from the list that holds the faulty message at `index`.
    #[must_use]
    pub(super) fn at_index(mut self, index: usize) -> Self {
        self.path_mut().prepend(PathSegment::Index(index));
        self
    }

    /// The AD API answer to a request with this fault: `success = false`,
    /// `code = PARAMETER_ERROR`, and this explanation as the message.
    #[must_use]
    pub fn to_status(&self) -> super::ResponseStatus {
        super::ResponseStatus {
            success: false,
            code: super::ResponseStatus::PARAMETER_ERROR,
            message: self.to_string(),
        }
    }
}

/// At most this many characters of a string from the input are quoted in a message.
const QUOTED: usize = 64;
/// A reader's explanation longer than this many characters is shortened in the middle.
const EXPLAINED: usize = 240;

/// A string from the input, quoted, and cut short if long: messages stay small whatever
/// arrives.
struct Quoted<'a>(&'a str);

impl fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.char_indices().nth(QUOTED) {
            None => write!(f, "{:?}", self.0),
            Some((end, _)) => write!(
                f,
                "{:?}… ({} bytes)",
                self.0.get(..end).unwrap_or_default(),
                self.0.len()
            ),
        }
    }
}

/// A reader's explanation, its middle left out if long (it may quote the input); the end,
/// which says where in the text the fault is, is kept.
struct Explained<'a>(&'a str);

impl fmt::Display for Explained<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = self.0;
        let chars = text.chars().count();
        if chars <= EXPLAINED {
            return f.write_str(text);
        }
        let head = EXPLAINED * 2 / 3;
        let tail = EXPLAINED - head;
        let offset = |n: usize| text.char_indices().nth(n).map_or(text.len(), |(at, _)| at);
        let start = text.get(..offset(head)).unwrap_or_default();
        let end = text.get(offset(chars - tail)..).unwrap_or_default();
        write!(f, "{start} … {end}")
    }
}

impl fmt::Display for Malformed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path();
        if !path.is_root() {
            write!(f, "{path}: ")?;
        }
        match self {
            Self::NotJson { detail, .. } => write!(f, "not JSON: {}", Explained(detail)),
            Self::Shape { detail, .. } => write!(f, "{}", Explained(detail)),
            Self::UndefinedConstant {
                constants, value, ..
            } => write!(f, "{value} is not a {constants} constant"),
            Self::UnacceptedConstant {
                constant,
                value,
                expected,
                ..
            } => write!(
                f,
                "{constant} ({value}) is not accepted here; expected {expected}"
            ),
            Self::UuidLength { len, .. } => {
                write!(f, "a UUID has 16 bytes, not {len}")
            }
            Self::UnknownBehavior { given, .. } => {
                write!(f, "{} is not a PlanningBehavior value", Quoted(given))
            }
            Self::UnknownSequence { given, .. } => write!(
                f,
                "{} is not a PlanningSequence value or the empty string",
                Quoted(given)
            ),
            Self::TooManyCooperation { len, .. } => {
                write!(f, "{len} entries; a factor has at most 1")
            }
            Self::NoCooperation { .. } => {
                f.write_str("empty; a scene's factor carries the scene's cooperation status")
            }
            Self::Frame { given, .. } => {
                write!(
                    f,
                    "{}; factor poses are in the \"map\" frame",
                    Quoted(given)
                )
            }
        }
    }
}

impl std::error::Error for Malformed {}
