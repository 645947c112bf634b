//! Standard base64 (RFC 4648, `A–Z a–z 0–9 + /`) for `uint8` arrays in rosbridge JSON: one
//! reader for every message that carries bytes as text, so every reader accepts the same
//! strings. The `base64` crate does the work; this module fixes its configuration and says
//! what a refusal means.

use core::fmt;

use base64::engine::{DecodePaddingMode, GeneralPurpose, GeneralPurposeConfig};
use base64::{alphabet, DecodeError, Engine};

/// Padding present, and then it must complete the last group of four.
const PADDED: GeneralPurpose = GeneralPurpose::new(
    &alphabet::STANDARD,
    GeneralPurposeConfig::new()
        .with_encode_padding(true)
        .with_decode_padding_mode(DecodePaddingMode::RequireCanonical)
        .with_decode_allow_trailing_bits(false),
);

/// Padding left out.
const UNPADDED: GeneralPurpose = GeneralPurpose::new(
    &alphabet::STANDARD,
    GeneralPurposeConfig::new()
        .with_decode_padding_mode(DecodePaddingMode::RequireNone)
        .with_decode_allow_trailing_bits(false),
);

/// A string that is not base64.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Base64Error {
    /// A character outside the standard alphabet (`A–Z a–z 0–9 + /`), at this byte offset.
    Character { at: usize, character: char },
    /// Padding (`=`) at this byte offset, which is not where the last group of four ends.
    Padding { at: usize },
    /// A length no base64 text has: one character left over after the last full group, or
    /// padding that does not complete a group of four.
    Length { len: usize },
    /// The last digit sets bits past the end of the data. Every byte string has one base64
    /// text, and these bits are zero in it.
    StrayBits { at: usize, character: char },
}

impl fmt::Display for Base64Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Character { at, character } => write!(
                f,
                "not base64: {character:?} at offset {at} is outside the standard alphabet"
            ),
            Self::Padding { at } => write!(
                f,
                "not base64: the padding at offset {at} does not end the last group of four"
            ),
            Self::Length { len } => write!(f, "not base64: no base64 text is {len} long"),
            Self::StrayBits { at, character } => write!(
                f,
                "not base64: the last digit, {character:?} at offset {at}, sets bits past the end of the data"
            ),
        }
    }
}

/// Decodes standard base64 as Python's `base64.standard_b64encode` (which rosbridge uses)
/// writes it. Padding may be left out; where present it must complete the last group. The
/// bits of the last digit past the end of the data must be zero, as every encoder writes
/// them: so each byte string is read from exactly one text, padding aside.
pub(crate) fn decode(text: &str) -> Result<Vec<u8>, Base64Error> {
    let engine = if text.ends_with('=') {
        PADDED
    } else {
        UNPADDED
    };
    // The character (not the byte) at an offset, for a message that shows what was sent.
    let at = |at: usize| {
        text.get(at..)
            .and_then(|rest| rest.chars().next())
            .unwrap_or(char::REPLACEMENT_CHARACTER)
    };
    engine.decode(text).map_err(|error| match error {
        DecodeError::InvalidByte(offset, b'=') => Base64Error::Padding { at: offset },
        DecodeError::InvalidByte(offset, _) => Base64Error::Character {
            at: offset,
            character: at(offset),
        },
        DecodeError::InvalidLastSymbol(offset, _) => Base64Error::StrayBits {
            at: offset,
            character: at(offset),
        },
        DecodeError::InvalidLength(_) | DecodeError::InvalidPadding => {
            Base64Error::Length { len: text.len() }
        }
    })
}

/// Encodes bytes as padded standard base64.
pub(crate) fn encode(bytes: &[u8]) -> String {
    PADDED.encode(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_encodings() {
        for (bytes, text) in [
            (&b""[..], ""),
            (b"f", "Zg=="),
            (b"fo", "Zm8="),
            (b"foo", "Zm9v"),
            (b"foob", "Zm9vYg=="),
            (b"fooba", "Zm9vYmE="),
            (b"foobar", "Zm9vYmFy"),
            (&[0xfb, 0xff, 0xbf], "+/+/"),
        ] {
            assert_eq!(encode(bytes), text);
            assert_eq!(decode(text).as_deref(), Ok(bytes));
            assert_eq!(decode(text.trim_end_matches('=')).as_deref(), Ok(bytes));
        }
        let uuid: Vec<u8> = (0..16).collect();
        assert_eq!(encode(&uuid), "AAECAwQFBgcICQoLDA0ODw==");
    }

    #[test]
    fn rejects_what_is_not_base64() {
        assert_eq!(
            decode("Zm9v!A=="),
            Err(Base64Error::Character {
                at: 4,
                character: '!'
            })
        );
        assert_eq!(
            decode("Zm\u{e9}v"),
            Err(Base64Error::Character {
                at: 2,
                character: '\u{e9}'
            })
        );
        for bad in ["Z", "Zm9vY", "Zg="] {
            assert_eq!(
                decode(bad),
                Err(Base64Error::Length { len: bad.len() }),
                "{bad}"
            );
        }
        for (bad, at) in [
            ("Zg===", 2),
            ("Z===", 1),
            ("=", 0),
            ("Zm9v=", 4),
            ("Zg==Zg==", 2),
        ] {
            assert_eq!(decode(bad), Err(Base64Error::Padding { at }), "{bad}");
        }
        // The bits past the data's end are zero: `Zg==` is "f", `Zh==` is nothing.
        for (bad, at, character) in [
            ("Zh==", 1, 'h'),
            ("Zh", 1, 'h'),
            ("Zm9=", 2, '9'),
            ("AAECAwQFBgcICQoLDA0ODx==", 21, 'x'),
        ] {
            assert_eq!(
                decode(bad),
                Err(Base64Error::StrayBits { at, character }),
                "{bad}"
            );
        }
        // URL-safe digits and whitespace are not in the standard alphabet.
        assert!(decode("Zm9-").is_err());
        assert!(decode("Zm9v Zm9v").is_err());
    }
}
