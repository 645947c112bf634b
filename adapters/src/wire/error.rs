//! What can be wrong with a message, and where.

use core::fmt;

use serde::de::value;
use serde::de::{
    DeserializeOwned, DeserializeSeed, Deserializer, Error as _, IntoDeserializer, MapAccess,
    SeqAccess, Visitor,
};
use serde_path_to_error::Segment;

use crate::path::{escaped, QUOTED};
use crate::path::{FieldPath, PathSegment};

impl From<&serde_path_to_error::Path> for FieldPath {
    /// The reader's path as it is: a list entry by position, a field by name.
    fn from(path: &serde_path_to_error::Path) -> Self {
        path.iter().map(plain).collect()
    }
}

/// One step of the reader's path as it is.
fn plain(segment: &Segment) -> PathSegment {
    match segment {
        Segment::Seq { index } => PathSegment::Index(*index),
        Segment::Map { key } => PathSegment::Field(key.clone()),
        Segment::Enum { variant } => PathSegment::Field(variant.clone()),
        // Not produced by this module's types; kept visible rather than dropped.
        Segment::Unknown => PathSegment::Field("?".to_owned()),
    }
}

// -------------------------------------------------------------------------------------------
// Naming the fields of a message given as a list
// -------------------------------------------------------------------------------------------

/// The type of the value at the end of a path, where the reader names it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Leaf {
    /// A message, a list, a string, or a value the reader took as any JSON.
    Other,
    /// A number of this type, e.g. `a 32-bit float (f32)`.
    Number(&'static str),
}

impl FieldPath {
    /// The reader's `path` into a `T`, each position in a message given as a list of its field
    /// values (as rosbridge allows) replaced by that field's name, so that `[0][0][1][0]`
    /// becomes `commands[0].cooperator.decision`; and the type of the value at its end.
    ///
    /// The names are the message's own, as `T`'s deserializer declares them: the path is
    /// walked by deserializing a `T` from a reader that holds nothing but the path.
    pub(super) fn named<T: DeserializeOwned>(path: &serde_path_to_error::Path) -> (Self, Leaf) {
        let reader: Vec<&Segment> = path.iter().collect();
        let mut named = Vec::with_capacity(reader.len());
        let mut leaf = Leaf::Other;
        // The walk always ends in an error of its own, where the path ends.
        let _stopped = T::deserialize(Walk {
            rest: &reader,
            named: &mut named,
            leaf: &mut leaf,
        });
        // Steps the walk did not reach keep the reader's form.
        let reached = named.len();
        named.extend(
            reader
                .get(reached..)
                .unwrap_or_default()
                .iter()
                .map(|s| plain(s)),
        );
        (named.into_iter().collect(), leaf)
    }
}

/// A deserializer that follows a path and names each step; see [`FieldPath::named`].
struct Walk<'p, 'w> {
    /// The steps not yet taken.
    rest: &'p [&'p Segment],
    /// The steps taken, named.
    named: &'w mut Vec<PathSegment>,
    /// The type at the end, once reached.
    leaf: &'w mut Leaf,
}

/// The end of a walk.
fn stop() -> value::Error {
    value::Error::custom("the end of the path")
}

impl<'de> Walk<'_, '_> {
    /// One step into a message (whose fields are `fields`) or a list (no `fields`).
    fn step<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, value::Error> {
        let Some((segment, rest)) = self.rest.split_first() else {
            return Err(stop());
        };
        let next = Walk {
            rest,
            named: &mut *self.named,
            leaf: &mut *self.leaf,
        };
        match segment {
            // A message given as a list: the position is a field.
            Segment::Seq { index } => match fields.get(*index) {
                Some(name) => {
                    next.named.push(PathSegment::Field((*name).to_owned()));
                    visitor.visit_map(Entry {
                        key: Some(name),
                        value: Some(next),
                    })
                }
                None => {
                    next.named.push(PathSegment::Index(*index));
                    visitor.visit_seq(Element(Some(next)))
                }
            },
            Segment::Map { key } => {
                next.named.push(PathSegment::Field(key.clone()));
                visitor.visit_map(Entry {
                    key: Some(key),
                    value: Some(next),
                })
            }
            Segment::Enum { .. } | Segment::Unknown => Err(stop()),
        }
    }

    /// A number: the end of any path.
    fn number(self, kind: &'static str) -> value::Error {
        if self.rest.is_empty() {
            *self.leaf = Leaf::Number(kind);
        }
        stop()
    }
}

macro_rules! numbers {
    ($($method:ident: $kind:literal),* $(,)?) => {
        $(fn $method<V: Visitor<'de>>(self, _visitor: V) -> Result<V::Value, value::Error> {
            Err(self.number($kind))
        })*
    };
}

impl<'de> Deserializer<'de> for Walk<'_, '_> {
    type Error = value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, value::Error> {
        self.step(&[], visitor)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, value::Error> {
        self.step(fields, visitor)
    }

    numbers! {
        deserialize_u8: "an 8-bit unsigned integer (u8)",
        deserialize_u16: "a 16-bit unsigned integer (u16)",
        deserialize_u32: "a 32-bit unsigned integer (u32)",
        deserialize_u64: "a 64-bit unsigned integer (u64)",
        deserialize_i8: "an 8-bit integer (i8)",
        deserialize_i16: "a 16-bit integer (i16)",
        deserialize_i32: "a 32-bit integer (i32)",
        deserialize_i64: "a 64-bit integer (i64)",
        deserialize_f32: "a 32-bit float (f32)",
        deserialize_f64: "a 64-bit float (f64)",
    }

    serde::forward_to_deserialize_any! {
        bool i128 u128 char str string bytes byte_buf option unit unit_struct newtype_struct
        seq tuple tuple_struct map enum identifier ignored_any
    }
}

/// A message of one field: the next step.
struct Entry<'p, 'w> {
    key: Option<&'p str>,
    value: Option<Walk<'p, 'w>>,
}

impl<'de> MapAccess<'de> for Entry<'_, '_> {
    type Error = value::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, value::Error> {
        match self.key.take() {
            Some(key) => seed.deserialize(key.into_deserializer()).map(Some),
            None => Ok(None),
        }
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> Result<V::Value, value::Error> {
        match self.value.take() {
            Some(walk) => seed.deserialize(walk),
            None => Err(stop()),
        }
    }
}

/// A list of one entry: the next step.
struct Element<'p, 'w>(Option<Walk<'p, 'w>>);

impl<'de> SeqAccess<'de> for Element<'_, '_> {
    type Error = value::Error;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, value::Error> {
        match self.0.take() {
            Some(walk) => seed.deserialize(walk).map(Some),
            None => Ok(None),
        }
    }
}

/// Why a message cannot be read or converted into the core's types. Each variant names the
/// field at fault; [`Display`](fmt::Display) writes `path: explanation`.
///
/// Rules of the cooperation state machine (an unknown scene, a module without a policy, the
/// same scene twice in a batch, a batch over the limit) are not checked here: the core checks
/// them, and the service handlers turn its [`Rejection`](cooperation::Rejection) into the response.
#[derive(Clone, PartialEq, Eq, Debug)]
#[non_exhaustive]
pub enum Malformed {
    /// The bytes are not JSON: bad syntax, the text ends early, or text follows the message.
    NotJson {
        /// Where the reader was.
        path: FieldPath,
        /// The JSON reader's explanation, with line and column.
        detail: String,
    },
    /// The JSON does not have the message's shape: a value of the wrong type, a field the
    /// message does not have or has once only, a number out of its field's range, a UUID
    /// that is not 16 bytes (`a UUID has 16 bytes, not 15`) or a UUID string that is not
    /// base64.
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
    /// A behaviour string that is neither a `PlanningBehavior` value (the empty `UNKNOWN` is
    /// refused) nor a valid user-extension name ([`cooperation::Extension`]).
    InvalidBehavior {
        /// The field.
        path: FieldPath,
        /// The string given.
        given: String,
        /// What is wrong with it.
        problem: cooperation::NameProblem,
    },
    /// A sequence string that is neither empty, a `PlanningSequence` value nor a valid
    /// user-extension name ([`cooperation::Extension`]).
    InvalidSequence {
        /// The field.
        path: FieldPath,
        /// The string given.
        given: String,
        /// What is wrong with it.
        problem: cooperation::NameProblem,
    },
    /// A factor's `cooperation` list has more than its one allowed entry.
    TooManyCooperation {
        /// The list.
        path: FieldPath,
        /// Its length.
        len: usize,
    },
    /// Factor poses in another frame than `map`, the frame of the core's poses.
    Frame {
        /// The header's `frame_id`.
        path: FieldPath,
        /// The frame given.
        given: String,
    },
    /// A request longer than [`MAX_REQUEST_BYTES`](super::MAX_REQUEST_BYTES), refused before
    /// it is read. The path is the request's own (the root).
    TooLarge {
        /// The request itself.
        path: FieldPath,
        /// Its length in bytes.
        len: usize,
        /// The most bytes a request may have.
        max: usize,
    },
}

/// `$body` with `$path` bound to the path of whichever fault `$fault` is: every variant
/// listed once, for both the shared and the mutable borrow.
macro_rules! with_path {
    ($fault:expr, $path:ident => $body:expr) => {
        match $fault {
            Malformed::NotJson { path: $path, .. }
            | Malformed::Shape { path: $path, .. }
            | Malformed::UndefinedConstant { path: $path, .. }
            | Malformed::UnacceptedConstant { path: $path, .. }
            | Malformed::InvalidBehavior { path: $path, .. }
            | Malformed::InvalidSequence { path: $path, .. }
            | Malformed::TooManyCooperation { path: $path, .. }
            | Malformed::Frame { path: $path, .. }
            | Malformed::TooLarge { path: $path, .. } => $body,
        }
    };
}

impl Malformed {
    /// Where the fault is.
    #[must_use]
    pub const fn path(&self) -> &FieldPath {
        with_path!(self, path => path)
    }

    fn path_mut(&mut self) -> &mut FieldPath {
        with_path!(self, path => path)
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
            return escaped(f, text);
        }
        let head = EXPLAINED * 2 / 3;
        let tail = EXPLAINED - head;
        let offset = |n: usize| text.char_indices().nth(n).map_or(text.len(), |(at, _)| at);
        escaped(f, text.get(..offset(head)).unwrap_or_default())?;
        f.write_str(" … ")?;
        escaped(f, text.get(offset(chars - tail)..).unwrap_or_default())
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
            Self::InvalidBehavior { given, problem, .. } => write!(
                f,
                "{} is no PlanningBehavior value or extension name: {problem}",
                Quoted(given)
            ),
            Self::InvalidSequence { given, problem, .. } => write!(
                f,
                "{} is no PlanningSequence value or extension name: {problem}",
                Quoted(given)
            ),
            Self::TooManyCooperation { len, .. } => {
                write!(f, "{len} entries; a factor has at most 1")
            }
            Self::Frame { given, .. } => {
                write!(
                    f,
                    "{}; factor poses are in the \"map\" frame",
                    Quoted(given)
                )
            }
            Self::TooLarge { len, max, .. } => {
                write!(
                    f,
                    "the request is {len} bytes long; at most {max} bytes are read"
                )
            }
        }
    }
}

impl std::error::Error for Malformed {}
