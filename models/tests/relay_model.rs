//! The relay model (`cooperation_models::model::relay`): the relay between an operator and a
//! planning module that behaves as upstream's `rtc_interface`, checked to completion with every
//! property holding, and each property failing on a planted fault (the switch property, on
//! faults of the relay itself: `docs/relay.md`).

use cooperation_models::check::{failing, pins};
use cooperation_models::model::relay::{self, RelayBounds, RelayFault, RelayModel};

fn model(bounds: RelayBounds) -> RelayModel {
    RelayModel::new(bounds).expect("valid bounds")
}

/// One identifier, two operator calls, one module move and one loss; a status array may come
/// ahead of its auto-mode status.
const BOUNDS: RelayBounds = RelayBounds {
    scenes: 1,
    operator_calls: 2,
    module_moves: 1,
    losses: 1,
    split: true,
};

/// Every property holds and every witness is reached.
#[test]
fn the_relay_meets_its_rules() {
    let (failing, unique) = failing(model(BOUNDS));
    println!("relay model, {BOUNDS:?}: {unique} unique states");
    assert_eq!(failing, Vec::<&str>::new());
    assert_eq!(unique, pins::RELAY_1.unique);
}

/// Each property fails on its planted fault.
#[test]
fn each_property_fails_on_its_planted_fault() {
    for (fault, property) in [
        (RelayFault::SuccessOnTimeout, relay::SUCCESS),
        (RelayFault::AnsweredForModule, relay::SHOWN),
        (RelayFault::CommandsInverted, relay::SHOWN),
        (RelayFault::LateArrayRestamped, relay::SCENES),
        (RelayFault::LateArrayRestamped, relay::FOLLOW),
        (RelayFault::InexpressibleAsDeactivate, relay::SUCCESS),
    ] {
        let (failing, _) = failing(model(BOUNDS).with_fault(fault).focus(property));
        assert_eq!(failing, vec![property], "{fault:?}");
    }
}

/// Two identifiers at the same budgets, each publication whole (split, it takes 9.4 million
/// states and 12 GB): about 4.2 million states, a minute on two threads.
#[test]
#[ignore = "a long check: cargo test --release -p cooperation-models -- --ignored"]
fn the_relay_meets_its_rules_with_two_scenes() {
    let bounds = RelayBounds {
        scenes: 2,
        split: false,
        ..BOUNDS
    };
    let (failing, unique) = failing(model(bounds));
    println!("relay model, {bounds:?}: {unique} unique states");
    assert_eq!(failing, Vec::<&str>::new());
    assert_eq!(unique, pins::RELAY_2.unique);
}

/// One identifier and two module moves, so that a scene runs and then finishes or aborts
/// between two of the module's arrays, and an array may come ahead of its auto-mode status:
/// about 3.6 million states, two minutes on two threads.
#[test]
#[ignore = "a long check: cargo test --release -p cooperation-models -- --ignored"]
fn the_relay_meets_its_rules_with_two_module_moves() {
    let bounds = RelayBounds {
        module_moves: 2,
        ..BOUNDS
    };
    let (failing, unique) = failing(model(bounds));
    println!("relay model, {bounds:?}: {unique} unique states");
    assert_eq!(failing, Vec::<&str>::new());
    assert_eq!(unique, pins::RELAY_1_TWO_MOVES.unique);
}
