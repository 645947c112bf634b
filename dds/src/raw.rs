//! Samples as bytes: the node writes and reads CDR through `cooperation_adapters::cdr` (the form the
//! golden tests check against Cyclone DDS), never through the DDS library's own serializer.
//!
//! rustdds takes the encapsulation header off a sample it receives and puts one on a sample it
//! sends; [`Raw`] holds the whole sample, header included, as `cooperation_adapters::cdr` reads and
//! writes it.

use std::io;

use cooperation_adapters::cdr::CDR_LE;
use rustdds::bytes::Bytes;
use rustdds::no_key::{Decode, DefaultDecoder, DeserializerAdapter, SerializerAdapter};
use rustdds::RepresentationIdentifier;

/// One sample in little-endian plain CDR: the four-byte encapsulation header, then the data.
#[derive(Clone, PartialEq, Eq, Debug, Default)]
pub struct Raw(pub Vec<u8>);

/// The adapter between [`Raw`] and rustdds, both ways.
#[derive(Clone, Copy, Debug)]
pub struct RawAdapter;

impl SerializerAdapter<Raw> for RawAdapter {
    type Error = io::Error;

    fn output_encoding() -> RepresentationIdentifier {
        RepresentationIdentifier::CDR_LE
    }

    fn to_bytes(value: &Raw) -> Result<Bytes, io::Error> {
        match value.0.split_at_checked(CDR_LE.len()) {
            Some((header, data)) if header == CDR_LE => Ok(Bytes::copy_from_slice(data)),
            _ => Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "a sample to send is not little-endian plain CDR",
            )),
        }
    }
}

impl DeserializerAdapter<Raw> for RawAdapter {
    type Error = io::Error;
    type Decoded = Raw;

    fn supported_encodings() -> &'static [RepresentationIdentifier] {
        &[RepresentationIdentifier::CDR_LE]
    }

    fn transform_decoded(decoded: Raw) -> Raw {
        decoded
    }
}

impl DefaultDecoder<Raw> for RawAdapter {
    type Decoder = RawDecoder;
    const DECODER: RawDecoder = RawDecoder;
}

/// Puts the encapsulation header back on a received sample.
#[derive(Clone, Copy, Debug)]
pub struct RawDecoder;

impl Decode<'_, Raw> for RawDecoder {
    type Error = io::Error;

    fn decode_bytes(
        self,
        input_bytes: &[u8],
        encoding: RepresentationIdentifier,
    ) -> Result<Raw, io::Error> {
        if encoding != RepresentationIdentifier::CDR_LE {
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!("a sample in {encoding:?}, not little-endian plain CDR"),
            ));
        }
        let mut sample = Vec::with_capacity(CDR_LE.len() + input_bytes.len());
        sample.extend_from_slice(&CDR_LE);
        sample.extend_from_slice(input_bytes);
        Ok(Raw(sample))
    }
}
