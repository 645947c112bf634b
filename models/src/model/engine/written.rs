//! The factor messages an engine's publication carries, read back into the spec oracle's form
//! ([`spec::messages::Factor`]) so that the engine model can compare them field by field.

use cooperation_adapters::engine;
use cooperation_adapters::wire;

use crate::model::spec;

/// The factors the streams write for the engine's core as the spec's oracle reads them
/// ([`spec::messages::Factor`]): velocity or steering, as the model's module reports.
#[must_use]
pub fn written(publication: &engine::Publication, steering: bool) -> Vec<spec::messages::Factor> {
    use spec::messages::Factor;
    let status = |status: &wire::CooperationStatus| {
        (
            status.uuid.uuid.to_vec(),
            status.autonomous.decision,
            status.cooperator.decision,
            status.cancellable,
        )
    };
    let factor = |distances: Vec<f32>,
                  direction: u16,
                  status_constant: u16,
                  names: [&str; 3],
                  cooperation: &[wire::CooperationStatus]| {
        let (uuid, autonomous, cooperator, cancellable) = match cooperation {
            [one] => status(one),
            _ => (Vec::new(), 0, 0, false),
        };
        Factor {
            uuid,
            distances: distances.iter().map(|d| d.to_bits()).collect(),
            direction,
            status: status_constant,
            behavior: names[0].to_owned(),
            sequence: names[1].to_owned(),
            detail: names[2].to_owned(),
            autonomous,
            cooperator,
            cancellable,
        }
    };
    if steering {
        publication
            .steering
            .factors
            .iter()
            .map(|f| {
                factor(
                    f.distance.to_vec(),
                    f.direction,
                    f.status,
                    [&f.behavior, &f.sequence, &f.detail],
                    &f.cooperation,
                )
            })
            .collect()
    } else {
        publication
            .velocity
            .factors
            .iter()
            .map(|f| {
                factor(
                    vec![f.distance],
                    0,
                    f.status,
                    [&f.behavior, &f.sequence, &f.detail],
                    &f.cooperation,
                )
            })
            .collect()
    }
}
