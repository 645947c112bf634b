//! Counterexamples and witnesses as data: saved as JSON, replayed, and printed as numbered
//! traces a person can follow.

use core::fmt::Write as _;

use cooperation::{Input, Rule, SceneId, State, TableLayout};
use serde::{Deserialize, Serialize};

use crate::model::describe::{describe, short};
use crate::model::ids::ModelError;
use crate::model::network::{
    NetAction, NetBounds, NetworkModel, PlannerKind, Seen, Views, OPERATORS,
};
use crate::model::rtc::{Call, RtcBounds, RtcFault, RtcModel};
use crate::model::sequential::{Bounds, SequentialModel};
use crate::Fault;

/// A path found by the checker, for one model and one property: replaying its actions from the
/// initial state reproduces it.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "lowercase")]
pub enum Trace {
    /// A path of the sequential model.
    Sequential {
        /// The model's bounds.
        bounds: Bounds,
        /// The layout of the core's scene table (speed only; `adaptive` when absent).
        #[serde(default, skip_serializing_if = "is_adaptive")]
        table: TableLayout,
        /// The injected fault, if the run was a sensitivity test.
        fault: Option<Fault>,
        /// The property the trace breaks (or, for a `sometimes` property, reaches).
        property: String,
        /// The inputs, in order.
        inputs: Vec<Input>,
    },
    /// A path of the network model.
    Network {
        /// The model's bounds.
        bounds: NetBounds,
        /// How many operators act (2 when absent).
        #[serde(
            default = "default_operators",
            skip_serializing_if = "is_default_operators"
        )]
        operators: usize,
        /// What status messages tell the operators (identifiers when absent).
        #[serde(default, skip_serializing_if = "is_identifiers")]
        views: Views,
        /// The injected fault, if the run was a sensitivity test.
        fault: Option<Fault>,
        /// What the planner is (the core when absent).
        #[serde(default, skip_serializing_if = "is_core")]
        planner: PlannerKind,
        /// The property the trace breaks.
        property: String,
        /// The actions (owner inputs, messages sent, delivered, duplicated, lost), in order.
        actions: Vec<NetAction>,
    },
    /// A path of the RTC adapter model.
    Rtc {
        /// The model's bounds.
        bounds: RtcBounds,
        /// The injected fault, if the run was a sensitivity test.
        fault: Option<RtcFault>,
        /// The property the trace breaks (or, for a `sometimes` property, reaches).
        property: String,
        /// The adapter calls, in order.
        calls: Vec<Call>,
    },
}

/// Why a trace could not be replayed.
#[derive(Debug)]
pub enum ReplayError {
    /// The model could not be built.
    Model(ModelError),
    /// No property has the trace's name.
    UnknownProperty(String),
}

impl core::fmt::Display for ReplayError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Model(error) => error.fmt(f),
            Self::UnknownProperty(name) => write!(f, "no property is named {name:?}"),
        }
    }
}

impl std::error::Error for ReplayError {}

impl Trace {
    /// The property's name.
    #[must_use]
    pub fn property(&self) -> &str {
        match self {
            Self::Sequential { property, .. }
            | Self::Network { property, .. }
            | Self::Rtc { property, .. } => property,
        }
    }

    /// How many steps the trace has.
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            Self::Sequential { inputs, .. } => inputs.len(),
            Self::Network { actions, .. } => actions.len(),
            Self::Rtc { calls, .. } => calls.len(),
        }
    }

    /// Whether the trace has no step.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The same trace run against the shipped code, without the injected fault.
    #[must_use]
    pub fn without_fault(&self) -> Self {
        let mut trace = self.clone();
        match &mut trace {
            Self::Sequential { fault, .. } | Self::Network { fault, .. } => *fault = None,
            Self::Rtc { fault, .. } => *fault = None,
        }
        trace
    }

    /// Whether the property holds in the trace's last state.
    ///
    /// # Errors
    /// If the model cannot be built or the property is unknown.
    pub fn holds_at_end(&self) -> Result<bool, ReplayError> {
        match self {
            Self::Sequential {
                bounds,
                table,
                fault,
                property,
                inputs,
            } => {
                let model = sequential(*bounds, *table, *fault)?;
                let steps = model.replay(inputs).map_err(ReplayError::Model)?;
                holds_at(&model, property, steps.last())
            }
            Self::Network {
                bounds,
                operators,
                views,
                fault,
                planner,
                property,
                actions,
            } => {
                let model = network(*bounds, *operators, *views, *fault)?.with_planner(*planner);
                let steps = model.replay(actions).map_err(ReplayError::Model)?;
                holds_at(&model, property, steps.last())
            }
            Self::Rtc {
                bounds,
                fault,
                property,
                calls,
            } => {
                let model = rtc(*bounds, *fault)?;
                let steps = model.replay(calls).map_err(ReplayError::Model)?;
                holds_at(&model, property, steps.last())
            }
        }
    }

    /// The trace as numbered steps: what happened, the rule the library applied, and every
    /// live scene's merged decision afterwards.
    ///
    /// # Errors
    /// If the model cannot be built.
    pub fn render(&self) -> Result<String, ReplayError> {
        let mut out = format!("{}\n", self.property());
        match self {
            Self::Sequential {
                bounds,
                table,
                fault,
                inputs,
                ..
            } => {
                let model = sequential(*bounds, *table, *fault)?;
                let steps = model.replay(inputs).map_err(ReplayError::Model)?;
                for (n, (input, step)) in inputs.iter().zip(steps.iter().skip(1)).enumerate() {
                    let _ = writeln!(out, "{:>3}. {}", n + 1, describe(input));
                    rule_line(&mut out, step.last);
                    scenes(&mut out, &step.core, |id| {
                        model.merged_decision(&step.core, id)
                    });
                }
            }
            Self::Network {
                bounds,
                operators,
                views,
                fault,
                planner,
                actions,
                ..
            } => {
                let model = network(*bounds, *operators, *views, *fault)?.with_planner(*planner);
                let steps = model.replay(actions).map_err(ReplayError::Model)?;
                for (n, (action, step)) in actions.iter().zip(steps.iter().skip(1)).enumerate() {
                    let _ = writeln!(out, "{:>3}. {}", n + 1, model.describe(action));
                    rule_line(&mut out, step.last);
                    scenes(&mut out, &step.core, |id| step.core.merged_decision(id));
                    for (k, view) in step.views.iter().enumerate().take(model.operators()) {
                        let seen: Vec<String> = view.iter().map(seen).collect();
                        let _ = writeln!(out, "     operator {} sees [{}]", k + 1, seen.join(", "));
                    }
                }
            }
            Self::Rtc {
                bounds,
                fault,
                calls,
                ..
            } => {
                let model = rtc(*bounds, *fault)?;
                let steps = model.replay(calls).map_err(ReplayError::Model)?;
                for (n, (call, step)) in calls.iter().zip(steps.iter().skip(1)).enumerate() {
                    let _ = writeln!(
                        out,
                        "{:>3}. {}",
                        n + 1,
                        crate::model::rtc::describe(call, model.names())
                    );
                    if let Some(outcome) = &step.last {
                        let _ = writeln!(out, "     {}", crate::model::rtc::answer(outcome));
                    }
                    for line in model.describe_step(step) {
                        let _ = writeln!(out, "     {line}");
                    }
                }
            }
        }
        Ok(out)
    }
}

impl Trace {
    /// The trace as a Mermaid sequence diagram between the scene owner (the planning module),
    /// the operator(s) and the planner, with the rule each input met and the merged decisions
    /// after it as notes.
    ///
    /// # Errors
    /// If the model cannot be built.
    pub fn sequence_diagram(&self) -> Result<String, ReplayError> {
        let mut out = String::from("sequenceDiagram\n");
        match self {
            Self::Sequential {
                bounds,
                table,
                fault,
                inputs,
                ..
            } => {
                out +=
                    "    participant Module\n    participant Planner\n    participant Operator\n";
                let model = sequential(*bounds, *table, *fault)?;
                let steps = model.replay(inputs).map_err(ReplayError::Model)?;
                for (input, step) in inputs.iter().zip(steps.iter().skip(1)) {
                    let from = match input {
                        Input::SetCommands { .. } | Input::SetPolicies { .. } => "Operator",
                        Input::Tick { .. } => "Planner",
                        Input::Register { .. } | Input::Update { .. } | Input::Remove { .. } => {
                            "Module"
                        }
                    };
                    let _ = writeln!(out, "    {from}->>Planner: {}", describe(input));
                    note(&mut out, step.last, &step.core, |id| {
                        model.merged_decision(&step.core, id)
                    });
                }
            }
            Self::Network {
                bounds,
                operators,
                views,
                fault,
                planner,
                actions,
                ..
            } => {
                out += "    participant Module\n    participant Planner\n    participant Operator1 as Operator 1\n";
                let model = network(*bounds, *operators, *views, *fault)?.with_planner(*planner);
                if model.operators() > 1 {
                    out += "    participant Operator2 as Operator 2\n";
                }
                let steps = model.replay(actions).map_err(ReplayError::Model)?;
                for (action, step) in actions.iter().zip(steps.iter().skip(1)) {
                    let (from, to, arrow) = match action {
                        NetAction::Owner(_) => ("Module", "Planner".to_owned(), "->>"),
                        NetAction::Publish(k) => ("Planner", format!("Operator{}", k + 1), "--)"),
                        NetAction::PublishAll => ("Planner", "Operator1".to_owned(), "--)"),
                        NetAction::Send(k, ..) => (operator(*k), "Planner".to_owned(), "--)"),
                        NetAction::Deliver(..) => ("Planner", "Planner".to_owned(), "->>"),
                        NetAction::Receive(k, _)
                        | NetAction::ReceiveDuplicate(k, _)
                        | NetAction::LoseStatus(k, _) => {
                            (operator(*k), operator(*k).to_owned(), "->>")
                        }
                        NetAction::DuplicateCommand(k, _) | NetAction::LoseCommand(k, _) => {
                            (operator(*k), operator(*k).to_owned(), "->>")
                        }
                    };
                    let _ = writeln!(out, "    {from}{arrow}{to}: {}", model.describe(action));
                    if matches!(action, NetAction::Owner(_) | NetAction::Deliver(..)) {
                        note(&mut out, step.last, &step.core, |id| {
                            step.core.merged_decision(id)
                        });
                    }
                }
            }
            Self::Rtc {
                bounds,
                fault,
                calls,
                ..
            } => {
                out +=
                    "    participant Module\n    participant Adapter\n    participant Operator\n";
                let model = rtc(*bounds, *fault)?;
                let steps = model.replay(calls).map_err(ReplayError::Model)?;
                for (call, step) in calls.iter().zip(steps.iter().skip(1)) {
                    let from = match call {
                        Call::Update { .. } | Call::Remove { .. } | Call::Clear { .. } => "Module",
                        Call::Tick => "Adapter",
                        _ => "Operator",
                    };
                    let said = crate::model::rtc::describe(call, model.names());
                    let _ = writeln!(out, "    {from}->>Adapter: {said}");
                    let answer = step
                        .last
                        .as_ref()
                        .map(crate::model::rtc::answer)
                        .unwrap_or_default();
                    // Mermaid ends a statement at `;`, so none may appear in a note.
                    let scenes = model.describe_step(step).join(" / ").replace(';', ",");
                    let _ = writeln!(out, "    Note over Adapter: {answer} — {scenes}");
                }
            }
        }
        Ok(out)
    }
}

/// Whether the named property of `model` holds in `last` (false when there is no last state).
fn holds_at<M: stateright::Model>(
    model: &M,
    property: &str,
    last: Option<&M::State>,
) -> Result<bool, ReplayError> {
    let condition = model
        .properties()
        .into_iter()
        .find(|p| p.name == property)
        .ok_or_else(|| ReplayError::UnknownProperty(property.to_owned()))?
        .condition;
    Ok(last.is_some_and(|last| condition(model, last)))
}

fn operator(k: usize) -> &'static str {
    if k == 0 {
        "Operator1"
    } else {
        "Operator2"
    }
}

/// A note over the planner: the rule the input met and every live scene's merged decision.
fn note(
    out: &mut String,
    rule: Option<Rule>,
    core: &State,
    merged: impl Fn(SceneId) -> Option<cooperation::Decision>,
) {
    let verdict = rule.map_or(String::new(), |r| {
        if r.is_rejection() {
            format!("rejected by {}", r.tag())
        } else {
            format!("{} fired", r.tag())
        }
    });
    let scenes: Vec<String> = core
        .scenes()
        .map(|(id, scene)| {
            let decision = merged(id).map_or("none", |d| d.as_str());
            format!(
                "{} {} {}: {decision}",
                short(id),
                scene.module(),
                scene.phase()
            )
        })
        .collect();
    let scenes = if scenes.is_empty() {
        "no live scene".to_owned()
    } else {
        scenes.join(", ")
    };
    // Mermaid ends a statement at `;`, so none may appear in a note.
    let _ = writeln!(out, "    Note over Planner: {verdict} — {scenes}");
}

const fn default_operators() -> usize {
    OPERATORS
}

fn is_default_operators(operators: &usize) -> bool {
    *operators == OPERATORS
}

fn is_core(planner: &PlannerKind) -> bool {
    *planner == PlannerKind::Core
}

fn is_identifiers(views: &Views) -> bool {
    *views == Views::Identifiers
}

/// A scene in an operator's view: its identifier and incarnation, and its status if the view
/// carries statuses.
fn seen(seen: &Seen) -> String {
    let Seen {
        id,
        incarnation,
        status,
    } = seen;
    match status {
        None => format!("{} (incarnation {incarnation})", short(*id)),
        Some(status) => format!(
            "{} (incarnation {incarnation}: module {}, operator {}, {})",
            short(*id),
            status.module_decision,
            status.operator_decision,
            if status.cancellable {
                "cancellable"
            } else {
                "not cancellable"
            }
        ),
    }
}

fn is_adaptive(table: &TableLayout) -> bool {
    *table == TableLayout::Adaptive
}

fn sequential(
    bounds: Bounds,
    table: TableLayout,
    fault: Option<Fault>,
) -> Result<SequentialModel, ReplayError> {
    let model = SequentialModel::new(bounds)
        .map_err(ReplayError::Model)?
        .with_table(table);
    Ok(match fault {
        Some(fault) => model.with_fault(fault),
        None => model,
    })
}

fn network(
    bounds: NetBounds,
    operators: usize,
    views: Views,
    fault: Option<Fault>,
) -> Result<NetworkModel, ReplayError> {
    let model = NetworkModel::new(bounds)
        .and_then(|model| model.with_operators(operators))
        .map_err(ReplayError::Model)?
        .with_views(views);
    Ok(match fault {
        Some(fault) => model.with_fault(fault),
        None => model,
    })
}

fn rtc(bounds: RtcBounds, fault: Option<RtcFault>) -> Result<RtcModel, ReplayError> {
    let model = RtcModel::new(bounds).map_err(ReplayError::Model)?;
    Ok(match fault {
        Some(fault) => model.with_fault(fault),
        None => model,
    })
}

fn rule_line(out: &mut String, rule: Option<Rule>) {
    if let Some(rule) = rule {
        let verdict = if rule.is_rejection() {
            "rejected by"
        } else {
            "fired"
        };
        let _ = writeln!(out, "     {verdict} {}", rule.tag());
    }
}

fn scenes(
    out: &mut String,
    core: &State,
    merged: impl Fn(SceneId) -> Option<cooperation::Decision>,
) {
    let mut any = false;
    for (id, scene) in core.scenes() {
        any = true;
        let decision = merged(id).map_or("none", |d| d.as_str());
        let _ = writeln!(
            out,
            "     {} {} {} [module {}, operator {}, policy {}] -> {decision}",
            short(id),
            scene.module(),
            scene.phase(),
            scene.module_decision(),
            scene.operator_decision(),
            core.policy(scene.module()).map_or("-", |p| p.as_str()),
        );
    }
    if !any {
        let _ = writeln!(out, "     no live scene");
    }
}
