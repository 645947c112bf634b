//! Every configured module's policy.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use crate::{Module, Policy};

/// Every module's policy; a module that does not support cooperation has none.
///
/// A built-in module has one slot, found by [`Module::index`] without a search; a module with
/// an extension name is in a list sorted by module, found by binary search. Both are canonical
/// (the list has no module twice), so the derived equality and hash are by contents.
///
/// The list is shared between clones until a policy in it changes: a state is cloned for every
/// step a model checker takes, and its policies rarely change, so a clone allocates nothing.
///
/// Equality and the hash read only the configured slots (the others hold no policy): a model
/// checker compares states after every step, and a slot at a time over every built-in module
/// was most of a state's comparison.
#[derive(Clone)]
pub(super) struct Policies {
    builtin: [Option<Policy>; Module::COUNT],
    /// Bit `i` is set when `builtin[i]` holds a policy: listing skips the empty slots, most of
    /// them, without reading each.
    configured: u64,
    extensions: Arc<Vec<Extension>>,
}

/// A module with an extension name, its policy, and its place among the built-in slots.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
struct Extension {
    module: Module,
    policy: Policy,
    /// How many built-in slots hold a module that comes before this one: listing puts it
    /// before the slot of that index and after those below, comparing numbers, not names.
    /// Fixed by the module, so it is worked out once, when the policies are made.
    before: usize,
}

impl Extension {
    fn new(module: Module, policy: Policy) -> Self {
        let before = (0..Module::COUNT)
            .filter(|&index| Module::at_index(index).is_some_and(|builtin| builtin < module))
            .count();
        Self {
            module,
            policy,
            before,
        }
    }
}

/// Where a scene's module keeps its policy ([`Policies::slot`]): kept by the scene so that asking
/// for its merged decision reads the policy at once, without working out the module's place.
///
/// It is the module's, and the module is the scene's, so it says nothing the scene does not:
/// equality, order and hash ignore it (two scenes equal in everything else are equal), a
/// serialised scene leaves it out, and reading a state back works it out again.
#[derive(Clone, Copy, Default)]
pub(super) struct Slot(u16);

impl Slot {
    /// Whether `self` and `other` are the same place.
    pub(super) const fn is(self, other: Self) -> bool {
        self.0 == other.0
    }
}

impl PartialEq for Slot {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Eq for Slot {}

impl PartialOrd for Slot {
    fn partial_cmp(&self, other: &Self) -> Option<core::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Slot {
    fn cmp(&self, _: &Self) -> core::cmp::Ordering {
        core::cmp::Ordering::Equal
    }
}

impl Hash for Slot {
    fn hash<H: Hasher>(&self, _: &mut H) {}
}

// One bit of `configured` for each built-in module.
const _: () = assert!(Module::COUNT <= u64::BITS as usize);

impl Policies {
    /// The policy of `module`, if it supports cooperation.
    #[inline]
    pub(super) fn get(&self, module: Module) -> Option<Policy> {
        match module.index() {
            // A built-in module's slot is its index: read at once.
            Some(index) => self.builtin.get(index).copied().flatten(),
            None => self.slot(module).and_then(|slot| self.at(slot)),
        }
    }

    /// Where `module`'s policy is kept, if it supports cooperation: a place that
    /// [`at`](Self::at) reads without looking at the module again. Fixed for the state's life,
    /// as the configured modules are.
    pub(super) fn slot(&self, module: Module) -> Option<Slot> {
        let slot = match module.index() {
            Some(index) => self.builtin.get(index).copied().flatten().map(|_| index),
            None => self
                .extensions
                .binary_search_by_key(&module, |listed| listed.module)
                .ok()
                .map(|at| Module::COUNT + at),
        }?;
        u16::try_from(slot).ok().map(Slot)
    }

    /// The policy kept at `slot`, which [`slot`](Self::slot) gave.
    #[inline]
    pub(super) fn at(&self, slot: Slot) -> Option<Policy> {
        let slot = usize::from(slot.0);
        match slot.checked_sub(Module::COUNT) {
            None => self.builtin.get(slot).copied().flatten(),
            Some(at) => self.extensions.get(at).map(|listed| listed.policy),
        }
    }

    /// The policy of `module`, to change, if it supports cooperation.
    pub(super) fn get_mut(&mut self, module: Module) -> Option<&mut Policy> {
        // Found first: only a policy that is in the shared list unshares it.
        let slot = usize::from(self.slot(module)?.0);
        match slot.checked_sub(Module::COUNT) {
            None => self.builtin.get_mut(slot).and_then(Option::as_mut),
            Some(at) => Arc::make_mut(&mut self.extensions)
                .get_mut(at)
                .map(|listed| &mut listed.policy),
        }
    }

    /// Every module that supports cooperation and its policy, in module order.
    pub(super) fn iter(&self) -> impl Iterator<Item = (Module, Policy)> + '_ {
        let mut configured = self.configured;
        let mut extensions = self.extensions.iter().peekable();
        core::iter::from_fn(move || loop {
            let slot = (configured != 0).then(|| configured.trailing_zeros() as usize);
            if let Some(extension) = extensions.next_if(|e| slot.map_or(true, |i| e.before <= i)) {
                return Some((extension.module, extension.policy));
            }
            let index = slot?;
            configured &= configured - 1;
            if let (Some(module), Some(Some(policy))) =
                (Module::at_index(index), self.builtin.get(index))
            {
                return Some((module, *policy));
            }
        })
    }
}

impl FromIterator<(Module, Policy)> for Policies {
    /// Of two policies for one module, the later one stays.
    fn from_iter<I: IntoIterator<Item = (Module, Policy)>>(policies: I) -> Self {
        let mut builtin = [None; Module::COUNT];
        let mut configured = 0_u64;
        let mut extensions = Vec::new();
        for (module, policy) in policies {
            match module.index() {
                Some(index) => {
                    if let Some(slot) = builtin.get_mut(index) {
                        *slot = Some(policy);
                        configured |= 1 << index;
                    }
                }
                None => extensions.push(Extension::new(module, policy)),
            }
        }
        // A stable sort keeps equal modules in input order; the last of each run stays.
        extensions.sort_by_key(|e| e.module);
        extensions.reverse();
        extensions.dedup_by_key(|e| e.module);
        extensions.reverse();
        Self {
            builtin,
            configured,
            extensions: Arc::new(extensions),
        }
    }
}

impl Policies {
    /// The configured slots' policies, in slot order.
    fn configured_slots(&self) -> impl Iterator<Item = Option<Policy>> + '_ {
        let mut configured = self.configured;
        core::iter::from_fn(move || {
            let index = (configured != 0).then(|| configured.trailing_zeros() as usize)?;
            configured &= configured - 1;
            Some(self.builtin.get(index).copied().flatten())
        })
    }
}

impl PartialEq for Policies {
    fn eq(&self, other: &Self) -> bool {
        // The same slots configured, so every other slot holds no policy in either.
        self.configured == other.configured
            && self.configured_slots().eq(other.configured_slots())
            && self.extensions == other.extensions
    }
}

impl Eq for Policies {}

impl Hash for Policies {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.configured.hash(state);
        self.configured_slots().for_each(|slot| slot.hash(state));
        self.extensions.hash(state);
    }
}

impl core::fmt::Debug for Policies {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_map().entries(self.iter()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Behavior, Sequence};

    fn extension(behavior: &str, sequence: &str) -> Module {
        Module::with_sequence(behavior.parse().unwrap(), sequence.parse().unwrap())
    }

    #[test]
    fn built_in_and_extension_modules_iterate_in_module_order_and_the_last_policy_stays() {
        let valet = extension("valet", "");
        let avoidance_back = Module::with_sequence(Behavior::Avoidance, "back".parse().unwrap());
        let crosswalk = Module::new(Behavior::Crosswalk);
        let return_ = Module::with_sequence(Behavior::Avoidance, Sequence::Return);
        let policies: Policies = [
            (valet, Policy::Optional),
            (crosswalk, Policy::Required),
            (avoidance_back, Policy::Required),
            (valet, Policy::Required),
            (return_, Policy::Optional),
            (avoidance_back, Policy::Optional),
        ]
        .into_iter()
        .collect();
        let listed: Vec<_> = policies.iter().collect();
        assert_eq!(
            listed,
            [
                (avoidance_back, Policy::Optional),
                (return_, Policy::Optional),
                (crosswalk, Policy::Required),
                (valet, Policy::Required),
            ]
        );
        assert_eq!(policies.get(valet), Some(Policy::Required));
        assert_eq!(policies.get(extension("valet", "approach")), None);
        assert_eq!(policies.get(Module::new(Behavior::Merge)), None);
    }

    /// Every built-in module, and extension modules placed before, between and after them
    /// (extension behaviours, and built-in behaviours with extension sequences), list in
    /// module order, whichever built-in slots are configured.
    #[test]
    fn extensions_list_among_the_built_in_modules_in_module_order() {
        let builtins: Vec<Module> = (0..Module::COUNT).filter_map(Module::at_index).collect();
        let mut extensions = vec![
            extension("aaa", ""),
            extension("zzz", ""),
            extension("m", "q"),
        ];
        for module in &builtins {
            for sequence in ["a", "m", "zz"] {
                extensions.push(Module::with_sequence(
                    module.behavior,
                    sequence.parse().unwrap(),
                ));
            }
        }
        for configured in [1, 2, 3, 7] {
            let modules: std::collections::BTreeSet<Module> = builtins
                .iter()
                .step_by(configured)
                .chain(&extensions)
                .copied()
                .collect();
            let policies: Policies = modules.iter().map(|&m| (m, Policy::Optional)).collect();
            let listed: Vec<Module> = policies.iter().map(|(module, _)| module).collect();
            assert_eq!(
                listed,
                modules.iter().copied().collect::<Vec<_>>(),
                "every {configured}th slot"
            );
        }
    }

    #[test]
    fn a_policy_changes_in_place_and_equal_contents_are_equal() {
        let valet = extension("valet", "");
        let mut policies: Policies = [(valet, Policy::Optional)].into_iter().collect();
        if let Some(policy) = policies.get_mut(valet) {
            *policy = Policy::Required;
        }
        let expected: Policies = [(valet, Policy::Required)].into_iter().collect();
        assert_eq!(policies, expected);
        assert!(policies.get_mut(extension("other", "")).is_none());
        // A clone shares the list until one of them changes a policy in it.
        let mut copy = policies.clone();
        assert!(Arc::ptr_eq(&copy.extensions, &policies.extensions));
        if let Some(policy) = copy.get_mut(valet) {
            *policy = Policy::Optional;
        }
        assert_eq!(policies.get(valet), Some(Policy::Required));
        assert_eq!(copy.get(valet), Some(Policy::Optional));
    }

    /// Equality and the hash read the configured slots only: policies made in another order
    /// are equal and hash alike, and a different policy or module in any slot, built-in or
    /// extension, makes them differ.
    #[test]
    fn equality_and_hash_are_by_the_configured_policies() {
        use std::hash::BuildHasher;
        let (crosswalk, merge) = (
            Module::new(Behavior::Crosswalk),
            Module::new(Behavior::Merge),
        );
        let valet = extension("valet", "");
        let made = |list: &[(Module, Policy)]| list.iter().copied().collect::<Policies>();
        let policies = made(&[
            (crosswalk, Policy::Required),
            (valet, Policy::Optional),
            (merge, Policy::Optional),
        ]);
        let reordered = made(&[
            (merge, Policy::Optional),
            (crosswalk, Policy::Required),
            (valet, Policy::Optional),
        ]);
        assert_eq!(policies, reordered);
        let state = std::hash::RandomState::new();
        assert_eq!(state.hash_one(&policies), state.hash_one(&reordered));
        let others = [
            made(&[
                (crosswalk, Policy::Optional),
                (valet, Policy::Optional),
                (merge, Policy::Optional),
            ]),
            made(&[
                (crosswalk, Policy::Required),
                (valet, Policy::Required),
                (merge, Policy::Optional),
            ]),
            made(&[(crosswalk, Policy::Required), (merge, Policy::Optional)]),
            made(&[(crosswalk, Policy::Required), (valet, Policy::Optional)]),
            made(&[
                (Module::new(Behavior::Avoidance), Policy::Required),
                (valet, Policy::Optional),
                (merge, Policy::Optional),
            ]),
        ];
        for other in &others {
            assert_ne!(&policies, other, "{other:?}");
        }
        // The hash tells each of them apart from the policies too.
        for other in &others {
            assert_ne!(
                state.hash_one(&policies),
                state.hash_one(other),
                "{other:?}"
            );
        }
    }

    #[test]
    fn a_modules_slot_reads_its_policy_and_an_unconfigured_module_has_none() {
        let valet = extension("valet", "");
        let parking = extension("parking", "approach");
        let crosswalk = Module::new(Behavior::Crosswalk);
        let change = Module::with_sequence(Behavior::Avoidance, Sequence::Change);
        let mut policies: Policies = [
            (parking, Policy::Optional),
            (crosswalk, Policy::Required),
            (valet, Policy::Required),
            (change, Policy::Optional),
        ]
        .into_iter()
        .collect();
        for module in [valet, parking, crosswalk, change] {
            let slot = policies.slot(module).expect("configured");
            assert_eq!(policies.at(slot), policies.get(module), "{module}");
        }
        for unconfigured in [
            extension("valet", "approach"),
            Module::new(Behavior::Avoidance),
            Module::new(Behavior::Intersection),
        ] {
            assert!(policies.slot(unconfigured).is_none(), "{unconfigured}");
        }
        // A changed policy is read through the slot taken before the change.
        let slot = policies.slot(valet).expect("configured");
        *policies.get_mut(valet).expect("configured") = Policy::Optional;
        assert_eq!(policies.at(slot), Some(Policy::Optional));
    }
}
