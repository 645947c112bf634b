//! History variables and what a step did to them: sticky flags that a step property sets only
//! when it is broken, so that a correct run adds no states.

use cooperation::{Input, Module, PolicySetting, Rejection, Rule, SceneId, State, Transition};

use super::{Step, MODULES, STRANGER};
use crate::model::ids::{index, MAX_SCENES};
use crate::model::spec::rules::verdict;
use crate::model::spec::Tables;

/// History variables: what the properties about steps need to remember. Indexed by identifier
/// number minus one (the model's identifiers are `1..=scenes`), so they never allocate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub struct Ghost {
    /// The module each identifier was first live under, as a byte ([`code`]): a state is
    /// compared and hashed once per input tried, and bytes compare and hash as one block.
    #[serde(serialize_with = "as_list")]
    pub(super) owners: [u8; MAX_SCENES],
    /// Every identifier ever retired, as a bit set.
    pub retired_ever: u64,
    /// Sticky flags: which step properties some step so far has broken.
    pub broken: Broken,
}

impl Default for Ghost {
    fn default() -> Self {
        Self {
            owners: [0; MAX_SCENES],
            retired_ever: 0,
            broken: Broken::default(),
        }
    }
}

/// An owner as a byte: 0 for none, then the model's modules in [`MODULES`] order, then
/// [`STRANGER`]; any other module (no model configures one) is [`UNLISTED`], which reads back
/// as no module, so a scene of such a module would break `ID_MOVED` loudly, never silently.
fn code(module: Module) -> u8 {
    MODULES
        .iter()
        .map(|(listed, _)| *listed)
        .chain([STRANGER])
        .position(|listed| listed == module)
        .and_then(|i| u8::try_from(i + 1).ok())
        .unwrap_or(UNLISTED)
}

// `Ghost::known` reads the owners eight at a time.
const _: () = assert!(MAX_SCENES % 8 == 0);

/// The code of a module the model does not list.
const UNLISTED: u8 = u8::MAX;

/// The module a byte of [`code`] stands for.
fn decode(code: u8) -> Option<Module> {
    let at = usize::from(code).checked_sub(1)?;
    MODULES
        .iter()
        .map(|(listed, _)| *listed)
        .chain([STRANGER])
        .nth(at)
}

/// The owners as a list of modules, up to the last identifier that has one.
fn as_list<S: serde::Serializer>(
    owners: &[u8; MAX_SCENES],
    serializer: S,
) -> Result<S::Ok, S::Error> {
    let used = owners.iter().rposition(|o| *o != 0).map_or(0, |i| i + 1);
    serializer.collect_seq(owners.iter().take(used).map(|o| decode(*o)))
}

impl Ghost {
    /// One past the index of the last identifier the history knows of (an owner or a
    /// retirement); every identifier from there on is unknown to it.
    pub(super) fn known(&self) -> usize {
        // Read eight owners at a time, from the end: every renaming asks, and most owners are
        // none.
        let owned = self
            .owners
            .chunks_exact(8)
            .enumerate()
            .rev()
            .find_map(|(word, owners)| {
                let mut bytes = [0; 8];
                bytes.copy_from_slice(owners);
                let bits = u64::from_le_bytes(bytes);
                // The last owner set in this word is its highest byte that is not zero.
                (bits != 0).then(|| word * 8 + 8 - (bits.leading_zeros() / 8) as usize)
            })
            .unwrap_or(0);
        let retired = (u64::BITS - self.retired_ever.leading_zeros()) as usize;
        owned.max(retired)
    }

    pub(super) fn was_retired(&self, id: SceneId) -> bool {
        index(id).is_some_and(|i| self.retired_ever & (1_u64 << i) != 0)
    }

    pub(super) fn owner(&self, id: SceneId) -> Option<Module> {
        index(id).and_then(|i| self.owners.get(i).and_then(|o| decode(*o)))
    }
}

/// Where the per-rule flags start: below are the named step properties.
pub(super) const RULE_BITS: u32 = 16;

/// A set of broken step properties (see the `BROKEN_*` constants' docs in the source).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
pub struct Broken(pub(super) u64);

impl Broken {
    /// A rejected input changed the state.
    pub const REJECTION_CHANGED: Self = Self(1);
    /// An input other than an applied command batch changed an operator decision.
    pub const OPERATOR_BY_OTHER: Self = Self(1 << 1);
    /// An applied command batch changed something besides the operator decisions it names.
    pub const COMMAND_SPILLED: Self = Self(1 << 2);
    /// An applied command batch left a named scene without the command's decision.
    pub const COMMAND_MISSED: Self = Self(1 << 3);
    /// An applied policy batch changed a scene or a module it does not name.
    pub const POLICY_SPILLED: Self = Self(1 << 4);
    /// An applied policy batch left a named module without the setting's policy.
    pub const POLICY_MISSED: Self = Self(1 << 5);
    /// An input other than an applied policy batch changed a policy.
    pub const POLICY_BY_OTHER: Self = Self(1 << 6);
    /// A batch naming a retired identifier changed the state.
    pub const RETIRED_COMMAND: Self = Self(1 << 7);
    /// A live identifier's module differs from the one it was first live under.
    pub const ID_MOVED: Self = Self(1 << 8);
    /// An identifier that had retired is live again.
    pub const REVIVED: Self = Self(1 << 9);
    /// A retirement record changed.
    pub const TERMINAL_LEFT: Self = Self(1 << 10);
    /// A retired identifier was forgotten while the retired set had room, or before an older one.
    pub const FORGOT_EARLY: Self = Self(1 << 11);
    /// An owner's update of a live scene of its module, of its kind, was refused although the
    /// spec's lifecycle table (§7) allows the phase change, or fired although it forbids it.
    pub const LIFECYCLE: Self = Self(1 << 12);

    /// The rule of spec §5 whose *When* held for a step whose outcome was not its *Then*: the
    /// library fired another rule, gave another transition or rejection, or left another state
    /// than the spec's (`crate::model::spec::rules`).
    #[must_use]
    pub fn rule(rule: Rule) -> Self {
        let at = Rule::ALL.iter().position(|r| *r == rule).unwrap_or(0);
        Self(1 << (RULE_BITS + at as u32))
    }

    /// Whether `flag` is among these.
    #[must_use]
    pub const fn contains(self, flag: Self) -> bool {
        self.0 & flag.0 != 0
    }

    fn set(&mut self, flag: Self, when: bool) {
        if when {
            self.0 |= flag.0;
        }
    }

    /// These and `other`.
    #[must_use]
    pub const fn and(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }
}

/// Which of the spec's statements the step from `from` by `input` to `core` broke: the rule the
/// spec's *When* picks, if the library's outcome is not that rule's *Then*
/// (`crate::model::spec::rules`), and the lifecycle table (§7) for an owner's update.
/// `unchanged`: `core` equals `from`'s core.
pub(super) fn against_spec(
    tables: &Tables,
    from: &Step,
    input: &Input,
    (result, core, unchanged): (&Result<Transition, Rejection>, &State, bool),
) -> Broken {
    let mut broken = Broken::default();
    let before = from.snapshot();
    let expected = verdict(&tables.lifecycle, before, input);
    broken.set(
        Broken::rule(expected.rule),
        !expected.agrees(before, result, unchanged, core),
    );
    if let Input::Update {
        id,
        module,
        phase,
        report,
    } = input
    {
        let scene = from.core.scene(*id);
        let applies = scene.is_some_and(|s| {
            s.module() == *module && s.geometry().kind() == report.geometry.kind()
        });
        if let (true, Some(scene)) = (applies, scene) {
            let allowed = tables.lifecycle.allows(scene.phase(), *phase);
            let moved = matches!(
                result,
                Ok(Transition {
                    rule: Rule::OwnerUpdate | Rule::OwnerFinish,
                    ..
                })
            );
            broken.set(Broken::LIFECYCLE, allowed != moved);
        }
    }
    broken
}

/// What the step from `from` by `input` to `core` did, as history for the step properties.
/// It compares states and reads the input; it decides nothing.
pub(super) fn observe(
    from: &Step,
    input: &Input,
    result: &Result<Transition, Rejection>,
    core: &State,
) -> Ghost {
    let old: &State = &from.core;
    let mut ghost = from.ghost;
    let broken = &mut ghost.broken;
    let rule = result.as_ref().ok().map(|t| t.rule);
    broken.set(Broken::REJECTION_CHANGED, result.is_err() && core != old);

    let scenes_changed = old.scenes().ne(core.scenes());
    let policies_changed = old.policies().ne(core.policies());
    // The scenes live before and after, walked again where needed rather than collected.
    let kept = || {
        core.scenes()
            .filter_map(|(id, new)| old.scene(id).map(|old| (id, old, new)))
    };
    if rule != Some(Rule::CommandApply) {
        let changed = kept().any(|(_, o, n)| o.operator_decision() != n.operator_decision());
        broken.set(Broken::OPERATOR_BY_OTHER, changed);
    }
    if rule != Some(Rule::PolicySet) {
        broken.set(Broken::POLICY_BY_OTHER, policies_changed);
    }
    match (input, rule) {
        (Input::SetCommands { commands }, Some(Rule::CommandApply)) => {
            let decision_of = |id| commands.iter().find(|c| c.id == id).map(|c| c.decision);
            let same_ids = old
                .scenes()
                .map(|(id, _)| id)
                .eq(core.scenes().map(|(id, _)| id));
            let spilled = !same_ids
                || policies_changed
                || old.retired_oldest_first().ne(core.retired_oldest_first())
                || kept().any(|(id, o, n)| {
                    let operator_moved = o.operator_decision() != n.operator_decision();
                    let rest_moved = o.phase() != n.phase()
                        || o.module_decision() != n.module_decision()
                        || o.is_requested() != n.is_requested()
                        || o.age_ms() != n.age_ms()
                        || o.geometry() != n.geometry()
                        || o.module() != n.module();
                    rest_moved || (operator_moved && decision_of(id).is_none())
                });
            broken.set(Broken::COMMAND_SPILLED, spilled);
            let missed = commands.iter().any(|c| {
                core.scene(c.id).map(cooperation::Scene::operator_decision) != Some(c.decision)
            });
            broken.set(Broken::COMMAND_MISSED, missed);
        }
        (Input::SetPolicies { policies }, Some(Rule::PolicySet)) => {
            let named = |module| policies.iter().any(|p: &PolicySetting| p.module == module);
            let foreign = old
                .policies()
                .zip(core.policies())
                .any(|(o, n)| o != n && !named(o.module));
            broken.set(
                Broken::POLICY_SPILLED,
                scenes_changed
                    || foreign
                    || old.retired_oldest_first().ne(core.retired_oldest_first()),
            );
            let missed = policies
                .iter()
                .any(|p| core.policy(p.module) != Some(p.policy));
            broken.set(Broken::POLICY_MISSED, missed);
        }
        _ => {}
    }
    if let Input::SetCommands { commands } = input {
        let names_retired = commands.iter().any(|c| old.retirement(c.id).is_some());
        broken.set(Broken::RETIRED_COMMAND, names_retired && core != old);
    }
    for (id, scene) in core.scenes() {
        let slot = index(id).and_then(|i| ghost.owners.get_mut(i));
        let owner = slot.and_then(|slot| {
            if *slot == 0 {
                *slot = code(scene.module());
            }
            decode(*slot)
        });
        ghost
            .broken
            .set(Broken::ID_MOVED, owner != Some(scene.module()));
        ghost.broken.set(Broken::REVIVED, ghost.was_retired(id));
    }
    for (id, retirement) in core.retired_by_id() {
        if let Some(i) = index(id) {
            ghost.retired_ever |= 1_u64 << i;
        }
        let changed = old
            .retirement(id)
            .is_some_and(|before| before != retirement);
        ghost.broken.set(Broken::TERMINAL_LEFT, changed);
    }
    // An identifier known before (live or retired) and unknown now has been forgotten: it is
    // unknown again, and the history forgets it too. Forgetting is allowed only to make room
    // (the retired set is full afterwards) and oldest first: of the earlier retirements only a
    // prefix of the retirement order, and one retired by this very step only after all of them.
    let vanished = |id: &SceneId| core.retirement(*id).is_none() && core.scene(*id).is_none();
    let old_order: Vec<SceneId> = old.retired_oldest_first().map(|(id, _)| id).collect();
    let forgotten_old = old_order.iter().take_while(|id| vanished(id)).count();
    let forgotten_new = old.scenes().filter(|(id, _)| vanished(id)).count();
    let any_forgotten = old_order.iter().any(vanished) || forgotten_new > 0;
    if any_forgotten {
        let prefix = old_order.iter().filter(|id| vanished(id)).count() == forgotten_old;
        let after_all_old = forgotten_new == 0 || forgotten_old == old_order.len();
        let full = core.retired_oldest_first().count() == core.limits().retired_capacity;
        ghost
            .broken
            .set(Broken::FORGOT_EARLY, !(prefix && after_all_old && full));
        let known = old_order
            .iter()
            .copied()
            .chain(old.scenes().map(|(id, _)| id));
        for id in known.filter(vanished) {
            if let Some(i) = index(id) {
                ghost.retired_ever &= !(1_u64 << i);
                if let Some(slot) = ghost.owners.get_mut(i) {
                    *slot = 0;
                }
            }
        }
    }
    ghost
}
