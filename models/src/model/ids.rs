//! What every model shares: its identifiers (`1..=MAX_SCENES`, indexed from 0) and the error
//! building a model can give.

use cooperation::SceneId;

use crate::model::spec::TableError;

/// The most identifiers the sequential model can have: enough for swarm simulation at a real
/// planner's sizes (`simulate --scenes 64`). Its history keeps one entry per identifier.
pub const MAX_SCENES: usize = 64;

/// The most identifiers the RTC and network models can have: they are checked exhaustively
/// only, and every state keeps fixed-size arrays of this length.
pub const MAX_SMALL_SCENES: usize = 8;

/// The model's index of an identifier: its number minus one.
#[must_use]
pub fn index(id: SceneId) -> Option<usize> {
    let number = id.to_u128();
    usize::try_from(number)
        .ok()
        .and_then(|n| n.checked_sub(1))
        .filter(|n| *n < MAX_SCENES)
}

/// Bounds the model cannot be built with.
#[derive(Debug)]
pub enum ModelError {
    /// A bound is out of range.
    Bounds(String),
    /// The spec's table could not be read.
    Table(TableError),
}

impl core::fmt::Display for ModelError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Bounds(why) => write!(f, "bad bounds: {why}"),
            Self::Table(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for ModelError {}
