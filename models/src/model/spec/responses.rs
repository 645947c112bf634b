//! What the AD API's service responses and the node's `/cooperation/scenes` topic must carry,
//! stated from the specification (`[COOP-API-STATUS.1]`, `[COOP-POL-GET.2]`, `[COOP-MERGE.1]`,
//! `[COOP-REQUESTED.1]`, `[COOP-CANCELLABLE.1]`) and the AD API's message definitions
//! (`autoware_adapi_v1_msgs`: `ResponseStatus`, `CooperationPolicy`), never by calling the
//! adapters' conversions: the engine model compares what the engine answers and publishes with
//! these, field by field and in order.

use cooperation::{Decision, Module, OperatorDecision, Phase, Policy, Rejection, SceneId, State};

use super::messages::decision;
use super::MergeTable;

/// `ResponseStatus`'s codes the spec's answers use.
pub mod code {
    /// Plain success.
    pub const SUCCESS: u16 = 0;
    /// `PARAMETER_ERROR`: every refused batch.
    pub const PARAMETER_ERROR: u16 = 50_004;
    /// `NO_EFFECT`: an empty batch.
    pub const NO_EFFECT: u16 = 60_001;
}

/// `CooperationPolicy`'s constants.
pub mod policy {
    /// `OPTIONAL`.
    pub const OPTIONAL: u8 = 1;
    /// `REQUIRED`.
    pub const REQUIRED: u8 = 2;
}

/// A `ResponseStatus` as the spec states it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Status {
    /// `success`.
    pub success: bool,
    /// `code`.
    pub code: u16,
    /// `message`.
    pub message: String,
}

/// `[COOP-API-STATUS.1]`: the status of a batch call of `len` entries that the core applied
/// (`Ok`) or refused with its rejection.
#[must_use]
pub fn batch_status(len: usize, result: Result<(), &Rejection>) -> Status {
    match result {
        Err(rejection) => Status {
            success: false,
            code: code::PARAMETER_ERROR,
            message: rejection.to_string(),
        },
        Ok(()) if len == 0 => Status {
            success: true,
            code: code::NO_EFFECT,
            message: "the batch is empty".to_owned(),
        },
        Ok(()) => Status {
            success: true,
            code: code::SUCCESS,
            message: String::new(),
        },
    }
}

const fn policy_constant(policy: Policy) -> u8 {
    match policy {
        Policy::Optional => policy::OPTIONAL,
        Policy::Required => policy::REQUIRED,
    }
}

/// One `CooperationPolicy` entry: behaviour, sequence, policy constant.
pub type PolicyEntry = (String, String, u8);

/// `[COOP-POL-GET.2]`: `get_policies`'s answer for `state` (always plain success), with every
/// configured module's policy, ordered by behaviour string, then sequence string, byte by byte.
#[must_use]
pub fn policies(state: &State) -> (Status, Vec<PolicyEntry>) {
    let mut entries: Vec<PolicyEntry> = state
        .policies()
        .map(|setting| {
            let Module { behavior, sequence } = setting.module;
            (
                behavior.as_str().to_owned(),
                sequence.as_str().to_owned(),
                policy_constant(setting.policy),
            )
        })
        .collect();
    entries.sort_by(|a, b| {
        a.0.as_bytes()
            .cmp(b.0.as_bytes())
            .then_with(|| a.1.as_bytes().cmp(b.1.as_bytes()))
    });
    (batch_status(1, Ok(())), entries)
}

/// One scene as `/cooperation/scenes` must show it, short of its age: identifier, merged
/// decision constant, whether it waits for an operator, whether its owner asked for one, and
/// the constant of the policy that applies to it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneRow {
    /// The identifier's bytes.
    pub uuid: Vec<u8>,
    /// `merged`.
    pub merged: u8,
    /// `awaits_operator`.
    pub awaits_operator: bool,
    /// `requested`.
    pub requested: bool,
    /// `policy`.
    pub policy: u8,
}

/// `/cooperation/scenes` for `state`: every live scene in identifier order, its merged decision
/// from the spec's own table (`merge`, read from its text), the policy that applies to it
/// (`required` if its owner asked for an operator, else its module's: `[COOP-REQUESTED.1]`),
/// and whether it waits for an operator (it takes commands, `[COOP-CANCELLABLE.1]`; no operator
/// has decided; that policy is `required`). A scene whose module has no policy, or whose row
/// the table lacks, is shown with constant 0, which no message may carry.
#[must_use]
pub fn scenes(state: &State, merge: &MergeTable) -> Vec<SceneRow> {
    let mut rows: Vec<(SceneId, SceneRow)> = state
        .scenes()
        .map(|(id, scene)| {
            let applies = state.policy(scene.module()).map(|module_policy| {
                if scene.is_requested() {
                    Policy::Required
                } else {
                    module_policy
                }
            });
            let operator = scene.operator_decision();
            let decided =
                applies.and_then(|policy| merge.merged(operator, policy, scene.module_decision()));
            let takes_commands = matches!(scene.phase(), Phase::Waiting | Phase::Running);
            let row = SceneRow {
                uuid: id.to_bytes().to_vec(),
                merged: match decided {
                    Some(Decision::Deactivate) => decision::DEACTIVATE,
                    Some(Decision::Activate) => decision::ACTIVATE,
                    None => 0,
                },
                awaits_operator: takes_commands
                    && operator == OperatorDecision::Undecided
                    && applies == Some(Policy::Required),
                requested: scene.is_requested(),
                policy: applies.map_or(0, policy_constant),
            };
            (id, row)
        })
        .collect();
    rows.sort_by_key(|(id, _)| *id);
    rows.into_iter().map(|(_, row)| row).collect()
}
