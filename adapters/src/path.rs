//! Where in a message a value sits: the field paths every reader's errors name, for the AD API
//! messages (`wire::Malformed`) and the RTC ones (`rtc::FieldError`) alike.

use core::fmt::{self, Write as _};

/// At most this many characters of a string from the input are quoted in a message.
pub(crate) const QUOTED: usize = 64;

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
/// `wire::CooperationCommand` names `cooperator.decision`, converting
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

    pub(crate) fn prepend(&mut self, segment: PathSegment) {
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
                    // A field name can come from the input (an unknown field): keep it short,
                    // on one line.
                    match name.char_indices().nth(QUOTED) {
                        None => escaped(f, name)?,
                        Some((end, _)) => {
                            escaped(f, name.get(..end).unwrap_or_default())?;
                            f.write_str("…")?;
                        }
                    }
                }
                PathSegment::Index(index) => write!(f, "[{index}]")?,
            }
        }
        Ok(())
    }
}

/// Text from the input on one line: control characters (line breaks, terminal escapes) are
/// written as Rust escapes, `\n`, `\u{1b}`.
pub(crate) fn escaped(f: &mut fmt::Formatter<'_>, text: &str) -> fmt::Result {
    for c in text.chars() {
        if c.is_control() {
            write!(f, "{}", c.escape_default())?;
        } else {
            f.write_char(c)?;
        }
    }
    Ok(())
}
