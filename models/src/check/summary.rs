//! One check's outcome as `cooperation-models check --summary` prints it: a `summary: ` line of
//! JSON, which the reach table (`cargo xtask reach`) reads from each child process.

use serde::{Deserialize, Serialize};

/// What one check came to.
#[derive(Serialize, Deserialize, Clone, Debug, PartialEq)]
pub struct Summary {
    /// Distinct states.
    pub unique: usize,
    /// Successors generated, duplicates included.
    pub generated: usize,
    /// Wall time of the search, in seconds.
    pub seconds: f64,
    /// Whether the search finished.
    pub complete: bool,
    /// What stopped an incomplete search: the time limit, a budget, a violation.
    #[serde(default)]
    pub stopped: Option<String>,
    /// The process's peak resident memory, where the system says it.
    pub peak_rss_bytes: Option<u64>,
}

/// The prefix of the line that carries a summary.
pub const PREFIX: &str = "summary: ";
