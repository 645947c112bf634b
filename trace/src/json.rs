//! Reading a record's JSON: a key given twice is refused, structs are objects only, the
//! failing field is named, and what an error echoes from the input is kept short and
//! printable.

use std::collections::BTreeSet;
use std::fmt::Write as _;

use serde::de::{self, DeserializeSeed, Deserializer, Visitor};
use serde::Deserialize;

use crate::strict::Strict;
use crate::ErrorKind;

/// At most this many characters of a key from the input are shown in a field path.
const QUOTED: usize = 64;
/// An explanation longer than this many characters is shortened in the middle.
const EXPLAINED: usize = 240;

/// One step of a field path.
enum Segment {
    Key(String),
    Index(usize),
}

/// A field path as shown: `input.Register.geometry`, `observed[2].cancellable`; each key cut
/// to [`QUOTED`] characters and made printable.
fn path_text(segments: &[Segment]) -> String {
    let mut text = String::new();
    for segment in segments {
        match segment {
            Segment::Key(key) => {
                if !text.is_empty() {
                    text.push('.');
                }
                text.push_str(&quoted(key));
            }
            Segment::Index(index) => {
                let _ = write!(text, "[{index}]");
            }
        }
    }
    text
}

/// A key or other short text from the input, cut to [`QUOTED`] characters and printable.
pub(crate) fn quoted(text: &str) -> String {
    match text.char_indices().nth(QUOTED) {
        None => printable(text),
        Some((end, _)) => format!("{}…", printable(text.get(..end).unwrap_or_default())),
    }
}

/// An explanation that may quote the input: printable, and its middle left out if it is
/// longer than [`EXPLAINED`] characters (the end, which says where the fault is, is kept).
pub(crate) fn explained(text: &str) -> String {
    let text = printable(text);
    let chars = text.chars().count();
    if chars <= EXPLAINED {
        return text;
    }
    let head = EXPLAINED * 2 / 3;
    let tail = EXPLAINED - head;
    let offset = |n: usize| text.char_indices().nth(n).map_or(text.len(), |(at, _)| at);
    let start = text.get(..offset(head)).unwrap_or_default();
    let end = text.get(offset(chars - tail)..).unwrap_or_default();
    format!("{start} … {end}")
}

/// `text` with control characters and the characters that reorder or hide text (bidi
/// controls, zero-width characters) written as escapes, so that an error line shows what it
/// says and nothing else.
fn printable(text: &str) -> String {
    let hidden = |c: char| {
        c.is_control()
            || matches!(c, '\u{061c}' | '\u{200b}'..='\u{200f}' | '\u{2028}'..='\u{202e}')
            || matches!(c, '\u{2060}'..='\u{206f}' | '\u{feff}')
    };
    if !text.contains(hidden) {
        return text.to_owned();
    }
    text.chars()
        .map(|c| {
            if hidden(c) {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// serde_json's message, made short and printable; within one line, "(column N)" rather than
/// "at line 1 column N".
fn json_message(error: &serde_json::Error, one_line: bool) -> String {
    let message = error.to_string();
    let position = format!(" at line {} column {}", error.line(), error.column());
    let message = match message.strip_suffix(&position) {
        Some(bare) if one_line => format!("{bare} (column {})", error.column()),
        _ => message,
    };
    explained(&message)
}

/// A JSON error at `field` with `message`, both already short and printable.
pub(crate) fn json_error(field: String, message: &str) -> ErrorKind {
    ErrorKind::Json {
        field,
        message: explained(message),
    }
}

/// The path of a failing field. serde_path_to_error marks a key it could not read (not a
/// string, or the text ends) with an unknown segment; the path is then the object's.
fn field_path(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment as Step;
    let segments: Vec<Segment> = path
        .iter()
        .map_while(|step| match step {
            Step::Seq { index } => Some(Segment::Index(*index)),
            Step::Map { key } | Step::Enum { variant: key } => Some(Segment::Key(key.clone())),
            Step::Unknown => None,
        })
        .collect();
    path_text(&segments)
}

/// Deserializes `text` as a `T`, naming the field that fails: no key twice in any object,
/// and every struct an object. For a single line (`one_line`), positions are columns.
pub(crate) fn from_json<'de, T: Deserialize<'de>>(
    text: &'de str,
    one_line: bool,
) -> Result<T, ErrorKind> {
    walk(text, one_line)?;
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(Strict(&mut deserializer)).map_err(|error| {
        let field = field_path(error.path());
        json_error(field, &json_message(&error.into_inner(), one_line))
    })?;
    deserializer
        .end()
        .map_err(|error| json_error(String::new(), &json_message(&error, one_line)))?;
    Ok(value)
}

/// Reads `text` as any JSON, whatever the format, and refuses what is not JSON (syntax, the
/// end of the text, nesting deeper than serde_json's 128 levels) and a key given twice in one
/// object, anywhere, naming the path where the reading stopped. What is left for the typed
/// reading is JSON with no key twice.
fn walk(text: &str, one_line: bool) -> Result<(), ErrorKind> {
    let mut walk = Walk { path: Vec::new() };
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let walked = (&mut walk)
        .deserialize(&mut deserializer)
        .and_then(|()| deserializer.end());
    walked.map_err(|error| json_error(path_text(&walk.path), &json_message(&error, one_line)))
}

/// A walk through a JSON value: where it is.
struct Walk {
    path: Vec<Segment>,
}

impl<'de> DeserializeSeed<'de> for &mut Walk {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<(), D::Error> {
        deserializer.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for &mut Walk {
    type Value = ();

    fn expecting(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("any JSON value")
    }

    fn visit_bool<E: de::Error>(self, _: bool) -> Result<(), E> {
        Ok(())
    }

    fn visit_i64<E: de::Error>(self, _: i64) -> Result<(), E> {
        Ok(())
    }

    fn visit_u64<E: de::Error>(self, _: u64) -> Result<(), E> {
        Ok(())
    }

    fn visit_f64<E: de::Error>(self, _: f64) -> Result<(), E> {
        Ok(())
    }

    fn visit_str<E: de::Error>(self, _: &str) -> Result<(), E> {
        Ok(())
    }

    fn visit_unit<E: de::Error>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut index = 0;
        loop {
            self.path.push(Segment::Index(index));
            if seq.next_element_seed(&mut *self)?.is_none() {
                self.path.pop();
                return Ok(());
            }
            self.path.pop();
            index += 1;
        }
    }

    fn visit_map<A: de::MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut keys = BTreeSet::new();
        while let Some(key) = map.next_key::<String>()? {
            if keys.contains(&key) {
                let message = format!(
                    "duplicate field `{}`: given twice in one object",
                    quoted(&key)
                );
                self.path.push(Segment::Key(key));
                return Err(de::Error::custom(message));
            }
            self.path.push(Segment::Key(key.clone()));
            map.next_value_seed(&mut *self)?;
            self.path.pop();
            keys.insert(key);
        }
        Ok(())
    }
}
