//! The batch model (`cooperation_models::model::batch`): pairs of inputs applied with
//! `State::apply_all`, checked to completion against `State::apply` input by input, with the
//! retired set small enough that a refused pair takes a forgetting back; and the property
//! failing on a planted fault.

use cooperation_models::check::{failing, pins};
use cooperation_models::model::batch::ALL_OR_NONE;
use cooperation_models::{BatchFault, BatchModel};

fn model() -> BatchModel {
    BatchModel::new().expect("valid bounds")
}

/// Every pair applies all or none, as `apply` says input by input, and a refused pair takes
/// back an identifier its first input forgot.
#[test]
fn a_sequence_applies_all_or_none() {
    let (failing, unique) = failing(model());
    println!(
        "batch model, {:?}: {unique} unique states",
        BatchModel::BOUNDS
    );
    assert_eq!(failing, Vec::<&str>::new());
    assert_eq!(unique, pins::BATCH.unique);
}

/// Keeping what the first input did when the second is refused fails the property.
#[test]
fn keeping_a_partial_sequence_fails_it() {
    let (failing, _) = failing(model().with_fault(BatchFault::KeptPartial));
    assert!(failing.contains(&ALL_OR_NONE), "{failing:?}");
}
