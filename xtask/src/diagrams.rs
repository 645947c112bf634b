//! Diagrams generated from the code, not drawn: the scene lifecycle, by running the transition
//! function on every pair of phases, and the merged-decision flow, by enumerating `merge` over
//! its whole domain. Both are Mermaid, embedded in `spec/cooperation.md` between markers and
//! kept equal to the code by a test (`models/tests/diagrams.rs`).

use core::fmt::Write as _;

use cooperation::{
    merge, Behavior, Config, Decision, Geometry, Input, Module, OperatorDecision, Phase, Policy,
    Report, Rule, SceneId, State,
};

const MODULE: Module = Module::new(Behavior::LaneChange);
const ID: SceneId = SceneId::from_u128(1);

/// A state with one scene, brought to `phase` by the transition function itself.
fn scene_in(phase: Phase) -> Option<State> {
    let mut state = State::new(Config::new([(MODULE, Policy::Optional)])).ok()?;
    let geometry = Geometry::velocity(0.0);
    state
        .apply(&Input::Register {
            id: ID,
            module: MODULE,
            report: Report::new(Decision::Activate, geometry),
        })
        .ok()?;
    let path: &[Phase] = match phase {
        Phase::Waiting => &[],
        Phase::Running => &[Phase::Running],
        Phase::Aborting => &[Phase::Running, Phase::Aborting],
        Phase::Succeeded | Phase::Failed => return None,
    };
    for step in path {
        let update = Input::Update {
            id: ID,
            module: MODULE,
            phase: *step,
            report: Report::new(Decision::Activate, geometry),
        };
        state.apply(&update).ok()?;
    }
    (state.scene(ID).map(cooperation::Scene::phase) == Some(phase)).then_some(state)
}

/// The lifecycle as a Mermaid state diagram: every owner update the transition function accepts
/// between live phases, the updates that retire a scene, and removal and expiry.
#[must_use]
pub fn lifecycle() -> String {
    let mut out = String::from("stateDiagram-v2\n    [*] --> waiting: Register\n");
    let geometry = Geometry::velocity(0.0);
    for from in Phase::ALL {
        let Some(state) = scene_in(from) else {
            continue;
        };
        for to in Phase::ALL {
            let update = Input::Update {
                id: ID,
                module: MODULE,
                phase: to,
                report: Report::new(Decision::Activate, geometry),
            };
            match state.clone().apply(&update).map(|t| t.rule) {
                Ok(Rule::OwnerUpdate) => {
                    let _ = writeln!(out, "    {from} --> {to}: Update");
                }
                Ok(Rule::OwnerFinish) => {
                    let _ = writeln!(out, "    {from} --> {to}: Update (retires)");
                }
                _ => {}
            }
        }
        let remove = Input::Remove {
            id: ID,
            module: MODULE,
        };
        if state.clone().apply(&remove).map(|t| t.rule) == Ok(Rule::OwnerRemove) {
            let _ = writeln!(out, "    {from} --> removed: Remove (retires)");
        }
        let late = Input::Tick {
            elapsed_ms: u64::MAX,
        };
        if state.clone().apply(&late).map(|t| t.rule) == Ok(Rule::TimeExpire) {
            let _ = writeln!(out, "    {from} --> expired: Tick past the TTL (retires)");
        }
    }
    for end in ["succeeded", "failed", "removed", "expired"] {
        let _ = writeln!(out, "    {end} --> [*]");
    }
    out
}

/// The variables `merge` reads, in the order the flow asks about them.
#[derive(Clone, Copy)]
enum Variable {
    Operator,
    Policy,
    Module,
}

type Point = (OperatorDecision, Policy, Decision);

fn values(variable: Variable, point: Point) -> Vec<(String, Point)> {
    let (operator, policy, module) = point;
    match variable {
        Variable::Operator => OperatorDecision::ALL
            .iter()
            .map(|o| (o.as_str().to_owned(), (*o, policy, module)))
            .collect(),
        Variable::Policy => Policy::ALL
            .iter()
            .map(|p| (p.as_str().to_owned(), (operator, *p, module)))
            .collect(),
        Variable::Module => Decision::ALL
            .iter()
            .map(|m| (m.as_str().to_owned(), (operator, policy, *m)))
            .collect(),
    }
}

/// Every point of the domain that agrees with `point` on the variables already asked.
fn completions(point: Point, asked: &[Variable]) -> Vec<Point> {
    let mut all = vec![point];
    for variable in [Variable::Operator, Variable::Policy, Variable::Module] {
        let fixed = asked
            .iter()
            .any(|a| core::mem::discriminant(a) == core::mem::discriminant(&variable));
        if !fixed {
            all = all
                .into_iter()
                .flat_map(|p| values(variable, p).into_iter().map(|(_, p)| p))
                .collect();
        }
    }
    all
}

fn merged((operator, policy, module): Point) -> Decision {
    merge(operator, policy, module)
}

/// The merged-decision flow as a Mermaid flowchart: a decision tree over operator decision,
/// policy and module decision that asks a question only where the answer changes the result.
#[must_use]
pub fn merge_flow() -> String {
    let mut out = String::from("flowchart TD\n");
    let mut next = 0;
    let start = (
        OperatorDecision::Undecided,
        Policy::Optional,
        Decision::Deactivate,
    );
    node(&mut out, &mut next, start, &[]);
    out
}

/// Writes the subtree for the points agreeing with `point` on `asked`; returns its node name.
fn node(out: &mut String, next: &mut usize, point: Point, asked: &[Variable]) -> String {
    let name = format!("n{next}");
    *next += 1;
    let results: Vec<Decision> = completions(point, asked).into_iter().map(merged).collect();
    if let Some(first) = results
        .first()
        .filter(|first| results.iter().all(|r| r == *first))
    {
        let _ = writeln!(out, "    {name}([{first}])");
        return name;
    }
    // Ask the first unasked variable whose value changes the result here.
    let remaining = [Variable::Operator, Variable::Policy, Variable::Module];
    let question = remaining.into_iter().find(|variable| {
        let unasked = !asked
            .iter()
            .any(|a| core::mem::discriminant(a) == core::mem::discriminant(variable));
        unasked && {
            let mut with: Vec<Variable> = asked.to_vec();
            with.push(*variable);
            let by_value: Vec<Vec<Decision>> = values(*variable, point)
                .into_iter()
                .map(|(_, p)| completions(p, &with).into_iter().map(merged).collect())
                .collect();
            by_value.windows(2).any(|w| matches!(w, [a, b] if a != b))
        }
    });
    let Some(question) = question else {
        return name;
    };
    let label = match question {
        Variable::Operator => "operator decision?",
        Variable::Policy => "cooperation policy?",
        Variable::Module => "module decision?",
    };
    let _ = writeln!(out, "    {name}{{{label}}}");
    let mut with = asked.to_vec();
    with.push(question);
    for (value, branch) in values(question, point) {
        let child = node(out, next, branch, &with);
        let _ = writeln!(out, "    {name} -- {value} --> {child}");
    }
    name
}

/// The spec with its generated blocks (between `<!-- generated: NAME -->` and
/// `<!-- end generated -->`) replaced by what the code gives now.
#[must_use]
pub fn regenerate(spec: &str) -> String {
    let mut out = String::new();
    let mut skipping = false;
    for line in spec.lines() {
        if skipping {
            if line.trim() == "<!-- end generated -->" {
                skipping = false;
                out.push_str(line);
                out.push('\n');
            }
            continue;
        }
        out.push_str(line);
        out.push('\n');
        let generated = match line.trim() {
            "<!-- generated: lifecycle -->" => Some(lifecycle()),
            "<!-- generated: merge-flow -->" => Some(merge_flow()),
            _ => None,
        };
        if let Some(diagram) = generated {
            out.push_str("```mermaid\n");
            out.push_str(&diagram);
            out.push_str("```\n");
            skipping = true;
        }
    }
    out
}
