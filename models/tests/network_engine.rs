//! The network model through the service engine (`NetworkModel::through_engine`): the planner
//! a node, reports sent as a planning module's sync, commands as `set_commands` requests,
//! statuses published when the engine says one is due and read back from the factors it
//! writes. Every network property holds, with the counts pinned (with status views, among the
//! long checks), and a wrong constant in what the engine writes fails the status property.

use cooperation_models::check::pins::{self, Pin};
use cooperation_models::check::run::{check, Settings, Strategy};
use cooperation_models::model::engine::EngineFault;
use cooperation_models::model::network::PlannerKind;
use cooperation_models::{NetBounds, NetworkModel, Views};

use crate::exhaustive::{assert_pinned, passes, unsatisfied};

const STATUS_RECEIVED: &str = "COOP-OUT-STATUS.1 (network): a status an operator receives is what the library reported for that scene when it was sent";

fn settings() -> Settings {
    Settings {
        threads: 2,
        strategy: Strategy::Bfs,
        symmetry: false,
    }
}

/// Checked to completion: every property holds, every witness is reached, at the pinned count.
fn holds(model: &NetworkModel, pin: Pin) {
    let report = passes(model, settings());
    println!(
        "{}: {} unique, {} generated",
        pin.model, report.unique, report.generated
    );
    assert_pinned(&report, pin);
}

/// Two operators, 2 identifiers, identifier views, through the engine.
#[test]
fn network_through_the_engine_two_operators() {
    let model = NetworkModel::new(NetBounds { scenes: 2 })
        .expect("valid bounds")
        .through_engine();
    holds(&model, pins::NETWORK_ENGINE);
}

/// One operator told the whole statuses the engine's factors carry, 2 identifiers.
#[test]
#[ignore = "a long exhaustive check: `cargo test --release -p cooperation-models -- --ignored` (CI runs it)"]
fn network_through_the_engine_status_views() {
    let model = NetworkModel::new(NetBounds { scenes: 2 })
        .and_then(|model| model.with_operators(1))
        .expect("valid bounds")
        .with_views(Views::Statuses)
        .through_engine();
    holds(&model, pins::NETWORK_ENGINE_STATUS_VIEWS);
}

/// An engine that writes an undecided operator decision as `UNKNOWN` (0) fails the status
/// property: what the operator is told is read from the factors the engine writes.
#[test]
fn a_wrong_constant_in_the_engine_s_factors_fails_the_status_property() {
    let model = NetworkModel::new(NetBounds { scenes: 2 })
        .and_then(|model| model.with_operators(1))
        .expect("valid bounds")
        .with_views(Views::Statuses)
        .with_planner(PlannerKind::Engine {
            written_fault: Some(EngineFault::UndecidedAsUnknown),
        })
        .focus(STATUS_RECEIVED);
    let report = check(&model, settings(), &mut std::io::sink());
    assert_eq!(unsatisfied(&report), vec![STATUS_RECEIVED]);
}
