//! Scene identifiers.

use core::fmt;

/// A scene's identifier: the 16 bytes of a UUID chosen by the scene's owner.
///
/// The core never generates identifiers; they arrive in [`Input::Register`](crate::Input).
/// An identifier belongs to one scene and one module for ever (spec §5.1).
///
/// With the `serde` feature it is (de)serialized as its hyphenated string.
///
/// Identifiers are ordered as their bytes are, most significant first (the order of
/// [`to_u128`](Self::to_u128)).
///
/// Held as two 64-bit halves, so that an identifier is aligned and loads as two words: it is
/// the key of every search the core makes.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SceneId {
    /// Bytes 0 to 7, big-endian: compared first.
    high: u64,
    /// Bytes 8 to 15, big-endian.
    low: u64,
}

impl SceneId {
    /// An identifier from the 16 bytes of a UUID, most significant first.
    #[must_use]
    pub const fn from_bytes(bytes: [u8; 16]) -> Self {
        Self::from_u128(u128::from_be_bytes(bytes))
    }

    /// An identifier from a 128-bit number (big-endian bytes), handy in tests and models.
    #[must_use]
    pub const fn from_u128(value: u128) -> Self {
        Self {
            high: (value >> 64) as u64,
            low: value as u64,
        }
    }

    /// The 16 bytes of the UUID, most significant first.
    #[must_use]
    pub const fn to_bytes(self) -> [u8; 16] {
        self.to_u128().to_be_bytes()
    }

    /// The identifier as a 128-bit number (its bytes big-endian): the inverse of
    /// [`from_u128`](Self::from_u128).
    #[must_use]
    pub const fn to_u128(self) -> u128 {
        ((self.high as u128) << 64) | self.low as u128
    }

    /// A cheap, fixed 64-bit hash of the identifier: its halves folded together and spread by
    /// a multiplication (Fibonacci hashing), its high bits folded into the low ones that pick a
    /// bucket. Cheap, since owners draw identifiers at random; fixed, so that a table keyed by
    /// identifiers behaves the same in every run. The core's scene table hashes with it.
    #[must_use]
    pub const fn spread(self) -> u64 {
        let folded = self.low ^ self.high.rotate_left(29);
        let h = folded.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        h ^ (h >> 32)
    }
}

impl fmt::Display for SceneId {
    /// The canonical hyphenated UUID form, `xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (index, byte) in self.to_bytes().iter().enumerate() {
            if matches!(index, 4 | 6 | 8 | 10) {
                f.write_str("-")?;
            }
            write!(f, "{byte:02x}")?;
        }
        Ok(())
    }
}

/// A string that is not a UUID: 32 hexadecimal digits, optionally hyphenated as 8-4-4-4-12.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct InvalidSceneId {
    /// The string that was given.
    pub given: String,
}

impl fmt::Display for InvalidSceneId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} is not a UUID (32 hexadecimal digits, optionally 8-4-4-4-12)",
            self.given
        )
    }
}

impl std::error::Error for InvalidSceneId {}

impl core::str::FromStr for SceneId {
    type Err = InvalidSceneId;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let invalid = || InvalidSceneId {
            given: text.to_owned(),
        };
        // Bytes, not characters: a valid UUID is ASCII, and any other byte fails as a digit.
        let hyphen_at: &[usize] = match text.len() {
            32 => &[],
            36 => &[8, 13, 18, 23],
            _ => return Err(invalid()),
        };
        let mut value: u128 = 0;
        for (at, byte) in text.bytes().enumerate() {
            if hyphen_at.contains(&at) {
                if byte != b'-' {
                    return Err(invalid());
                }
                continue;
            }
            let digit = char::from(byte).to_digit(16).ok_or_else(invalid)?;
            value = (value << 4) | u128::from(digit);
        }
        Ok(Self::from_u128(value))
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for SceneId {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for SceneId {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = <std::borrow::Cow<'de, str>>::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

impl fmt::Debug for SceneId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "SceneId({self})")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn displays_as_hyphenated_uuid() {
        let id = SceneId::from_u128(0x0123_4567_89ab_cdef_0011_2233_4455_6677);
        assert_eq!(id.to_string(), "01234567-89ab-cdef-0011-223344556677");
        assert_eq!(
            format!("{id:?}"),
            "SceneId(01234567-89ab-cdef-0011-223344556677)"
        );
    }

    #[test]
    fn parses_hyphenated_and_plain_forms_only() {
        let id = SceneId::from_u128(0x0123_4567_89ab_cdef_0011_2233_4455_6677);
        assert_eq!("01234567-89ab-cdef-0011-223344556677".parse(), Ok(id));
        assert_eq!("0123456789ABCDEF0011223344556677".parse(), Ok(id));
        assert_eq!(id.to_string().parse(), Ok(id));
        for bad in [
            "",
            "0123",
            "01234567-89ab-cdef-0011-22334455667",
            "0123456789ab-cdef-0011-223344556677-",
            "g1234567-89ab-cdef-0011-223344556677",
            "0123456789abcdef00112233445566+7",
            "01234567-89ab-cdef-0011-2233445566\u{e9}",
            // Hyphens count only where the 8-4-4-4-12 form puts them.
            "--------------------------------",
            "-000000000000000000000000000abcd",
            "0123456789abcdef00112233445566-7",
            "01234567-89ab-cdef-0011-22334455667-",
            "01234567089ab-cdef-0011-223344556677",
        ] {
            assert!(bad.parse::<SceneId>().is_err(), "{bad}");
        }
    }

    proptest::proptest! {
        /// A string parses only if it is one of the two documented forms of the identifier it
        /// gives, in either case.
        #[test]
        fn parses_only_the_documented_forms(text in "[0-9a-fA-F-]{30,37}") {
            if let Ok(id) = text.parse::<SceneId>() {
                let canonical = id.to_string();
                let lower = text.to_ascii_lowercase();
                proptest::prop_assert!(lower == canonical || lower == canonical.replace('-', ""), "{text}");
            }
        }

        /// Identifiers order as their bytes do, and the bytes and the number read back.
        #[test]
        fn order_is_byte_order(a in proptest::array::uniform16(0u8..), b in proptest::array::uniform16(0u8..)) {
            let (x, y) = (SceneId::from_bytes(a), SceneId::from_bytes(b));
            proptest::prop_assert_eq!(x.cmp(&y), a.cmp(&b));
            proptest::prop_assert_eq!(x.to_bytes(), a);
            proptest::prop_assert_eq!(SceneId::from_u128(x.to_u128()), x);
        }
    }
}
