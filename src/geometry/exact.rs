//! The serde form of the geometry's floats, exact for every bit pattern, so that whatever the
//! core holds is read back as it was written (a state, a trace, a counterexample).
//!
//! - A finite value is a number. Read back, it must fit its type: a distance (`f32`) beyond
//!   ±3.4028235e38 is refused, not turned into an infinity.
//! - `"inf"` and `"-inf"` are the infinities.
//! - A NaN is `"NaN:0x"` and its bit pattern in lowercase hexadecimal, 8 digits for a
//!   distance and 16 for a pose coordinate (`"NaN:0x7fc00000"`), because its sign and payload
//!   are part of the value: floats compare by their bits.
//!
//! Formats without NaN or infinities, JSON among them, can thus carry every geometry.

use core::fmt;
use core::marker::PhantomData;

use serde::de::{Error, IgnoredAny, SeqAccess, Unexpected, Visitor};
use serde::ser::SerializeTuple;
use serde::{Deserializer, Serializer};

/// A float type of the geometry: `f32` (distances) or `f64` (poses).
pub(super) trait Float: Copy + Default + fmt::Display {
    /// What a reader is told it should have given.
    const EXPECTING: &'static str;
    /// Hexadecimal digits of a NaN's bit pattern.
    const HEX_DIGITS: usize;
    fn from_f64(value: f64) -> Option<Self>;
    fn bits(self) -> u64;
    fn from_bits(bits: u64) -> Option<Self>;
    fn is_finite(self) -> bool;
    fn is_nan(self) -> bool;
    fn serialize<S: Serializer>(self, serializer: S) -> Result<S::Ok, S::Error>;
}

impl Float for f32 {
    const EXPECTING: &'static str = "a number that fits a 32-bit float, \"inf\", \"-inf\" \
                                     or \"NaN:0x\" and 8 hexadecimal digits";
    const HEX_DIGITS: usize = 8;

    #[allow(clippy::cast_possible_truncation)] // Rounds to nearest; checked for overflow.
    fn from_f64(value: f64) -> Option<Self> {
        // What an `f32` written in decimal reads back as, `3.4028235e38` included, rounds
        // back to it; only a number beyond every `f32` becomes an infinity, and is refused.
        let rounded = value as Self;
        rounded.is_finite().then_some(rounded)
    }
    fn bits(self) -> u64 {
        u64::from(self.to_bits())
    }
    fn from_bits(bits: u64) -> Option<Self> {
        u32::try_from(bits).ok().map(Self::from_bits)
    }
    fn is_finite(self) -> bool {
        self.is_finite()
    }
    fn is_nan(self) -> bool {
        self.is_nan()
    }
    fn serialize<S: Serializer>(self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_f32(self)
    }
}

impl Float for f64 {
    const EXPECTING: &'static str =
        "a number, \"inf\", \"-inf\" or \"NaN:0x\" and 16 hexadecimal digits";
    const HEX_DIGITS: usize = 16;

    fn from_f64(value: f64) -> Option<Self> {
        Some(value)
    }
    fn bits(self) -> u64 {
        self.to_bits()
    }
    fn from_bits(bits: u64) -> Option<Self> {
        Some(Self::from_bits(bits))
    }
    fn is_finite(self) -> bool {
        self.is_finite()
    }
    fn is_nan(self) -> bool {
        self.is_nan()
    }
    fn serialize<S: Serializer>(self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_f64(self)
    }
}

/// One float in its exact form.
pub(super) struct Exact<T>(pub(super) T);

impl<T: Float> serde::Serialize for Exact<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let value = self.0;
        if value.is_finite() {
            value.serialize(serializer)
        } else if value.is_nan() {
            let digits = T::HEX_DIGITS;
            serializer.collect_str(&format_args!("NaN:0x{:0digits$x}", value.bits()))
        } else {
            serializer.serialize_str(if value.bits() == inf_bits::<T>() {
                "inf"
            } else {
                "-inf"
            })
        }
    }
}

impl<'de, T: Float> serde::Deserialize<'de> for Exact<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(ExactVisitor(PhantomData))
    }
}

struct ExactVisitor<T>(PhantomData<T>);

impl<T: Float> Visitor<'_> for ExactVisitor<T> {
    type Value = Exact<T>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(T::EXPECTING)
    }

    fn visit_f64<E: Error>(self, value: f64) -> Result<Exact<T>, E> {
        // A non-finite number comes only from a format that has them: keep it as it is.
        let exact = if value.is_nan() {
            None
        } else if value.is_infinite() {
            T::from_bits(inf_bits::<T>() | sign_bit::<T>(value.is_sign_negative()))
        } else {
            T::from_f64(value)
        };
        exact
            .map(Exact)
            .ok_or_else(|| E::invalid_value(Unexpected::Float(value), &self))
    }

    #[allow(clippy::cast_precision_loss)] // As JSON readers take integers for floats.
    fn visit_i64<E: Error>(self, value: i64) -> Result<Exact<T>, E> {
        self.visit_f64(value as f64)
    }

    #[allow(clippy::cast_precision_loss)] // As JSON readers take integers for floats.
    fn visit_u64<E: Error>(self, value: u64) -> Result<Exact<T>, E> {
        self.visit_f64(value as f64)
    }

    fn visit_str<E: Error>(self, text: &str) -> Result<Exact<T>, E> {
        let bits = match text {
            "inf" => Some(inf_bits::<T>()),
            "-inf" => Some(inf_bits::<T>() | sign_bit::<T>(true)),
            _ => text
                .strip_prefix("NaN:0x")
                .filter(|hex| {
                    hex.len() == T::HEX_DIGITS
                        && hex.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
                })
                .and_then(|hex| u64::from_str_radix(hex, 16).ok())
                .filter(|bits| T::from_bits(*bits).is_some_and(T::is_nan)),
        };
        bits.and_then(T::from_bits).map(Exact).ok_or_else(|| {
            // Quoted in part: a reader's text is not echoed whole.
            let quoted: String = text.chars().take(32).collect();
            E::invalid_value(Unexpected::Str(&quoted), &self)
        })
    }
}

/// `T`'s sign bit, if `negative`.
fn sign_bit<T: Float>(negative: bool) -> u64 {
    u64::from(negative) << (T::HEX_DIGITS * 4 - 1)
}

/// The bit pattern of `T`'s positive infinity.
fn inf_bits<T: Float>() -> u64 {
    // Exponent all ones, fraction zero: the bits above the fraction, less the sign.
    match T::HEX_DIGITS {
        8 => 0x7f80_0000,
        _ => 0x7ff0_0000_0000_0000,
    }
}

/// `#[serde(with)]` for a distance array, or a pose's coordinates.
pub(super) mod array {
    use super::{
        Deserializer, Error, Exact, Float, IgnoredAny, PhantomData, SeqAccess, SerializeTuple,
        Serializer, Visitor,
    };
    use core::fmt;

    pub(in crate::geometry) fn serialize<S: Serializer, T: Float, const N: usize>(
        values: &[T; N],
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        let mut tuple = serializer.serialize_tuple(N)?;
        for value in values {
            tuple.serialize_element(&Exact(*value))?;
        }
        tuple.end()
    }

    pub(in crate::geometry) fn deserialize<'de, D: Deserializer<'de>, T: Float, const N: usize>(
        deserializer: D,
    ) -> Result<[T; N], D::Error> {
        deserializer.deserialize_tuple(N, Values(PhantomData))
    }

    struct Values<T, const N: usize>(PhantomData<T>);

    impl<'de, T: Float, const N: usize> Visitor<'de> for Values<T, N> {
        type Value = [T; N];

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(f, "a list of {N} numbers")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[T; N], A::Error> {
            let mut values = [T::default(); N];
            for (index, value) in values.iter_mut().enumerate() {
                let Exact(read) = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(index, &self))?;
                *value = read;
            }
            if seq.next_element::<IgnoredAny>()?.is_some() {
                return Err(A::Error::invalid_length(N + 1, &self));
            }
            Ok(values)
        }
    }
}
