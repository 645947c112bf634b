//! Which interface each scene registered through ([`Routes`]), and each interface's scenes in
//! identifier order, so that an interface's calls walk its own scenes rather than every live
//! scene of the core.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::Arc;

use cooperation::{Scene, SceneId, State, Transition};

/// The routes: for each identifier registered through an interface, which interface (an index
/// into the adapter's bindings), hashed by [`SceneId::spread`] as the core's scene table is, so
/// that a query or a command finds its scene's interface in a probe or two rather than a search
/// of an ordered tree. Beside them, each interface's identifiers in identifier order
/// (`members`), which its calls walk.
///
/// An interface's list holds every live scene that registered through it, and may hold
/// identifiers that are no longer live. The adapter drops an identifier from it when a call it
/// makes retires the scene; one retired by an input the adapter did not make (a host's own
/// `Tick` or `Remove` to the core) stays until a later call finds more identifiers listed than
/// the core has live scenes ([`settle`](Self::settle)). Every walk skips identifiers that are
/// not live, so what a list holds besides changes no answer, only how long an answer takes; and
/// equality reads the routes alone.
#[derive(Clone, Debug)]
pub(crate) struct Routes {
    by_id: HashMap<SceneId, usize, BuildHasherDefault<SpreadHasher>>,
    /// Each interface's identifiers, by index, sorted and distinct; no identifier in two lists.
    /// Shared between copies until one registers or retires a scene: a model checker copies
    /// the adapter for every call it makes, and most calls do neither.
    members: Arc<Vec<Vec<SceneId>>>,
    /// How many identifiers the lists hold together.
    listed: usize,
}

impl Routes {
    /// No routes, for an adapter of `interfaces` interfaces.
    pub(crate) fn new(interfaces: usize) -> Self {
        Self {
            by_id: HashMap::default(),
            members: Arc::new(vec![Vec::new(); interfaces]),
            listed: 0,
        }
    }

    /// The interface `id` registered through, if the route is kept.
    pub(crate) fn get(&self, id: &SceneId) -> Option<&usize> {
        self.by_id.get(id)
    }

    /// How many routes are kept.
    pub(crate) fn len(&self) -> usize {
        self.by_id.len()
    }

    /// Routes `id`, registered through interface `index`; listed there if it is live in `state`.
    pub(crate) fn insert(&mut self, id: SceneId, index: usize, state: &State) {
        if let Some(previous) = self.by_id.insert(id, index) {
            if previous != index {
                self.unlist(previous, id);
            }
        }
        if state.scene(id).is_none() {
            return;
        }
        let Some(Err(at)) = self.members.get(index).map(|list| list.binary_search(&id)) else {
            return;
        };
        if let Some(list) = Arc::make_mut(&mut self.members).get_mut(index) {
            list.insert(at, id);
            self.listed += 1;
        }
    }

    /// Drops `id` from interface `index`'s list, if it is there.
    fn unlist(&mut self, index: usize, id: SceneId) {
        let Some(Ok(at)) = self.members.get(index).map(|list| list.binary_search(&id)) else {
            return;
        };
        if let Some(list) = Arc::make_mut(&mut self.members).get_mut(index) {
            list.remove(at);
            self.listed -= 1;
        }
    }

    /// Drops from the lists the identifiers `transitions` retired.
    pub(crate) fn retired<'t>(&mut self, transitions: impl IntoIterator<Item = &'t Transition>) {
        for id in transitions
            .into_iter()
            .flat_map(|transition| &transition.retired)
        {
            if let Some(&index) = self.by_id.get(id) {
                self.unlist(index, *id);
            }
        }
    }

    /// Drops the identifiers that are no longer live from the lists, if they list more
    /// identifiers than `state` has live scenes: some scene was retired by an input the adapter
    /// did not make. So once this has run, the lists hold no more identifiers that are not live
    /// than the core holds live scenes on no list (scenes registered past the adapter).
    pub(crate) fn settle(&mut self, state: &State) {
        if self.listed > state.scene_count() {
            self.sweep(state);
        }
    }

    /// Drops the identifiers that are no longer live from the lists.
    fn sweep(&mut self, state: &State) {
        let live = |id: &SceneId| state.scene(*id).is_some();
        if self.members.iter().flatten().all(live) {
            return;
        }
        for list in Arc::make_mut(&mut self.members).iter_mut() {
            list.retain(live);
        }
        self.listed = self.members.iter().map(Vec::len).sum();
    }

    /// Forgets the routes of identifiers `state` no longer remembers, once they could outnumber
    /// the live and retired identifiers; so the routes never hold more than the core can
    /// remember plus one.
    pub(crate) fn prune(&mut self, state: &State) {
        let remembered = state
            .scene_count()
            .saturating_add(state.limits().retired_capacity);
        if self.by_id.len() > remembered {
            self.by_id
                .retain(|id, _| state.scene(*id).is_some() || state.retirement(*id).is_some());
            self.sweep(state);
        }
    }

    /// Interface `index`'s live scenes in `state`, in identifier order: its list's identifiers
    /// found in the core one by one, so that the walk costs a look-up for each of the
    /// interface's scenes whatever the core holds besides.
    pub(crate) fn scenes<'a>(
        &'a self,
        index: usize,
        state: &'a State,
    ) -> impl Iterator<Item = (SceneId, &'a Scene)> + 'a {
        let list = self.members.get(index).map_or(&[][..], Vec::as_slice);
        list.iter()
            .filter_map(move |id| state.scene(*id).map(|scene| (*id, scene)))
    }
}

impl PartialEq for Routes {
    /// The routes alone: the lists follow from them and the core.
    fn eq(&self, other: &Self) -> bool {
        self.by_id == other.by_id
    }
}

impl Eq for Routes {}

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
