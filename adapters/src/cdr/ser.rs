//! Writing: a serde serializer for the messages' shapes (structs, sequences, fixed arrays,
//! strings, booleans and numbers). Any other shape is an error: no message has one.

use serde::ser::{self, Serialize};

use super::{CdrError, CDR_LE};

/// `value` in little-endian plain CDR, its encapsulation header first.
///
/// # Errors
/// A [`CdrError`] if the value has a shape no message has (a map, an option, an enum), a
/// string holding a NUL byte, a sequence of unknown length, or a UUID that is not sixteen bytes.
pub fn to_vec<T: Serialize + ?Sized>(value: &T) -> Result<Vec<u8>, CdrError> {
    let mut writer = Writer {
        out: CDR_LE.to_vec(),
    };
    value.serialize(&mut writer)?;
    Ok(writer.out)
}

struct Writer {
    out: Vec<u8>,
}

impl Writer {
    /// The offset from the start of the data, after the header.
    fn offset(&self) -> usize {
        self.out.len().saturating_sub(CDR_LE.len())
    }

    fn error(&self, message: impl Into<String>) -> CdrError {
        CdrError {
            message: message.into(),
            offset: self.offset(),
        }
    }

    fn align(&mut self, size: usize) {
        let padding = (size - self.offset() % size) % size;
        self.out.extend(core::iter::repeat(0).take(padding));
    }

    fn put(&mut self, bytes: &[u8]) {
        self.align(bytes.len());
        self.out.extend_from_slice(bytes);
    }

    fn count(&mut self, len: usize) -> Result<(), CdrError> {
        let count = u32::try_from(len)
            .map_err(|_| self.error(format!("{len} elements do not fit a CDR count")))?;
        self.put(&count.to_le_bytes());
        Ok(())
    }
}

/// The serializer methods for numbers: little-endian, aligned to their size.
macro_rules! numbers {
    ($($method:ident $ty:ty;)*) => {
        $(
            fn $method(self, v: $ty) -> Result<(), CdrError> {
                self.put(&v.to_le_bytes());
                Ok(())
            }
        )*
    };
}

/// The serializer methods for shapes no message has.
macro_rules! refuse {
    ($($method:ident($($arg:ty),*) -> $ok:ty;)*) => {
        $(
            fn $method(self, $(_: $arg),*) -> Result<$ok, CdrError> {
                Err(self.error(concat!("no message has this shape (", stringify!($method), ")")))
            }
        )*
    };
}

/// The collector's methods for anything but bytes.
impl<'a> ser::Serializer for &'a mut Writer {
    type Ok = ();
    type Error = CdrError;
    type SerializeSeq = Elements<'a>;
    type SerializeTuple = Elements<'a>;
    type SerializeTupleStruct = Elements<'a>;
    type SerializeTupleVariant = ser::Impossible<(), CdrError>;
    type SerializeMap = ser::Impossible<(), CdrError>;
    type SerializeStruct = Fields<'a>;
    type SerializeStructVariant = ser::Impossible<(), CdrError>;

    fn serialize_bool(self, v: bool) -> Result<(), CdrError> {
        self.put(&[u8::from(v)]);
        Ok(())
    }
    numbers! {
        serialize_i8 i8; serialize_i16 i16; serialize_i32 i32; serialize_i64 i64;
        serialize_u8 u8; serialize_u16 u16; serialize_u32 u32; serialize_u64 u64;
        serialize_f32 f32; serialize_f64 f64;
    }
    fn serialize_str(self, v: &str) -> Result<(), CdrError> {
        if v.as_bytes().contains(&0) {
            return Err(self.error("a string holding a NUL byte has no CDR form"));
        }
        self.count(v.len().saturating_add(1))?;
        self.out.extend_from_slice(v.as_bytes());
        self.out.push(0);
        Ok(())
    }
    fn serialize_bytes(self, v: &[u8]) -> Result<(), CdrError> {
        self.count(v.len())?;
        self.out.extend_from_slice(v);
        Ok(())
    }
    fn serialize_unit(self) -> Result<(), CdrError> {
        Ok(())
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        value: &T,
    ) -> Result<(), CdrError> {
        value.serialize(self)
    }
    fn serialize_seq(self, len: Option<usize>) -> Result<Elements<'a>, CdrError> {
        let len = len.ok_or_else(|| self.error("a sequence of unknown length"))?;
        self.count(len)?;
        Ok(Elements { writer: self })
    }
    fn serialize_tuple(self, _: usize) -> Result<Elements<'a>, CdrError> {
        Ok(Elements { writer: self })
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Elements<'a>, CdrError> {
        Ok(Elements { writer: self })
    }
    fn serialize_struct(self, _: &'static str, len: usize) -> Result<Fields<'a>, CdrError> {
        if len == 0 {
            // ROS 2 gives an empty message one member, `uint8 structure_needs_at_least_one_member`.
            self.put(&[0]);
        }
        Ok(Fields { writer: self })
    }
    refuse! {
        serialize_char(char) -> ();
        serialize_none() -> ();
        serialize_unit_struct(&'static str) -> ();
        serialize_unit_variant(&'static str, u32, &'static str) -> ();
        serialize_tuple_variant(&'static str, u32, &'static str, usize) -> Self::SerializeTupleVariant;
        serialize_map(Option<usize>) -> Self::SerializeMap;
        serialize_struct_variant(&'static str, u32, &'static str, usize) -> Self::SerializeStructVariant;
    }
    fn serialize_some<T: Serialize + ?Sized>(self, _: &T) -> Result<(), CdrError> {
        Err(self.error("no message has an optional field"))
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<(), CdrError> {
        Err(self.error("no message has an enum field"))
    }
}

/// A sequence's or array's elements, one after the other.
struct Elements<'a> {
    writer: &'a mut Writer,
}

/// The three element traits, each writing its elements in order.
macro_rules! elements {
    ($($trait:ident::$method:ident),*) => {
        $(
            impl ser::$trait for Elements<'_> {
                type Ok = ();
                type Error = CdrError;
                fn $method<T: Serialize + ?Sized>(&mut self, value: &T) -> Result<(), CdrError> {
                    value.serialize(&mut *self.writer)
                }
                fn end(self) -> Result<(), CdrError> {
                    Ok(())
                }
            }
        )*
    };
}

elements!(
    SerializeSeq::serialize_element,
    SerializeTuple::serialize_element,
    SerializeTupleStruct::serialize_field
);

/// A struct's fields, in order.
struct Fields<'a> {
    writer: &'a mut Writer,
}

impl ser::SerializeStruct for Fields<'_> {
    type Ok = ();
    type Error = CdrError;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        _: &'static str,
        value: &T,
    ) -> Result<(), CdrError> {
        value.serialize(&mut *self.writer)
    }
    fn end(self) -> Result<(), CdrError> {
        Ok(())
    }
}
