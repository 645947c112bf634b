//! The table against an ordered map, under every layout, and its layouts' edge cases.

use std::collections::BTreeMap;

use proptest::prelude::*;

use super::{spread, IdTable, Layout, TableLayout, SMALL};
use crate::SceneId;

/// One operation on a table.
#[derive(Clone, Debug)]
enum Op {
    Insert(u8, u32),
    Remove(u8),
}

/// Identifiers from a small pool, so that operations meet existing entries often; the
/// pool is larger than [`SMALL`] so that tables grow their index and shrink again, and
/// some identifiers share their low or high half.
fn id(n: u8) -> SceneId {
    let n = u128::from(n);
    SceneId::from_u128(((n % 7) << 64) | (n * 0x9e37_79b9) | ((n % 3) << 120))
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => (0..60u8, any::<u32>()).prop_map(|(k, v)| Op::Insert(k, v)),
        2 => (0..60u8).prop_map(Op::Remove),
    ]
}

/// A layout that sends every identifier to one of eight buckets next to the end of the
/// index, so that clusters are long and wrap round to its start: the paths of probing and
/// of deletion that random identifiers seldom take.
fn wrapping() -> Layout {
    Layout {
        hash: |id| u64::MAX - (spread(id) & 7),
        ..Layout::of(TableLayout::Adaptive)
    }
}

/// A layout under which every identifier collides.
fn constant() -> Layout {
    Layout {
        hash: |_| 0,
        ..Layout::of(TableLayout::Adaptive)
    }
}

/// Applies `ops` to a table laid out as `layout` and to a `BTreeMap`, and checks that they
/// answer alike, that the table stays consistent, and that it equals (and hashes as) a
/// table built afresh from its entries, in any layout, and no table with other entries.
fn behaves_as_an_ordered_map_with(layout: Layout, ops: &[Op]) -> Result<(), TestCaseError> {
    let mut table = IdTable::<u32>::with(layout);
    let mut model = BTreeMap::new();
    for op in ops {
        match *op {
            Op::Insert(k, v) => {
                prop_assert_eq!(table.insert(id(k), v), model.insert(id(k), v));
            }
            Op::Remove(k) => {
                prop_assert_eq!(table.remove(id(k)), model.remove(&id(k)));
            }
        }
        prop_assert!(table.is_consistent());
        prop_assert_eq!(table.len(), model.len());
    }
    for k in 0..60 {
        prop_assert_eq!(table.get(id(k)), model.get(&id(k)));
    }
    let walked: Vec<_> = table.iter().map(|(k, v)| (k, *v)).collect();
    let expected: Vec<_> = model.iter().map(|(k, v)| (*k, *v)).collect();
    prop_assert_eq!(&walked, &expected);
    let afresh: IdTable<u32> = expected.iter().copied().collect();
    // Both ways round: a table that grew large and shrank back compares with a small one.
    prop_assert_eq!(&afresh, &table);
    prop_assert_eq!(&table, &afresh);
    prop_assert_eq!(fingerprint(&afresh), fingerprint(&table));
    // Equality is by contents in every pair of layouts: one value changed, or one entry
    // fewer, is another table.
    if let Some(&(first, value)) = expected.first() {
        let changed: IdTable<u32> = expected
            .iter()
            .map(|&(k, v)| (k, if k == first { value.wrapping_add(1) } else { v }))
            .collect();
        prop_assert_ne!(&changed, &table);
        prop_assert_ne!(&table, &changed);
        let fewer: IdTable<u32> = expected.iter().copied().skip(1).collect();
        prop_assert_ne!(&fewer, &table);
        prop_assert_ne!(&table, &fewer);
    }
    let relaid = afresh.relaid(TableLayout::Colliding);
    prop_assert!(relaid.is_consistent());
    prop_assert_eq!(&relaid, &table);
    prop_assert_eq!(fingerprint(&relaid), fingerprint(&table));
    prop_assert_eq!(table.into_iter().collect::<Vec<_>>(), expected);
    Ok(())
}

proptest! {
    /// The table behaves as an ordered map after any sequence of insertions and removals,
    /// with its own hash and with hashes that make every cluster long or wrap round.
    #[test]
    fn behaves_as_an_ordered_map(ops in proptest::collection::vec(op(), 0..400)) {
        behaves_as_an_ordered_map_with(Layout::of(TableLayout::Adaptive), &ops)?;
        behaves_as_an_ordered_map_with(Layout::of(TableLayout::Colliding), &ops)?;
        behaves_as_an_ordered_map_with(wrapping(), &ops)?;
        behaves_as_an_ordered_map_with(constant(), &ops)?;
    }
}

fn fingerprint(table: &IdTable<u32>) -> u64 {
    use core::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    table.hash(&mut hasher);
    hasher.finish()
}

#[test]
fn grows_an_index_past_small_and_keeps_it() {
    let mut table = IdTable::<usize>::new();
    for n in 0..=SMALL {
        assert_eq!(table.insert(SceneId::from_u128(n as u128), n), None);
    }
    assert!(table.is_large());
    for n in 0..=SMALL {
        assert_eq!(table.remove(SceneId::from_u128(n as u128)), Some(n));
        assert!(table.is_consistent());
    }
    assert!(table.is_large());
    assert_eq!(table, IdTable::new());
}

#[test]
fn the_colliding_layout_indexes_from_the_first_entry_and_wraps_round() {
    let mut table = IdTable::<usize>::with_layout(TableLayout::Colliding);
    assert_eq!(table.insert(SceneId::from_u128(1), 1), None);
    assert!(table.is_large());
    assert_eq!(table.index.len(), 2);
    for n in 2..=3 {
        table.insert(SceneId::from_u128(n), n as usize);
    }
    assert_eq!(table.index.len(), 8, "the index doubled as it filled");
    let homes: Vec<usize> = (1..=3)
        .map(|n| table.home(table.hash_of(SceneId::from_u128(n))))
        .collect();
    assert!(homes.iter().all(|home| *home >= 6), "{homes:?}");
    assert!(
        table.index.iter().take(2).any(|at| *at != super::EMPTY),
        "a cluster wrapped round"
    );
    assert!(table.is_consistent());
}
