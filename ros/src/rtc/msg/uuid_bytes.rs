//! A UUID's bytes in JSON: an array of 16 numbers, or rosbridge's base64 string.

use core::fmt;

use serde::de::{Error, SeqAccess, Visitor};

pub(super) fn deserialize<'de, D: serde::Deserializer<'de>>(
    deserializer: D,
) -> Result<[u8; 16], D::Error> {
    deserializer.deserialize_any(Bytes)
}

struct Bytes;

impl<'de> Visitor<'de> for Bytes {
    type Value = [u8; 16];

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("16 bytes: an array of 16 numbers from 0 to 255, or a base64 string")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut bytes = [0; 16];
        for (index, byte) in bytes.iter_mut().enumerate() {
            *byte = seq
                .next_element()?
                .ok_or_else(|| A::Error::invalid_length(index, &self))?;
        }
        if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
            return Err(A::Error::invalid_length(17, &self));
        }
        Ok(bytes)
    }

    fn visit_str<E: Error>(self, text: &str) -> Result<Self::Value, E> {
        let bytes = crate::base64::decode(text).map_err(E::custom)?;
        let len = bytes.len();
        bytes
            .try_into()
            .map_err(|_| E::custom(format_args!("base64 of {len} bytes, where a UUID has 16")))
    }
}

#[cfg(test)]
mod tests {
    /// The 16 bytes a base64 string gives, if it is one.
    fn decode_base64(text: &str) -> Option<[u8; 16]> {
        serde_json::from_value::<super::super::Uuid>(serde_json::json!({ "uuid": text }))
            .ok()
            .map(|uuid| uuid.uuid)
    }

    #[test]
    fn base64_of_16_bytes() {
        let bytes: [u8; 16] = core::array::from_fn(|i| u8::try_from(i * 17).unwrap());
        // The standard encoding of 00 11 22 … ff.
        assert_eq!(decode_base64("ABEiM0RVZneImaq7zN3u/w=="), Some(bytes));
        assert_eq!(decode_base64("ABEiM0RVZneImaq7zN3u/w"), Some(bytes));
        assert_eq!(
            decode_base64("ABEiM0RVZneImaq7zN3u/x=="),
            None,
            "stray low bits"
        );
        assert_eq!(decode_base64("ABEiM0RVZneImaq7zN3u/w="), None);
        assert_eq!(decode_base64("ABEiM0RVZneImaq7zN3u-w=="), None);
        assert_eq!(decode_base64(""), None);
    }
}
