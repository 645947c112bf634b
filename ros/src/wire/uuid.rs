//! The two JSON forms of a `uint8` array: a list of numbers, or rosbridge's base64 string.

use core::fmt;

use serde::de::{Deserializer, Error, SeqAccess, Visitor};

use super::Uuid;
use crate::base64;

/// Reads a `uint8` array from a list of numbers (each 0 to 255), a base64 string (standard
/// alphabet, `=` padding optional, no
/// stray bits: [`crate::base64::decode`]), or serde bytes.
pub(super) fn bytes_or_base64<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<u8>, D::Error> {
    deserializer.deserialize_any(BytesOrBase64)
}

struct BytesOrBase64;

impl<'de> Visitor<'de> for BytesOrBase64 {
    type Value = Vec<u8>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a list of numbers from 0 to 255, or a base64 string")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<u8>, A::Error> {
        // Never trust a length hint beyond what a UUID needs: the input pays for the rest.
        let mut bytes = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(16));
        while let Some(byte) = seq.next_element::<u8>()? {
            bytes.push(byte);
        }
        Ok(bytes)
    }

    fn visit_str<E: Error>(self, text: &str) -> Result<Vec<u8>, E> {
        base64::decode(text).map_err(E::custom)
    }

    fn visit_bytes<E: Error>(self, bytes: &[u8]) -> Result<Vec<u8>, E> {
        Ok(bytes.to_vec())
    }

    fn visit_byte_buf<E: Error>(self, bytes: Vec<u8>) -> Result<Vec<u8>, E> {
        Ok(bytes)
    }
}

impl Uuid {
    /// The bytes as rosbridge writes a `uint8` array: padded standard base64.
    #[must_use]
    pub fn to_base64(&self) -> String {
        base64::encode(&self.uuid)
    }
}
