//! Output: a readable table per step, or one JSON object per step; validation verdicts.

use std::fmt::Write as _;
use std::io::Write;
use std::ops::ControlFlow;

use cooperation::{
    Decision, Input, Module, OperatorDecision, Phase, Policy, SceneId, State, Transition,
};
use serde::Serialize;

use crate::{Cause, Departure, ErrorKind, Observation, Replayer, Sink, Step, TraceError, Verdict};

fn write_error(error: &std::io::Error) -> TraceError {
    TraceError::nowhere(ErrorKind::Write {
        message: error.to_string(),
    })
}

/// A sink that writes every step, as a table or as JSON lines.
#[derive(Debug)]
pub struct Printer<W> {
    out: W,
    json: bool,
}

impl<W: Write> Printer<W> {
    /// A printer to `out`; `json` for one JSON object per step.
    pub const fn new(out: W, json: bool) -> Self {
        Self { out, json }
    }

    /// The output, back.
    pub fn into_inner(self) -> W {
        self.out
    }
}

impl<W: Write> Sink for Printer<W> {
    fn step(&mut self, step: &Step, replayer: &Replayer) -> Result<ControlFlow<()>, TraceError> {
        let text = match (self.json, replayer.state()) {
            (true, Some(state)) => step_json(step, state)?,
            (false, Some(state)) => step_text(step, state),
            (_, None) => String::new(),
        };
        self.out
            .write_all(text.as_bytes())
            .map_err(|error| write_error(&error))?;
        Ok(ControlFlow::Continue(()))
    }

    fn observed(
        &mut self,
        _: usize,
        _: &Observation,
        _: &Replayer,
    ) -> Result<ControlFlow<()>, TraceError> {
        // Replay shows what the spec does; `validate` compares observations.
        Ok(ControlFlow::Continue(()))
    }
}

fn retired_text(transition: &Transition, state: &State) -> String {
    let mut text = String::new();
    for (index, id) in transition.retired.iter().enumerate() {
        let separator = if index == 0 { ", retired " } else { ", " };
        let _ = write!(text, "{separator}{id}");
        if let Some(retirement) = state.retirement(*id) {
            let _ = write!(text, " ({})", retirement.reason);
        }
    }
    text
}

/// A step as text: a heading with the rule, then the table of live scenes.
#[must_use]
pub fn step_text(step: &Step, state: &State) -> String {
    let mut text = format!("step {}, line {}", step.number, step.line);
    if let Some(at_ms) = step.at_ms {
        let _ = write!(text, ", at {at_ms} ms");
    }
    let _ = write!(text, ": {} -> ", step.input);
    match &step.outcome {
        Ok(transition) => {
            let _ = write!(
                text,
                "{}{}",
                transition.rule,
                retired_text(transition, state)
            );
        }
        Err(rejection) => {
            let _ = write!(text, "rejected by {}: {rejection}", rejection.rule());
        }
    }
    text.push('\n');
    if matches!(step.input, Input::SetPolicies { .. }) && step.outcome.is_ok() {
        text.push_str("  policies:");
        for (index, setting) in state.policies().enumerate() {
            let separator = if index == 0 { " " } else { ", " };
            let _ = write!(text, "{separator}{} {}", setting.module, setting.policy);
        }
        text.push('\n');
    }
    text + &scenes_table(state)
}

/// The live scenes as an aligned table, indented by two spaces: identifier, module, phase,
/// module decision, operator decision, cancellable, the module's policy, the merged decision
/// and the force flag that is set, if any.
#[must_use]
pub fn scenes_table(state: &State) -> String {
    const HEADINGS: [&str; 9] = [
        "scene",
        "module",
        "phase",
        "decision",
        "operator",
        "cancellable",
        "policy",
        "merged",
        "force",
    ];
    if state.scene_count() == 0 {
        return "  (no live scenes)\n".into();
    }
    let mut rows = vec![HEADINGS.map(String::from)];
    for (id, scene) in state.scenes() {
        let policy = state.policy(scene.module());
        let force = if scene.is_force_activated() {
            "activated"
        } else if scene.is_force_deactivated() {
            "deactivated"
        } else {
            "-"
        };
        rows.push([
            id.to_string(),
            scene.module().to_string(),
            scene.phase().to_string(),
            scene.module_decision().to_string(),
            scene.operator_decision().to_string(),
            if scene.is_cancellable() { "yes" } else { "no" }.into(),
            policy.map_or_else(|| "-".into(), |p| p.to_string()),
            state
                .merged_decision(id)
                .map_or_else(|| "-".into(), |d| d.to_string()),
            force.into(),
        ]);
    }
    let mut widths = [0; 9];
    for row in &rows {
        for (width, cell) in widths.iter_mut().zip(row) {
            *width = (*width).max(cell.len());
        }
    }
    let mut text = String::new();
    for row in &rows {
        let mut line = String::new();
        for (width, cell) in widths.iter().zip(row) {
            let _ = write!(line, "  {cell:<width$}");
        }
        text.push_str(line.trim_end());
        text.push('\n');
    }
    text
}

/// One live scene in a step's JSON. Its `id`, `module_decision`, `operator_decision` and
/// `cancellable` are a `CooperationStatus` in its serde form, so an object can serve as an
/// observed status.
#[derive(Serialize)]
struct SceneJson {
    id: SceneId,
    module: Module,
    phase: Phase,
    module_decision: Decision,
    operator_decision: OperatorDecision,
    cancellable: bool,
    policy: Option<Policy>,
    merged_decision: Option<Decision>,
    force_activated: bool,
    force_deactivated: bool,
}

#[derive(Serialize)]
struct RetiredJson {
    id: SceneId,
    reason: Option<cooperation::RetireReason>,
}

#[derive(Serialize)]
struct RejectionJson {
    rule: &'static str,
    message: String,
}

#[derive(Serialize)]
struct StepJson<'a> {
    step: u64,
    line: usize,
    at_ms: Option<u64>,
    generated: bool,
    input: &'a Input,
    rule: &'static str,
    accepted: bool,
    rejection: Option<RejectionJson>,
    retired: Vec<RetiredJson>,
    scenes: Vec<SceneJson>,
}

/// A step as one line of JSON, newline included.
///
/// # Errors
/// [`ErrorKind::Write`] if serialization fails (it does not for the core's types).
pub fn step_json(step: &Step, state: &State) -> Result<String, TraceError> {
    let retired = step
        .outcome
        .as_ref()
        .map(|transition| {
            transition
                .retired
                .iter()
                .map(|id| RetiredJson {
                    id: *id,
                    reason: state.retirement(*id).map(|r| r.reason),
                })
                .collect()
        })
        .unwrap_or_default();
    let scenes = state
        .scenes()
        .map(|(id, scene)| SceneJson {
            id,
            module: scene.module(),
            phase: scene.phase(),
            module_decision: scene.module_decision(),
            operator_decision: scene.operator_decision(),
            cancellable: scene.is_cancellable(),
            policy: state.policy(scene.module()),
            merged_decision: state.merged_decision(id),
            force_activated: scene.is_force_activated(),
            force_deactivated: scene.is_force_deactivated(),
        })
        .collect();
    let json = StepJson {
        step: step.number,
        line: step.line,
        at_ms: step.at_ms,
        generated: step.generated,
        input: &step.input,
        rule: step.rule().tag(),
        accepted: step.outcome.is_ok(),
        rejection: step.outcome.as_ref().err().map(|rejection| RejectionJson {
            rule: rejection.rule().tag(),
            message: rejection.to_string(),
        }),
        retired,
        scenes,
    };
    let mut text = serde_json::to_string(&json).map_err(|error| {
        TraceError::nowhere(ErrorKind::Write {
            message: error.to_string(),
        })
    })?;
    text.push('\n');
    Ok(text)
}

fn cause_text(cause: Option<Cause>) -> String {
    cause.map_or_else(
        || "none: no remembered input named this scene".into(),
        |cause| format!("{} (step {}, line {})", cause.rule, cause.step, cause.line),
    )
}

/// A verdict as text.
#[must_use]
pub fn verdict_text(verdict: &Verdict) -> String {
    match verdict {
        Verdict::Conforms {
            steps,
            observations,
        } => format!("conforms: {steps} steps, {observations} observations agree with the spec\n"),
        Verdict::Departs(departure) => departure_text(departure),
    }
}

fn departure_text(departure: &Departure) -> String {
    let mut text = format!(
        "departs at line {} (after step {}",
        departure.line, departure.after_step
    );
    if let Some(at_ms) = departure.at_ms {
        let _ = write!(text, ", at {at_ms} ms");
    }
    text.push_str(")\n");
    for difference in &departure.differences {
        let _ = writeln!(
            text,
            "  scene {} {}: expected {}, observed {}\n    rule involved: {}",
            difference.id,
            difference.field.as_str(),
            difference.expected,
            difference.observed,
            cause_text(difference.cause)
        );
    }
    if let Some(last) = departure.last_input {
        let _ = writeln!(
            text,
            "  last input before it: {} (step {}, line {})",
            last.rule, last.step, last.line
        );
    }
    text
}

#[derive(Serialize)]
struct CauseJson {
    rule: &'static str,
    step: u64,
    line: usize,
}

impl From<Cause> for CauseJson {
    fn from(cause: Cause) -> Self {
        Self {
            rule: cause.rule.tag(),
            step: cause.step,
            line: cause.line,
        }
    }
}

#[derive(Serialize)]
struct DifferenceJson<'a> {
    scene: SceneId,
    field: &'static str,
    expected: &'a str,
    observed: &'a str,
    rule: Option<CauseJson>,
}

#[derive(Serialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
enum VerdictJson<'a> {
    Conforms {
        steps: u64,
        observations: u64,
    },
    Departs {
        line: usize,
        after_step: u64,
        at_ms: Option<u64>,
        last_input: Option<CauseJson>,
        differences: Vec<DifferenceJson<'a>>,
    },
}

/// A verdict as one line of JSON, newline included.
///
/// # Errors
/// [`ErrorKind::Write`] if serialization fails (it does not for these types).
pub fn verdict_json(verdict: &Verdict) -> Result<String, TraceError> {
    let json = match verdict {
        Verdict::Conforms {
            steps,
            observations,
        } => VerdictJson::Conforms {
            steps: *steps,
            observations: *observations,
        },
        Verdict::Departs(departure) => VerdictJson::Departs {
            line: departure.line,
            after_step: departure.after_step,
            at_ms: departure.at_ms,
            last_input: departure.last_input.map(CauseJson::from),
            differences: departure
                .differences
                .iter()
                .map(|difference| DifferenceJson {
                    scene: difference.id,
                    field: difference.field.as_str(),
                    expected: &difference.expected,
                    observed: &difference.observed,
                    rule: difference.cause.map(CauseJson::from),
                })
                .collect(),
        },
    };
    let mut text = serde_json::to_string(&json).map_err(|error| {
        TraceError::nowhere(ErrorKind::Write {
            message: error.to_string(),
        })
    })?;
    text.push('\n');
    Ok(text)
}
