//! What status messages tell the operators.

use serde::{Deserialize, Serialize};

/// What a status message tells an operator of each live scene.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
pub enum Views {
    /// Its identifier only: which scenes exist. Which scene a command reaches, and when, is
    /// what the model is then about; two operators stay in reach of a complete check.
    #[default]
    #[serde(rename = "ids")]
    Identifiers,
    /// Its whole `CooperationStatus` as the library reports it: module and operator decisions
    /// and whether it is cancellable. Owners can then also abort a scene, and an operator
    /// decides from what it sees.
    #[serde(rename = "statuses")]
    Statuses,
}

impl Views {
    /// The name the command line uses: `ids` or `statuses`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Identifiers => "ids",
            Self::Statuses => "statuses",
        }
    }
}
