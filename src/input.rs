//! The input alphabet: everything that can change the state, and who sends it.

use crate::{Decision, Detail, Geometry, Module, OperatorDecision, Phase, Policy, SceneId};

#[cfg(feature = "serde")]
mod form;

/// One input to [`State::apply`](crate::State::apply).
///
/// Scene owners (planning modules) send `Register`, `Update` and `Remove`; operators send
/// `SetCommands` and `SetPolicies`; the system clock sends `Tick`.
///
/// Serialised, an owner's [`Report`] is not nested: its fields sit beside `id` and `module`,
/// as in `{"Register": {"id": …, "module": …, "decision": …, "requested": …, "geometry": …}}`.
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(from = "form::Input", into = "form::Input"))]
pub enum Input {
    /// A module opens a scene under an identifier it chose (`[COOP-REG-NEW.1]`).
    Register {
        /// The new scene's identifier.
        id: SceneId,
        /// The module the scene belongs to, for ever.
        module: Module,
        /// The module's first decision, its request and the scene's geometry, whose kind
        /// (velocity or steering) is fixed from here on.
        report: Report,
    },
    /// A scene's owner reports its phase, decision and geometry (`[COOP-OWN-UPDATE.1]`).
    Update {
        /// The scene.
        id: SceneId,
        /// The module the owner believes the scene belongs to.
        module: Module,
        /// The phase the owner moves the scene to.
        phase: Phase,
        /// The module's current decision, its request and the scene's current geometry.
        report: Report,
    },
    /// A scene's owner drops the scene (`[COOP-OWN-REMOVE.1]`).
    Remove {
        /// The scene.
        id: SceneId,
        /// The module the owner believes the scene belongs to.
        module: Module,
    },
    /// The AD API `set_commands` call: operator decisions for scenes, all or none
    /// (`[COOP-CMD-APPLY.1]`).
    SetCommands {
        /// The commands, in request order.
        commands: Vec<Command>,
    },
    /// The AD API `set_policies` call: policies for modules, all or none (`[COOP-POL-SET.1]`).
    SetPolicies {
        /// The policies, in request order.
        policies: Vec<PolicySetting>,
    },
    /// Time passed (`[COOP-TIME-AGE.1]`). The caller measures it; the core reads no clock.
    Tick {
        /// How much time passed since the previous tick, in milliseconds.
        elapsed_ms: u64,
    },
}

/// What a scene's owner reports each time it registers or updates the scene: the one payload
/// [`Input::Register`] and [`Input::Update`] share.
///
/// ```
/// use cooperation::{Decision, Detail, Geometry, Report};
///
/// let report = Report::new(Decision::Deactivate, Geometry::velocity(12.0));
/// assert!(!report.requested);
/// assert!(report.detail.is_empty());
/// let asking = report.requesting().with_detail(Detail::new("a parked truck"));
/// assert!(asking.requested);
/// assert_eq!(asking.detail.as_str(), "a parked truck");
/// ```
#[derive(Clone, PartialEq, Eq, Hash, Debug)]
pub struct Report {
    /// The module's decision.
    pub decision: Decision,
    /// The owner asks for an operator decision whatever the module's policy
    /// (`[COOP-REQUESTED.1]`). Absent in a serialised input means `false`.
    pub requested: bool,
    /// Where the scene is.
    pub geometry: Geometry,
    /// Free text for the operator, carried to the scene's factor (AD API `detail`). Absent in
    /// a serialised input means empty.
    pub detail: Detail,
}

impl Report {
    /// A report of `decision` at `geometry`, asking for no operator decision.
    #[must_use]
    pub const fn new(decision: Decision, geometry: Geometry) -> Self {
        Self {
            decision,
            requested: false,
            geometry,
            detail: Detail::EMPTY,
        }
    }

    /// This report, asking for an operator decision (`[COOP-REQUESTED.1]`).
    #[must_use]
    pub fn requesting(self) -> Self {
        Self {
            requested: true,
            ..self
        }
    }

    /// This report, with `detail` for the operator.
    #[must_use]
    pub fn with_detail(self, detail: Detail) -> Self {
        Self { detail, ..self }
    }
}

/// One operator command: an operator decision for the scene with this identifier.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Command {
    /// The scene.
    pub id: SceneId,
    /// The operator's decision; `Undecided` withdraws an earlier one (`[COOP-CMD-APPLY.1]`).
    pub decision: OperatorDecision,
}

/// One policy setting: the cooperation policy for a module.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct PolicySetting {
    /// The module.
    pub module: Module,
    /// Its new policy.
    pub policy: Policy,
}

/// An input in a few words, its identifiers named by `name`: what
/// [`Input::describe_with`] returns.
pub struct Described<'a, F> {
    input: &'a Input,
    name: F,
}

/// At most this many entries of a batch are listed; the rest are counted.
const LISTED: usize = 4;

impl<F: Fn(SceneId) -> String> core::fmt::Display for Described<'_, F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let name = &self.name;
        let requested = |requested: bool| if requested { " requested" } else { "" };
        match self.input {
            Input::Register { id, module, report } => write!(
                f,
                "register {} {module} {}{} {}",
                name(*id),
                report.decision,
                requested(report.requested),
                report.geometry.kind()
            ),
            Input::Update {
                id,
                module,
                phase,
                report,
            } => write!(
                f,
                "update {} {module} {phase} {}{}",
                name(*id),
                report.decision,
                requested(report.requested)
            ),
            Input::Remove { id, module } => write!(f, "remove {} {module}", name(*id)),
            Input::SetCommands { commands } => {
                let entries = commands
                    .iter()
                    .map(|c| format!("{} {}", name(c.id), c.decision));
                write_batch(f, "set_commands", entries, commands.len())
            }
            Input::SetPolicies { policies } => {
                let entries = policies
                    .iter()
                    .map(|p| format!("{} {}", p.module, p.policy));
                write_batch(f, "set_policies", entries, policies.len())
            }
            Input::Tick { elapsed_ms } => write!(f, "time +{elapsed_ms} ms"),
        }
    }
}

/// `call [first, second, …, and N more]`, listing at most [`LISTED`] entries.
fn write_batch(
    f: &mut core::fmt::Formatter<'_>,
    call: &str,
    entries: impl Iterator<Item = String>,
    len: usize,
) -> core::fmt::Result {
    write!(f, "{call} [")?;
    for (index, entry) in entries.take(LISTED).enumerate() {
        let separator = if index == 0 { "" } else { ", " };
        write!(f, "{separator}{entry}")?;
    }
    if len > LISTED {
        write!(f, ", and {} more", len - LISTED)?;
    }
    f.write_str("]")
}

impl Input {
    /// This input in a few words, naming each identifier with `name` (a model checker names
    /// them by small numbers): `register {id} {module} {decision} velocity`, `time +100 ms`.
    /// A batch lists its first four entries and counts the rest. [`Display`](core::fmt::Display)
    /// is this with identifiers in full.
    pub fn describe_with<F: Fn(SceneId) -> String>(&self, name: F) -> Described<'_, F> {
        Described { input: self, name }
    }
}

impl core::fmt::Display for Input {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        self.describe_with(|id| id.to_string()).fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Behavior, Direction};

    #[test]
    fn an_input_in_a_few_words() {
        let module = Module::new(Behavior::LaneChange);
        let id = SceneId::from_u128(7);
        let register = Input::Register {
            id,
            module,
            report: Report::new(
                Decision::Activate,
                Geometry::steering(Direction::Left, 1.0, 2.0),
            )
            .requesting(),
        };
        assert_eq!(
            register.to_string(),
            "register 00000000-0000-0000-0000-000000000007 lane-change activate requested steering"
        );
        let short = |id: SceneId| format!("#{}", id.to_u128());
        let commands = (1..=6)
            .map(|n| Command {
                id: SceneId::from_u128(n),
                decision: OperatorDecision::Deactivate,
            })
            .collect();
        assert_eq!(
            Input::SetCommands { commands }
                .describe_with(short)
                .to_string(),
            "set_commands [#1 deactivate, #2 deactivate, #3 deactivate, #4 deactivate, and 2 more]"
        );
        let update = Input::Update {
            id,
            module,
            phase: Phase::Running,
            report: Report::new(Decision::Deactivate, Geometry::velocity(3.0)),
        };
        assert_eq!(
            update.describe_with(short).to_string(),
            "update #7 lane-change running deactivate"
        );
        assert_eq!(Input::Tick { elapsed_ms: 100 }.to_string(), "time +100 ms");
    }
}
