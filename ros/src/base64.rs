//! Standard base64 (RFC 4648, `A–Z a–z 0–9 + /`) for `uint8` arrays in rosbridge JSON: one
//! decoder for every message that carries bytes as text, so every reader accepts the same
//! strings.

use core::fmt;

/// A string that is not base64.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Base64Error {
    /// A character outside the standard alphabet (`A–Z a–z 0–9 + /`), at this byte offset.
    Character { at: usize, character: char },
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
            Self::Length { len } => write!(f, "not base64: no base64 text is {len} long"),
            Self::StrayBits { at, character } => write!(
                f,
                "not base64: the last digit, {character:?} at offset {at}, sets bits past the end of the data"
            ),
        }
    }
}

/// The value of one base64 digit.
const fn sextet(c: u8) -> Option<u8> {
    match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    }
}

/// The base64 digit of the low six bits of `value`.
const fn digit(value: u32) -> char {
    // Always below 64, so every arm's result is in its range.
    let value = (value & 0x3f) as u8;
    (match value {
        0..=25 => b'A' + value,
        26..=51 => b'a' + (value - 26),
        52..=61 => b'0' + (value - 52),
        62 => b'+',
        _ => b'/',
    }) as char
}

/// Decodes standard base64 as Python's `base64.standard_b64encode` (which rosbridge uses)
/// writes it. Padding may be left out; where present it must complete the last group. The
/// bits of the last digit past the end of the data must be zero, as every encoder writes
/// them: so each byte string is read from exactly one text, padding aside.
pub(crate) fn decode(text: &str) -> Result<Vec<u8>, Base64Error> {
    let unpadded = text.trim_end_matches('=');
    let padding = text.len() - unpadded.len();
    let mut bytes = Vec::with_capacity(unpadded.len() / 4 * 3 + 2);
    let mut buffer: u32 = 0;
    let mut bits = 0;
    for (at, c) in unpadded.bytes().enumerate() {
        let value = sextet(c).ok_or_else(|| Base64Error::Character {
            at,
            character: unpadded
                .get(at..)
                .and_then(|rest| rest.chars().next())
                .unwrap_or(char::REPLACEMENT_CHARACTER),
        })?;
        buffer = (buffer << 6) | u32::from(value);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            // `buffer` holds `bits + 8` bits, so this is the next whole byte.
            bytes.push((buffer >> bits) as u8);
            buffer &= (1 << bits) - 1;
        }
    }
    if unpadded.len() % 4 == 1 || (padding > 0 && (padding > 2 || text.len() % 4 != 0)) {
        return Err(Base64Error::Length { len: text.len() });
    }
    if buffer != 0 {
        let at = unpadded.len().saturating_sub(1);
        return Err(Base64Error::StrayBits {
            at,
            character: unpadded
                .get(at..)
                .and_then(|rest| rest.chars().next())
                .unwrap_or('?'),
        });
    }
    Ok(bytes)
}

/// Encodes bytes as padded standard base64.
pub(crate) fn encode(bytes: &[u8]) -> String {
    let mut text = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for group in bytes.chunks(3) {
        let mut padded = [0; 3];
        for (slot, byte) in padded.iter_mut().zip(group) {
            *slot = *byte;
        }
        let [a, b, c] = padded;
        let word = u32::from_be_bytes([0, a, b, c]);
        let digits = group.len() + 1;
        for shift in [18, 12, 6, 0].into_iter().take(digits) {
            text.push(digit(word >> shift));
        }
        for _ in digits..4 {
            text.push('=');
        }
    }
    text
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
        for bad in ["Z", "Zm9vY", "Zg=", "Zg===", "Z===", "=", "Zm9v="] {
            assert_eq!(
                decode(bad),
                Err(Base64Error::Length { len: bad.len() }),
                "{bad}"
            );
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
