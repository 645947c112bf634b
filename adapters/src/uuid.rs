//! `unique_identifier_msgs/UUID`: the one UUID of every message this crate reads and writes,
//! the AD API's and the RTC interface's alike.
//!
//! A UUID is 16 bytes, and its type says so: a message with a UUID of another length does not
//! read, and the error names the field (`commands[0].uuid.uuid: a UUID has 16 bytes, not 15`).
//! In JSON it is written as 16 numbers and read from 16 numbers or from the base64 string
//! rosbridge writes for `uint8` arrays (`crate::base64`: standard alphabet, `=` padding
//! optional, no stray bits). As in ROS, its default is 16 zeros, and a UUID message without its
//! field (`{}`, or `[]` in the list form) reads as that default, as rosbridge fills it.

use core::fmt;

use cooperation::SceneId;
use serde::de::{Error, IgnoredAny, SeqAccess, Visitor};

use crate::base64;

/// A UUID (`unique_identifier_msgs/UUID`, a `uint8[16]`).
#[derive(
    Clone,
    Copy,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    Debug,
    Default,
    serde::Serialize,
    serde::Deserialize,
)]
#[serde(default, deny_unknown_fields)]
pub struct Uuid {
    /// The 16 bytes, most significant first. In JSON an array of 16 numbers; a base64 string of
    /// 16 bytes (rosbridge's encoding of `uint8` arrays) is accepted when reading.
    #[serde(deserialize_with = "sixteen_bytes")]
    pub uuid: [u8; 16],
}

impl Uuid {
    /// The bytes as rosbridge writes a `uint8` array: padded standard base64.
    #[must_use]
    pub fn to_base64(&self) -> String {
        base64::encode(&self.uuid)
    }
}

impl From<SceneId> for Uuid {
    fn from(id: SceneId) -> Self {
        Self {
            uuid: id.to_bytes(),
        }
    }
}

impl From<Uuid> for SceneId {
    fn from(uuid: Uuid) -> Self {
        Self::from_bytes(uuid.uuid)
    }
}

impl From<&Uuid> for SceneId {
    fn from(uuid: &Uuid) -> Self {
        Self::from_bytes(uuid.uuid)
    }
}

/// Reads the 16 bytes: from whichever form a text format holds (numbers or base64), or, from a
/// binary one such as CDR, as the fixed array they are.
fn sixteen_bytes<'de, D: serde::Deserializer<'de>>(deserializer: D) -> Result<[u8; 16], D::Error> {
    if deserializer.is_human_readable() {
        deserializer.deserialize_any(SixteenBytes)
    } else {
        deserializer.deserialize_tuple(16, SixteenBytes)
    }
}

/// The refusal of `len` bytes where a UUID has 16.
fn wrong_length<E: Error>(len: usize) -> E {
    E::custom(format_args!("a UUID has 16 bytes, not {len}"))
}

fn exactly_sixteen<E: Error>(bytes: &[u8]) -> Result<[u8; 16], E> {
    bytes.try_into().map_err(|_| wrong_length(bytes.len()))
}

struct SixteenBytes;

impl<'de> Visitor<'de> for SixteenBytes {
    type Value = [u8; 16];

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("16 bytes: an array of 16 numbers from 0 to 255, or a base64 string")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut bytes = [0; 16];
        let mut len = 0;
        while let Some(byte) = seq.next_element::<u8>()? {
            if let Some(slot) = bytes.get_mut(len) {
                *slot = byte;
            }
            len += 1;
            if len > 16 {
                // Count the rest for the message; they cost the sender, not the reader.
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    len += 1;
                }
            }
        }
        if len == 16 {
            Ok(bytes)
        } else {
            Err(wrong_length(len))
        }
    }

    fn visit_str<E: Error>(self, text: &str) -> Result<Self::Value, E> {
        exactly_sixteen(&base64::decode(text).map_err(E::custom)?)
    }

    fn visit_bytes<E: Error>(self, bytes: &[u8]) -> Result<Self::Value, E> {
        exactly_sixteen(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::Uuid;

    fn read(uuid: serde_json::Value) -> Result<[u8; 16], String> {
        serde_json::from_value::<Uuid>(serde_json::json!({ "uuid": uuid }))
            .map(|uuid| uuid.uuid)
            .map_err(|error| error.to_string())
    }

    #[test]
    fn sixteen_numbers_or_base64_of_sixteen_bytes() {
        let bytes: [u8; 16] = core::array::from_fn(|i| u8::try_from(i * 17).unwrap());
        assert_eq!(read(serde_json::json!(bytes)), Ok(bytes));
        // The standard encoding of 00 11 22 … ff, with and without its padding.
        assert_eq!(read("ABEiM0RVZneImaq7zN3u/w==".into()), Ok(bytes));
        assert_eq!(read("ABEiM0RVZneImaq7zN3u/w".into()), Ok(bytes));
        assert!(read("ABEiM0RVZneImaq7zN3u/x==".into())
            .unwrap_err()
            .contains("sets bits past the end"));
        assert!(read("ABEiM0RVZneImaq7zN3u-w==".into())
            .unwrap_err()
            .contains("outside the standard alphabet"));
    }

    #[test]
    fn another_length_is_refused_with_its_length() {
        for (uuid, len) in [
            (serde_json::json!([]), 0),
            (serde_json::json!([1_u8; 15].to_vec()), 15),
            (serde_json::json!([1_u8; 17].to_vec()), 17),
            (serde_json::json!([1_u8; 40].to_vec()), 40),
            (serde_json::json!("AAECAwQFBgcICQoL"), 12),
            (serde_json::json!(""), 0),
        ] {
            assert_eq!(
                read(uuid),
                Err(format!("a UUID has 16 bytes, not {len}")),
                "{len}"
            );
        }
        assert!(read(serde_json::json!([1, 256])).is_err());
        assert!(read(serde_json::json!(7)).is_err());
    }
}
