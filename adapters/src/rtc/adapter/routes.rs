//! Which interface each scene registered through: a hash map keyed by scene identifier, hashed
//! by [`SceneId::spread`] as the core's scene table is, so that a query or a command finds its
//! scene's interface in a probe or two rather than a search of an ordered tree.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use cooperation::SceneId;

/// The interface (an index into the adapter's bindings) each scene registered through.
pub(crate) type Routes = HashMap<SceneId, usize, BuildHasherDefault<SpreadHasher>>;

/// Hashes a [`SceneId`] by [`SceneId::spread`]: the identifier writes its two halves, most
/// significant first, and the hash is theirs. Bytes written otherwise are folded into the
/// halves, so any key still hashes; only identifiers are keyed here.
#[derive(Default)]
pub(crate) struct SpreadHasher {
    halves: [u64; 2],
    written: usize,
}

impl Hasher for SpreadHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0_u8; 8];
            word.iter_mut()
                .zip(chunk)
                .for_each(|(to, from)| *to = *from);
            self.write_u64(u64::from_be_bytes(word));
        }
    }

    fn write_u64(&mut self, word: u64) {
        let [high, low] = &mut self.halves;
        if self.written % 2 == 0 {
            *high ^= word;
        } else {
            *low ^= word;
        }
        self.written += 1;
    }

    fn finish(&self) -> u64 {
        let [high, low] = self.halves;
        SceneId::from_u128((u128::from(high) << 64) | u128::from(low)).spread()
    }
}

#[cfg(test)]
mod tests {
    use std::hash::BuildHasher;

    use super::*;

    /// An identifier hashes to its spread, so the routes and the core's table agree on what
    /// is cheap to find.
    #[test]
    fn an_identifier_hashes_to_its_spread() {
        let hasher = BuildHasherDefault::<SpreadHasher>::default();
        for value in [0, 1, u128::MAX, 0x0123_4567_89ab_cdef_fedc_ba98_7654_3210] {
            let id = SceneId::from_u128(value);
            assert_eq!(hasher.hash_one(id), id.spread(), "{id}");
        }
    }
}
