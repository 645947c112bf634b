//! The live scenes' table: found by identifier in constant time, walked in identifier order.
//!
//! A planner updates every live scene once a cycle and asks for its merged decision, so the
//! search by identifier is the hot path; the status list is produced in identifier order, and
//! a model checker clones, compares and hashes the state for every transition. The table
//! serves all three:
//!
//! - **Small** (at most [`SMALL`] entries, every state a model checker sees): one vector sorted
//!   by identifier, searched by scanning it. A clone is one allocation.
//! - **Large**: the entries stay where they were put (a removal moves the last entry into the
//!   gap), an open-addressing hash index finds an entry's position, and a vector of positions
//!   keeps the identifier order. A search costs one hash and, on average, under two probes at
//!   any size.
//!
//! Equality and hashing see only the entries in identifier order, never the layout: two tables
//! with the same entries are equal, whatever happened to them before.
//!
//! [`TableLayout::Colliding`] makes every table large from its first entry, under a hash that
//! sends identifiers to two buckets at the end of a small index: the model checker uses it to
//! explore probing, wrap-around deletion and index rebuilds with a handful of scenes. The
//! layout is invisible to equality, hashing, iteration and every rule.
//!
//! The hash is fixed and not keyed: the core draws no random numbers. Identifiers are chosen by
//! scene owners, which draw random UUIDs; owners that chose identifiers to collide would make
//! searches slower (at worst a scan of the live scenes, the cost of the linear registry the
//! benchmarks compare against), never wrong.

use core::fmt;
use core::hash::{Hash, Hasher};

use crate::SceneId;

/// The most entries kept as a sorted vector without an index.
pub(crate) const SMALL: usize = 16;

/// A bucket of the index that holds no position.
const EMPTY: usize = usize::MAX;

/// How a state's table of live scenes is laid out. No rule, query or comparison can tell the
/// layouts apart; only speed differs.
///
/// A hook for the model checker, public with the `verification` feature only: planners always
/// get [`TableLayout::Adaptive`].
#[cfg_attr(not(feature = "verification"), allow(unreachable_pub, dead_code))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum TableLayout {
    /// A sorted vector while at most 16 scenes are live, then a hash index: what planners use.
    #[default]
    Adaptive,
    /// A hash index from the first scene, under a hash that sends every identifier to one of
    /// the two last buckets of an index that starts with two buckets and doubles as it fills.
    /// Slow, and there for verification: with a handful of scenes, every search probes, every
    /// cluster wraps round the end of the index, and removals shift entries across it.
    Colliding,
}

/// The fewest buckets an index has: two, so that [`TableLayout::Colliding`]'s two last buckets
/// are distinct. An adaptive index starts past 16 entries, so with at least 32 buckets anyway.
const MIN_BUCKETS: usize = 2;

/// What a layout means to the table: when the index starts and how it hashes.
#[derive(Clone, Copy)]
struct Layout {
    /// The most entries kept as a sorted vector without an index.
    small: usize,
    /// The hash of an identifier; its low bits pick the bucket.
    hash: fn(SceneId) -> u64,
    /// The layout this stands for.
    #[cfg_attr(not(feature = "verification"), allow(dead_code))]
    name: TableLayout,
}

impl Layout {
    const fn of(layout: TableLayout) -> Self {
        match layout {
            TableLayout::Adaptive => Self {
                small: SMALL,
                hash: spread,
                name: layout,
            },
            TableLayout::Colliding => Self {
                small: 0,
                hash: colliding,
                name: layout,
            },
        }
    }
}

/// The table's hash of an identifier ([`SceneId::spread`]).
const fn spread(id: SceneId) -> u64 {
    id.spread()
}

/// [`TableLayout::Colliding`]'s hash: one of the two last buckets of any index.
fn colliding(id: SceneId) -> u64 {
    u64::MAX - (spread(id) & 1)
}

/// A map from scene identifiers to values, ordered by identifier.
#[derive(Clone)]
pub(crate) struct IdTable<V> {
    /// The entries: sorted by identifier while the table is small, in no particular order once
    /// it is large.
    entries: Vec<(SceneId, V)>,
    /// Large only: every position in `entries`, in identifier order. Empty while small.
    order: Vec<usize>,
    /// Large only: the hash index, from identifier to position in `entries`. Linear probing,
    /// a power-of-two length, at most half full, so a probe always ends at an empty bucket.
    /// Empty while small; once built it stays, whatever the table shrinks to.
    index: Vec<usize>,
    /// When the index starts and how it hashes.
    layout: Layout,
}

/// Where a probe of the index ended.
enum Probe {
    /// The bucket that holds the identifier.
    Found(usize),
    /// The empty bucket where the identifier would go.
    Vacant(usize),
    /// Every bucket was full and none matched: impossible while the index is at most half full,
    /// and handled all the same.
    Full,
}

impl<V> IdTable<V> {
    /// An empty table with the default layout.
    pub(crate) const fn new() -> Self {
        Self::with_layout(TableLayout::Adaptive)
    }

    /// An empty table laid out as `layout` says.
    pub(crate) const fn with_layout(layout: TableLayout) -> Self {
        Self::with(Layout::of(layout))
    }

    const fn with(layout: Layout) -> Self {
        Self {
            entries: Vec::new(),
            order: Vec::new(),
            index: Vec::new(),
            layout,
        }
    }

    /// The layout.
    #[cfg(feature = "verification")]
    pub(crate) const fn layout(&self) -> TableLayout {
        self.layout.name
    }

    /// The same entries laid out as `layout` says.
    #[cfg(any(test, feature = "verification"))]
    pub(crate) fn relaid(self, layout: TableLayout) -> Self {
        let mut table = Self::with_layout(layout);
        for (id, value) in self {
            table.insert(id, value);
        }
        table
    }

    /// A table of these entries, laid out as this one; of two with one identifier, the later
    /// one stays.
    #[cfg(feature = "verification")]
    pub(crate) fn like(&self, entries: impl IntoIterator<Item = (SceneId, V)>) -> Self {
        let mut table = Self::with(self.layout);
        for (id, value) in entries {
            table.insert(id, value);
        }
        table
    }

    fn hash_of(&self, id: SceneId) -> u64 {
        (self.layout.hash)(id)
    }

    /// How many entries there are.
    pub(crate) fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the table has grown its index.
    fn is_large(&self) -> bool {
        !self.index.is_empty()
    }

    /// The identifier at `position` of `entries`.
    fn id_at(&self, position: usize) -> Option<SceneId> {
        self.entries.get(position).map(|(id, _)| *id)
    }

    /// The bucket where a probe for `hash` starts.
    fn home(&self, hash: u64) -> usize {
        (hash as usize) & self.index.len().wrapping_sub(1)
    }

    /// Probes the index from `hash`'s home bucket for a position `is_it` accepts.
    fn probe(&self, hash: u64, is_it: impl Fn(usize) -> bool) -> Probe {
        let mask = self.index.len().wrapping_sub(1);
        let mut bucket = self.home(hash);
        // At most half the buckets are full, so the loop meets an empty one long before it
        // has gone round; the bound only makes that visible.
        for _ in 0..self.index.len() {
            match self.index.get(bucket) {
                Some(&position) if position != EMPTY => {
                    if is_it(position) {
                        return Probe::Found(bucket);
                    }
                }
                _ => return Probe::Vacant(bucket),
            }
            bucket = (bucket + 1) & mask;
        }
        Probe::Full
    }

    /// The position of `id` in `entries`.
    pub(crate) fn position(&self, id: SceneId) -> Option<usize> {
        if !self.is_large() {
            return self.entries.iter().position(|(key, _)| *key == id);
        }
        match self.probe(self.hash_of(id), |position| {
            self.id_at(position) == Some(id)
        }) {
            Probe::Found(bucket) => self.index.get(bucket).copied(),
            Probe::Vacant(_) | Probe::Full => None,
        }
    }

    /// The value of `id`.
    pub(crate) fn get(&self, id: SceneId) -> Option<&V> {
        self.position(id)
            .and_then(|position| self.value_at(position))
    }

    /// The value of `id`, to change.
    pub(crate) fn get_mut(&mut self, id: SceneId) -> Option<&mut V> {
        let position = self.position(id)?;
        self.value_at_mut(position)
    }

    /// The value at a position [`position`](Self::position) returned, with no change since.
    pub(crate) fn value_at(&self, position: usize) -> Option<&V> {
        self.entries.get(position).map(|(_, value)| value)
    }

    /// The value at a position [`position`](Self::position) returned, with no change since, to
    /// change.
    pub(crate) fn value_at_mut(&mut self, position: usize) -> Option<&mut V> {
        self.entries.get_mut(position).map(|(_, value)| value)
    }

    /// The entry at `position`, the place [`iter_unordered`](Self::iter_unordered) gives it.
    pub(crate) fn entry_at(&self, position: usize) -> Option<(SceneId, &V)> {
        self.entries.get(position).map(|(id, value)| (*id, value))
    }

    /// Where `id` is, or would go, in the identifier order (large tables only).
    fn rank(&self, id: SceneId) -> Result<usize, usize> {
        self.order
            .binary_search_by(|&position| self.id_at(position).cmp(&Some(id)))
    }

    /// Adds an entry, or replaces the value of an existing one and returns the old value.
    pub(crate) fn insert(&mut self, id: SceneId, value: V) -> Option<V> {
        if let Some(old) = self.get_mut(id) {
            return Some(core::mem::replace(old, value));
        }
        if !self.is_large() && self.entries.len() < self.layout.small {
            let at = self
                .entries
                .binary_search_by(|(key, _)| key.cmp(&id))
                .unwrap_or_else(|at| at);
            self.entries.insert(at, (id, value));
            return None;
        }
        if !self.is_large() {
            // The sorted entries give the identifier order as it stands.
            self.order = (0..self.entries.len()).collect();
        }
        let position = self.entries.len();
        self.entries.push((id, value));
        let rank = self.rank(id).unwrap_or_else(|rank| rank);
        self.order.insert(rank, position);
        match self.probe(self.hash_of(id), |_| false) {
            Probe::Vacant(bucket) if self.entries.len() * 2 <= self.index.len() => {
                if let Some(slot) = self.index.get_mut(bucket) {
                    *slot = position;
                }
            }
            _ => self.rebuild_index(),
        }
        None
    }

    /// Builds the index afresh, with at least twice as many buckets as entries.
    fn rebuild_index(&mut self) {
        let buckets = (self.entries.len() * 2)
            .next_power_of_two()
            .max(MIN_BUCKETS);
        self.index = vec![EMPTY; buckets];
        for position in 0..self.entries.len() {
            let Some(id) = self.id_at(position) else {
                continue;
            };
            if let Probe::Vacant(bucket) = self.probe(self.hash_of(id), |_| false) {
                if let Some(slot) = self.index.get_mut(bucket) {
                    *slot = position;
                }
            }
        }
    }

    /// Removes `id`'s entry and returns its value.
    pub(crate) fn remove(&mut self, id: SceneId) -> Option<V> {
        let position = self.position(id)?;
        if !self.is_large() {
            return Some(self.entries.remove(position).1);
        }
        if let Ok(rank) = self.rank(id) {
            self.order.remove(rank);
        }
        if let Probe::Found(bucket) = self.probe(self.hash_of(id), |at| at == position) {
            self.vacate(bucket);
        }
        let last = self.entries.len() - 1;
        if position != last {
            // The last entry will move into the gap: point its place in the order and its
            // bucket at its new position, while its old position still names it.
            if let Some(moved) = self.id_at(last) {
                if let Ok(rank) = self.rank(moved) {
                    if let Some(slot) = self.order.get_mut(rank) {
                        *slot = position;
                    }
                }
                if let Probe::Found(bucket) = self.probe(self.hash_of(moved), |at| at == last) {
                    if let Some(slot) = self.index.get_mut(bucket) {
                        *slot = position;
                    }
                }
            }
        }
        let (_, value) = self.entries.swap_remove(position);
        Some(value)
    }

    /// Empties `bucket`, shifting back the entries after it that probing would otherwise no
    /// longer reach (deletion without tombstones for linear probing).
    fn vacate(&mut self, bucket: usize) {
        let mask = self.index.len().wrapping_sub(1);
        let mut hole = bucket;
        let mut next = (hole + 1) & mask;
        for _ in 0..self.index.len() {
            let Some(&position) = self.index.get(next) else {
                break;
            };
            let Some(id) = self.id_at(position) else {
                break; // `EMPTY`: the run of full buckets ends here.
            };
            let home = self.home(self.hash_of(id));
            // The entry may fill the hole if the hole lies between its home and where it is.
            if next.wrapping_sub(home) & mask >= next.wrapping_sub(hole) & mask {
                if let Some(slot) = self.index.get_mut(hole) {
                    *slot = position;
                }
                hole = next;
            }
            next = (next + 1) & mask;
        }
        if let Some(slot) = self.index.get_mut(hole) {
            *slot = EMPTY;
        }
    }

    /// Every entry, in identifier order.
    pub(crate) fn iter(&self) -> Iter<'_, V> {
        Iter {
            table: self,
            rank: 0,
        }
    }

    /// Every entry, in no particular order: for work whose result does not depend on it.
    pub(crate) fn iter_unordered(&self) -> impl Iterator<Item = (SceneId, &V)> + '_ {
        self.entries.iter().map(|(id, value)| (*id, value))
    }

    /// Every value, in no particular order, to change.
    pub(crate) fn values_mut(&mut self) -> impl Iterator<Item = &mut V> + '_ {
        self.entries.iter_mut().map(|(_, value)| value)
    }

    /// Whether the layout is sound: the order and the index each name every entry once, and
    /// the index finds each at its position. For tests.
    #[cfg(test)]
    fn is_consistent(&self) -> bool {
        if !self.is_large() {
            return self.order.is_empty()
                && self.entries.windows(2).all(|pair| match pair {
                    [(a, _), (b, _)] => a < b,
                    _ => false,
                });
        }
        let ordered = self.order.len() == self.entries.len()
            && self.order.windows(2).all(|pair| match pair {
                [a, b] => self.id_at(*a) < self.id_at(*b),
                _ => false,
            })
            && self.order.iter().all(|&at| at < self.entries.len());
        let indexed = self.index.iter().filter(|&&at| at != EMPTY).count() == self.entries.len()
            && self.entries.len() * 2 <= self.index.len()
            && self
                .entries
                .iter()
                .enumerate()
                .all(|(at, (id, _))| self.position(*id) == Some(at));
        ordered && indexed
    }
}

impl<V> Default for IdTable<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V> FromIterator<(SceneId, V)> for IdTable<V> {
    /// A table of these entries; of two with one identifier, the later one stays.
    fn from_iter<I: IntoIterator<Item = (SceneId, V)>>(entries: I) -> Self {
        let mut table = Self::new();
        for (id, value) in entries {
            table.insert(id, value);
        }
        table
    }
}

impl<V> IntoIterator for IdTable<V> {
    type Item = (SceneId, V);
    type IntoIter = std::vec::IntoIter<(SceneId, V)>;

    /// Every entry, in identifier order.
    fn into_iter(self) -> Self::IntoIter {
        let Self { entries, order, .. } = self;
        if order.is_empty() {
            return entries.into_iter();
        }
        let mut slots: Vec<Option<(SceneId, V)>> = entries.into_iter().map(Some).collect();
        order
            .iter()
            .filter_map(|&position| slots.get_mut(position).and_then(Option::take))
            .collect::<Vec<_>>()
            .into_iter()
    }
}

/// The entries of an [`IdTable`], in identifier order.
pub(crate) struct Iter<'a, V> {
    table: &'a IdTable<V>,
    rank: usize,
}

impl<'a, V> Iterator for Iter<'a, V> {
    type Item = (SceneId, &'a V);

    fn next(&mut self) -> Option<Self::Item> {
        let table = self.table;
        let position = if table.is_large() {
            *table.order.get(self.rank)?
        } else {
            self.rank
        };
        self.rank += 1;
        table.entries.get(position).map(|(id, value)| (*id, value))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.table.len().saturating_sub(self.rank);
        (left, Some(left))
    }
}

impl<V> ExactSizeIterator for Iter<'_, V> {}

impl<V: PartialEq> PartialEq for IdTable<V> {
    fn eq(&self, other: &Self) -> bool {
        if !self.is_large() && !other.is_large() {
            // Both small: each one's entries are in identifier order already.
            return self.entries == other.entries;
        }
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl<V: Eq> Eq for IdTable<V> {}

impl<V: Hash> Hash for IdTable<V> {
    fn hash<S: Hasher>(&self, state: &mut S) {
        state.write_usize(self.len());
        for entry in self.iter() {
            entry.hash(state);
        }
    }
}

impl<V: fmt::Debug> fmt::Debug for IdTable<V> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_map().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests;
