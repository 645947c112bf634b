//! Reading: a serde deserializer for the messages' shapes, strict about every byte.

use serde::de::{self, DeserializeOwned, DeserializeSeed, Visitor};

use super::{CdrError, CDR_LE};

/// A message from little-endian plain CDR, its encapsulation header first.
///
/// # Errors
/// A [`CdrError`] naming the offset if the header is not little-endian plain CDR, the data ends
/// early, a boolean is neither 0 nor 1, a string lacks its final NUL, holds another or is not
/// UTF-8, a count exceeds
/// the bytes left, or more than three bytes (of padding) follow the message.
pub fn from_slice<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, CdrError> {
    let Some((header, data)) = bytes.split_first_chunk::<4>() else {
        return Err(CdrError {
            message: format!("{} bytes are no encapsulation header", bytes.len()),
            offset: 0,
        });
    };
    // The options (last two bytes) are ignored, as readers of plain CDR do.
    if header[..2] != CDR_LE[..2] {
        return Err(CdrError {
            message: format!(
                "encapsulation {:02x}{:02x} is not little-endian plain CDR (0001)",
                header[0], header[1]
            ),
            offset: 0,
        });
    }
    let mut reader = Reader {
        data,
        pos: 0,
        first: None,
    };
    let value = T::deserialize(&mut reader).map_err(|error| error.placed_at(0))?;
    // A writer may pad the message to a multiple of four bytes; padding, inside or after, is
    // not read, whatever its value.
    let rest = reader.remaining();
    if rest > 3 {
        return Err(reader.error(format!("{rest} bytes follow the message")));
    }
    Ok(value)
}

struct Reader<'de> {
    data: &'de [u8],
    /// The offset of the next byte from the start of the data, after the header.
    pos: usize,
    /// Where the first byte read (padding aside) of the element being read is, once one is.
    first: Option<usize>,
}

impl<'de> Reader<'de> {
    fn error(&self, message: impl Into<String>) -> CdrError {
        CdrError {
            message: message.into(),
            offset: self.pos,
        }
    }

    fn remaining(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    fn take(&mut self, len: usize) -> Result<&'de [u8], CdrError> {
        if len > 0 {
            self.first.get_or_insert(self.pos);
        }
        self.skip(len)
    }

    /// The next `len` bytes, padding or data: not where a value starts.
    fn skip(&mut self, len: usize) -> Result<&'de [u8], CdrError> {
        let end = self.pos.checked_add(len);
        let bytes = end
            .and_then(|end| self.data.get(self.pos..end))
            .ok_or_else(|| {
                self.error(format!(
                    "the message ends {} bytes early",
                    len.saturating_sub(self.remaining())
                ))
            })?;
        self.pos += len;
        Ok(bytes)
    }

    fn aligned<const N: usize>(&mut self) -> Result<[u8; N], CdrError> {
        let padding = (N - self.pos % N) % N;
        self.skip(padding)?;
        let bytes = self.take(N)?;
        let mut out = [0; N];
        out.copy_from_slice(bytes);
        Ok(out)
    }

    /// A count, no greater than the bytes left: each element takes at least one.
    fn count(&mut self) -> Result<usize, CdrError> {
        let count = u32::from_le_bytes(self.aligned::<4>()?);
        let count = usize::try_from(count).unwrap_or(usize::MAX);
        if count > self.remaining() {
            return Err(self.error(format!(
                "a count of {count} exceeds the {} bytes left",
                self.remaining()
            )));
        }
        Ok(count)
    }
}

macro_rules! number {
    ($($method:ident $visit:ident $ty:ty;)*) => {
        $(
            fn $method<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
                let bytes = self.aligned::<{ core::mem::size_of::<$ty>() }>()?;
                visitor.$visit(<$ty>::from_le_bytes(bytes))
            }
        )*
    };
}

macro_rules! refuse {
    ($($method:ident;)*) => {
        $(
            fn $method<V: Visitor<'de>>(self, _: V) -> Result<V::Value, CdrError> {
                Err(self.error(concat!("no message has this shape (", stringify!($method), ")")))
            }
        )*
    };
}

impl<'de> de::Deserializer<'de> for &mut Reader<'de> {
    type Error = CdrError;

    number! {
        deserialize_i8 visit_i8 i8; deserialize_i16 visit_i16 i16; deserialize_i32 visit_i32 i32;
        deserialize_i64 visit_i64 i64; deserialize_u8 visit_u8 u8; deserialize_u16 visit_u16 u16;
        deserialize_u32 visit_u32 u32; deserialize_u64 visit_u64 u64;
        deserialize_f32 visit_f32 f32; deserialize_f64 visit_f64 f64;
    }

    fn deserialize_bool<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        match self.take(1)? {
            [0] => visitor.visit_bool(false),
            [1] => visitor.visit_bool(true),
            other => {
                self.pos -= 1;
                Err(self.error(format!("a boolean is 0 or 1, not {other:?}")))
            }
        }
    }

    fn deserialize_str<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        let len = self.count()?;
        let start = self.pos;
        let bytes = self.take(len)?;
        let Some((0, text)) = bytes.split_last() else {
            self.pos = start;
            return Err(self.error("a string must end with a NUL byte"));
        };
        if text.contains(&0) {
            self.pos = start;
            return Err(self.error("a string holds a NUL byte before its end"));
        }
        match core::str::from_utf8(text) {
            Ok(text) => visitor.visit_borrowed_str(text),
            Err(e) => {
                self.pos = start;
                Err(self.error(format!("a string that is not UTF-8: {e}")))
            }
        }
    }

    fn deserialize_string<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        self.deserialize_str(visitor)
    }

    fn deserialize_bytes<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        let len = self.count()?;
        visitor.visit_borrowed_bytes(self.take(len)?)
    }

    fn deserialize_byte_buf<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        self.deserialize_bytes(visitor)
    }

    fn deserialize_unit<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        visitor.visit_unit()
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        visitor: V,
    ) -> Result<V::Value, CdrError> {
        visitor.visit_newtype_struct(self)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, CdrError> {
        let count = self.count()?;
        visitor.visit_seq(Elements {
            reader: self,
            left: count,
        })
    }

    fn deserialize_tuple<V: Visitor<'de>>(
        self,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, CdrError> {
        visitor.visit_seq(Elements {
            reader: self,
            left: len,
        })
    }

    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        len: usize,
        visitor: V,
    ) -> Result<V::Value, CdrError> {
        self.deserialize_tuple(len, visitor)
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, CdrError> {
        if fields.is_empty() {
            // The member ROS 2 adds to an empty message.
            self.take(1)?;
        }
        visitor.visit_seq(Elements {
            reader: self,
            left: fields.len(),
        })
    }

    refuse! {
        deserialize_any; deserialize_char; deserialize_option; deserialize_map;
        deserialize_identifier; deserialize_ignored_any;
    }

    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        visitor: V,
    ) -> Result<V::Value, CdrError> {
        visitor.visit_unit()
    }

    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _: &'static str,
        _: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, CdrError> {
        Err(self.error("no message has an enum field"))
    }

    fn is_human_readable(&self) -> bool {
        false
    }
}

/// The elements of a sequence, array or struct.
struct Elements<'a, 'de> {
    reader: &'a mut Reader<'de>,
    left: usize,
}

impl<'de> de::SeqAccess<'de> for Elements<'_, 'de> {
    type Error = CdrError;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, CdrError> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        // An error the element's type raises itself is placed at the element's first byte
        // (after any padding before it); the enclosing element starts where it started, or
        // here if this is its first.
        let outer = self.reader.first.take();
        let start = self.reader.pos;
        let value = seed.deserialize(&mut *self.reader);
        let first = self.reader.first.unwrap_or(start);
        self.reader.first = Some(outer.unwrap_or(first));
        value.map(Some).map_err(|error| error.placed_at(first))
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.left)
    }
}
