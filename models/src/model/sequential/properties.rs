//! The sequential model's properties, stated from the specification and named by its tags.

use std::sync::OnceLock;

use cooperation::{
    CooperationStatus, Decision, FactorKind, FactorLists, Geometry, Module, OperatorDecision,
    Phase, Policy, Rule, SceneId, State, TableLayout,
};
use stateright::Property;

use super::{Broken, SequentialModel, Step};

// ---------------------------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------------------------

type Condition = fn(&SequentialModel, &Step) -> bool;

/// The policy `[COOP-MERGE.1]` applies to a scene: required if it is requested
/// (`[COOP-REQUESTED.1]`), else its module's.
fn policy_for(core: &State, scene: &cooperation::Scene) -> Option<Policy> {
    let module = core.policy(scene.module())?;
    Some(if scene.is_requested() {
        Policy::Required
    } else {
        module
    })
}

/// Every live scene's merged decision is the spec table's for its current values.
fn merge_is_the_table(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let policy = policy_for(&step.core, scene);
        let expected = policy.and_then(|policy| {
            model
                .tables
                .merge
                .merged(scene.operator_decision(), policy, scene.module_decision())
        });
        expected.is_some() && model.merged_decision(&step.core, id) == expected
    })
}

/// A required policy, or a request for the operator, with no operator decision never
/// activates.
fn required_none_never_activates(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let held = scene.operator_decision() == OperatorDecision::Undecided
            && (scene.is_requested() || step.core.policy(scene.module()) == Some(Policy::Required));
        !held || model.merged_decision(&step.core, id) == Some(Decision::Deactivate)
    })
}

/// An explicit operator decision (activate or deactivate) is the merged decision.
fn explicit_operator_wins(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let explicit = match scene.operator_decision() {
            OperatorDecision::Activate => Some(Decision::Activate),
            OperatorDecision::Deactivate => Some(Decision::Deactivate),
            OperatorDecision::Autonomous | OperatorDecision::Undecided => None,
        };
        explicit.is_none() || model.merged_decision(&step.core, id) == explicit
    })
}

fn unbroken<const FLAG: u64>(_: &SequentialModel, step: &Step) -> bool {
    !step.ghost.broken.contains(Broken(FLAG))
}

/// The library's own invariant check (every invariant of spec §8) passes.
fn invariants_hold(_: &SequentialModel, step: &Step) -> bool {
    step.core.check_invariants().is_ok()
}

fn rule_fired<const I: usize>(_: &SequentialModel, step: &Step) -> bool {
    step.last.is_some() && step.last == Rule::ALL.get(I).copied()
}

/// No step so far met rule `I`'s *When* without ending in its *Then*.
fn rule_kept<const I: usize>(_: &SequentialModel, step: &Step) -> bool {
    Rule::ALL
        .get(I)
        .is_some_and(|rule| !step.ghost.broken.contains(Broken::rule(*rule)))
}

/// Spec §3's scenes are a map: laid out the other way ([`State::with_table_layout`]), the state
/// is equal to itself, lists the same scenes in the same order, and says which layout it has.
fn layout_is_invisible(_: &SequentialModel, step: &Step) -> bool {
    let other = match step.core.table_layout() {
        TableLayout::Adaptive => TableLayout::Colliding,
        TableLayout::Colliding => TableLayout::Adaptive,
    };
    let relaid = State::clone(&step.core).with_table_layout(other);
    relaid.table_layout() == other && relaid == *step.core && relaid.scenes().eq(step.core.scenes())
}

/// The name of the serialization property, which the model checks with one module only
/// ([`SequentialModel`]'s `properties`).
pub(super) const SERIALIZES: &str = "spec §3, §8: a state read back from its serialized form is the same state, and a corrupted one is refused";

/// The state's serialized form (the one traces and counterexamples carry) reads back as the
/// same state; and read back corrupted, it is refused (`State::check_invariants` on the way in,
/// spec §8): a retired identifier listed twice in the retirement order, a live one listed in
/// place of a retired one (`[COOP-INV-RETIRED-ORDER.1]`), a live scene that succeeded
/// (`[COOP-INV-LIVE-PHASE.1]`). A corruption the state has no part for is skipped.
fn serializes(_: &SequentialModel, step: &Step) -> bool {
    use serde_json::Value;
    let Ok(value) = serde_json::to_value(&*step.core) else {
        return false;
    };
    let reads_back =
        serde_json::from_value::<State>(value.clone()).is_ok_and(|back| back == *step.core);
    let refused = |corrupt: &dyn Fn(&mut Value) -> Option<()>| {
        let mut corrupted = value.clone();
        corrupt(&mut corrupted).is_none() || serde_json::from_value::<State>(corrupted).is_err()
    };
    let first_live = |v: &Value| v.get("scenes")?.get(0)?.get(0).cloned();
    reads_back
        && refused(&|v| {
            let order = v.get_mut("retired_order")?.as_array_mut()?;
            let first = order.first()?.clone();
            order.push(first);
            Some(())
        })
        && refused(&|v| {
            let live = first_live(v)?;
            *v.get_mut("retired_order")?.get_mut(0)? = live;
            Some(())
        })
        && refused(&|v| {
            let scene = v.get_mut("scenes")?.get_mut(0)?.get_mut(1)?;
            *scene.get_mut("phase")? = Value::from("succeeded");
            Some(())
        })
}

/// Whether `a` comes before `b` in the module order of `[COOP-POL-GET.2]`: behaviour string,
/// then sequence string, byte by byte.
fn spec_order(a: &Module, b: &Module) -> bool {
    (
        a.behavior.as_str().as_bytes(),
        a.sequence.as_str().as_bytes(),
    ) < (
        b.behavior.as_str().as_bytes(),
        b.sequence.as_str().as_bytes(),
    )
}

/// Spec §3's state seen through every query: the listings agree with the lookups and the
/// counts, scenes and retirements are listed in identifier order, the retired identifiers
/// in order of retirement are the same set, the scene listing's size hint is valid, and the
/// policies are listed in the module order of `[COOP-POL-GET.2]`: by behaviour string, then
/// sequence string, byte by byte, built-in and extension names alike.
fn queries_agree(_: &SequentialModel, step: &Step) -> bool {
    let core: &State = &step.core;
    let mut previous: Option<Module> = None;
    let policies_ordered = core.policies().all(|setting| {
        let after = previous.map_or(true, |p| spec_order(&p, &setting.module));
        previous = Some(setting.module);
        after
    }) && core
        .policies()
        .all(|setting| core.policy(setting.module) == Some(setting.policy));
    let ascending = |ids: &[SceneId]| ids.windows(2).all(|w| w.first() < w.last());
    let live: Vec<SceneId> = core.scenes().map(|(id, _)| id).collect();
    let by_id: Vec<SceneId> = core.retired_by_id().map(|(id, _)| id).collect();
    let mut by_age: Vec<SceneId> = core.retired_oldest_first().map(|(id, _)| id).collect();
    by_age.sort_unstable();
    // The iterator's size hint is valid, as Rust's `Iterator` contract asks of every iterator.
    let (lower, upper) = core.scenes().size_hint();
    let hint = lower <= live.len() && upper.map_or(true, |upper| live.len() <= upper);
    hint && policies_ordered
        && ascending(&live)
        && live.len() == core.scene_count()
        && core
            .scenes()
            .all(|(id, scene)| core.scene(id) == Some(scene))
        && ascending(&by_id)
        && by_id == by_age
        && core
            .retired_by_id()
            .all(|(id, retirement)| core.retirement(id) == Some(retirement))
}

/// `[COOP-OUT-STATUS.1]`: statuses are listed in identifier order, whatever order the scenes
/// were registered in. Symmetry reduction expands one state of each class equal up to
/// renaming, the first one met, in which scenes registered in identifier order; so this state
/// is also renamed by the identifiers' reversal, which puts its scenes into a new table of the
/// same layout in descending order, and the renamed state's listings must be the spec's: every
/// live identifier once, ascending, each with its own status. The live identifiers and their
/// statuses are found by lookup, identifier by identifier, never by the table's own listing.
fn statuses_in_identifier_order(_: &SequentialModel, step: &Step) -> bool {
    let known = step.ghost.known() as u128;
    let id = SceneId::from_u128;
    let reverse = |scene: SceneId| {
        let n = scene.to_u128();
        if (1..=known).contains(&n) {
            id(known + 1 - n)
        } else {
            scene
        }
    };
    let listed_as_the_spec = |core: &State| {
        let expected: Vec<CooperationStatus> =
            (1..=known).filter_map(|n| core.status(id(n))).collect();
        let mut statuses = Vec::new();
        core.statuses_into(&mut statuses);
        statuses == expected
            && core
                .scenes()
                .map(|(scene, _)| scene)
                .eq(expected.iter().map(|status| status.id))
    };
    listed_as_the_spec(&step.core)
        && step
            .core
            .relabel(reverse)
            .is_some_and(|reversed| listed_as_the_spec(&reversed))
}

/// `State::relabel`, which symmetry reduction relies on: renaming by the identity gives the
/// state back, swapping two identifiers in use twice gives it back, and a rename that merges
/// two identifiers in use is refused.
fn relabel_is_a_renaming(_: &SequentialModel, step: &Step) -> bool {
    let core: &State = &step.core;
    let mut ids: Vec<SceneId> = core.scenes().map(|(id, _)| id).collect();
    ids.extend(core.retired_by_id().map(|(id, _)| id));
    let identity = core.relabel(|id| id).as_ref() == Some(core);
    let (Some(&a), Some(&b)) = (ids.first(), ids.get(1)) else {
        return identity;
    };
    let swap = |id: SceneId| match id {
        x if x == a => b,
        x if x == b => a,
        x => x,
    };
    let swapped_back = core
        .relabel(swap)
        .and_then(|once| once.relabel(swap))
        .is_some_and(|twice| twice == *core);
    identity && swapped_back && core.relabel(|_| a).is_none()
}

/// `[COOP-OUT-ORDER.1]`: each factor list holds every live scene of its kind once, with its
/// status, by distance and then identifier; `factors_into` lists what the one-list calls list.
fn factor_lists_are_the_spec(_: &SequentialModel, step: &Step) -> bool {
    let core: &State = &step.core;
    let expected = |kind: FactorKind| {
        let mut scenes: Vec<(f32, SceneId)> = core
            .scenes()
            .filter(|(_, scene)| scene.geometry().kind() == kind)
            .map(|(id, scene)| (scene.geometry().sort_distance().0, id))
            .collect();
        scenes.sort_by(|a, b| {
            crate::model::spec::messages::distance_order(a.0, b.0).then(a.1.cmp(&b.1))
        });
        scenes.into_iter().map(|(_, id)| id).collect::<Vec<_>>()
    };
    let mut velocity = Vec::new();
    let mut steering = Vec::new();
    core.velocity_factors_into(&mut velocity);
    core.steering_factors_into(&mut steering);
    let mut lists = FactorLists::default();
    core.factors_into(&mut lists);
    // Every factor of the core's lists is a scene's, with the scene's current status.
    let statuses_are_current = velocity
        .iter()
        .map(|f| f.cooperation)
        .chain(steering.iter().map(|f| f.cooperation))
        .all(|status| status.is_some_and(|status| core.status(status.id) == Some(status)));
    let geometry_is_the_scenes = velocity.iter().all(|f| {
        f.cooperation
            .and_then(|status| core.scene(status.id))
            .map(|s| *s.geometry())
            == Some(Geometry::Velocity {
                pose: f.pose,
                distance: f.distance,
                status: f.status,
            })
    });
    statuses_are_current
        && geometry_is_the_scenes
        && velocity
            .iter()
            .map(|f| f.cooperation.map(|status| status.id))
            .eq(expected(FactorKind::Velocity).into_iter().map(Some))
        && steering
            .iter()
            .map(|f| f.cooperation.map(|status| status.id))
            .eq(expected(FactorKind::Steering).into_iter().map(Some))
        && lists.velocity == velocity
        && lists.steering == steering
}

/// `[COOP-FORCE-ACTIVATED.1]` and `[COOP-FORCE-DEACTIVATED.1]`, from their definitions.
fn force_flags_are_the_spec(_: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().all(|(id, scene)| {
        let (operator, module) = (scene.operator_decision(), scene.module_decision());
        let cancellable = matches!(scene.phase(), Phase::Waiting | Phase::Running);
        let activated = cancellable
            && operator == OperatorDecision::Activate
            && (module == Decision::Deactivate || scene.is_requested());
        let deactivated = scene.phase() == Phase::Running
            && operator == OperatorDecision::Deactivate
            && module == Decision::Activate;
        step.core.force_activated(id) == Some(activated)
            && step.core.force_deactivated(id) == Some(deactivated)
            && scene.is_cancellable() == cancellable
    })
}

/// Witness: the operator made the planner go on with a scene its module holds back.
fn operator_overrides_module(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().any(|(id, scene)| {
        scene.module_decision() == Decision::Deactivate
            && model.merged_decision(&step.core, id) == Some(Decision::Activate)
    })
}

/// Witness: a required policy holds back a scene its module would go on with.
fn policy_holds_scene_back(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().any(|(id, scene)| {
        scene.module_decision() == Decision::Activate
            && scene.operator_decision() == OperatorDecision::Undecided
            && !scene.is_requested()
            && step.core.policy(scene.module()) == Some(Policy::Required)
            && model.merged_decision(&step.core, id) == Some(Decision::Deactivate)
    })
}

/// Witness: an owner's request holds back a scene whose module's policy is optional.
fn request_holds_scene_back(model: &SequentialModel, step: &Step) -> bool {
    step.core.scenes().any(|(id, scene)| {
        scene.is_requested()
            && step.core.policy(scene.module()) == Some(Policy::Optional)
            && scene.module_decision() == Decision::Activate
            && model.merged_decision(&step.core, id) == Some(Decision::Deactivate)
    })
}

macro_rules! per_index {
    ($f:ident: $($i:literal)*) => { [$($f::<$i> as Condition),*] };
}

/// The safety properties, by name.
fn always() -> Vec<(&'static str, Condition)> {
    vec![
        (
            "COOP-MERGE.1: the merged decision is the spec table's",
            merge_is_the_table,
        ),
        (
            "COOP-MERGE.1, COOP-REQUESTED.1: required or requested with no operator decision never activates",
            required_none_never_activates,
        ),
        (
            "COOP-MERGE.1: an explicit operator decision wins",
            explicit_operator_wins,
        ),
        (
            "spec §4: a rejected input changes nothing",
            unbroken::<{ Broken::REJECTION_CHANGED.0 }>,
        ),
        (
            "COOP-CMD-APPLY.1: only commands change operator decisions",
            unbroken::<{ Broken::OPERATOR_BY_OTHER.0 }>,
        ),
        (
            "COOP-CMD-APPLY.1: a command changes only the operator decision it names",
            unbroken::<{ Broken::COMMAND_SPILLED.0 }>,
        ),
        (
            "COOP-CMD-APPLY.1: an applied command takes effect",
            unbroken::<{ Broken::COMMAND_MISSED.0 }>,
        ),
        (
            "COOP-POL-SET.1: a policy change alters no scene and no other module",
            unbroken::<{ Broken::POLICY_SPILLED.0 }>,
        ),
        (
            "COOP-POL-SET.1: a policy change reaches its module",
            unbroken::<{ Broken::POLICY_MISSED.0 }>,
        ),
        (
            "COOP-POL-SET.1: only policy changes change policies",
            unbroken::<{ Broken::POLICY_BY_OTHER.0 }>,
        ),
        (
            "COOP-CMD-RETIRED.1: commands naming retired identifiers change nothing",
            unbroken::<{ Broken::RETIRED_COMMAND.0 }>,
        ),
        (
            "COOP-OWN-MODULE.1: an identifier keeps its module while remembered",
            unbroken::<{ Broken::ID_MOVED.0 }>,
        ),
        (
            "COOP-REG-RETIRED.1: a remembered retired identifier never becomes live again",
            unbroken::<{ Broken::REVIVED.0 }>,
        ),
        (
            "COOP-RETIRE.1: terminal states are sticky",
            unbroken::<{ Broken::TERMINAL_LEFT.0 }>,
        ),
        (
            "COOP-RETIRE.1: the retired set forgets only when full, oldest first",
            unbroken::<{ Broken::FORGOT_EARLY.0 }>,
        ),
        (
            "§7: an update goes where the spec's lifecycle table allows, and nowhere else",
            unbroken::<{ Broken::LIFECYCLE.0 }>,
        ),
        (
            "COOP-FORCE-ACTIVATED.1, COOP-FORCE-DEACTIVATED.1, COOP-CANCELLABLE.1: force flags and cancellability are the spec's",
            force_flags_are_the_spec,
        ),
        (
            "spec §3: the scenes are a map, the same in either table layout",
            layout_is_invisible,
        ),
        (
            "spec §3, COOP-POL-GET.2: the state's queries agree with one another, policies in module order",
            queries_agree,
        ),
        (
            "COOP-OUT-STATUS.1: statuses are listed in identifier order, whatever order the scenes registered in",
            statuses_in_identifier_order,
        ),
        (SERIALIZES, serializes),
        (
            "spec §3: renaming identifiers (symmetry) keeps the state and refuses merging two",
            relabel_is_a_renaming,
        ),
        (
            "COOP-OUT-ORDER.1: each factor list holds every live scene of its kind once, by distance and then identifier",
            factor_lists_are_the_spec,
        ),
    ]
}

/// The name of the property that runs the library's invariant check.
pub const INVARIANTS: &str = "COOP-INV-*: State::check_invariants holds (spec §8)";

/// The name of rule `rule`'s own safety property.
#[must_use]
pub fn rule_property(rule: Rule) -> String {
    format!(
        "{}: when the spec's condition holds, this rule fires with the spec's outcome",
        rule.tag()
    )
}

/// Every property: the safety properties, one per rule of §5 from its *When*/*Then*, the
/// library's invariant check, one reachability property per rule, and scenario witnesses.
#[must_use]
pub fn properties() -> Vec<Property<SequentialModel>> {
    static NAMES: OnceLock<Vec<(&'static str, &'static str)>> = OnceLock::new();
    let names = NAMES.get_or_init(|| {
        let leak = |text: String| -> &'static str { Box::leak(text.into_boxed_str()) };
        Rule::ALL
            .iter()
            .map(|r| {
                let kept = leak(rule_property(*r));
                (kept, leak(format!("{} is reachable", r.tag())))
            })
            .collect()
    });
    let kept = per_index!(rule_kept: 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23);
    let fired =
        per_index!(rule_fired: 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23);
    let mut properties: Vec<Property<SequentialModel>> = always()
        .into_iter()
        .map(|(name, condition)| Property::always(name, condition))
        .collect();
    properties.extend(
        names
            .iter()
            .zip(kept)
            .map(|((name, _), condition)| Property::always(name, condition)),
    );
    properties.push(Property::always(INVARIANTS, invariants_hold));
    properties.extend(
        names
            .iter()
            .zip(fired)
            .map(|((_, name), condition)| Property::sometimes(name, condition)),
    );
    properties.push(Property::sometimes(
        "witness: the operator overrides a deactivated scene",
        operator_overrides_module,
    ));
    properties.push(Property::sometimes(
        "witness: a required policy holds a scene back",
        policy_holds_scene_back,
    ));
    properties.push(Property::sometimes(
        "witness: an owner's request holds a scene back under an optional policy",
        request_holds_scene_back,
    ));
    properties
}
