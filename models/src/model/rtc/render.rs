//! The RTC model's steps in words, for traces.

use core::fmt::Write as _;

use super::step::{Answer, Outcome, Refusal, RtcStep};
use super::RtcModel;
use crate::model::describe::short;

/// What a call answered, in words.
#[must_use]
pub fn answer(outcome: &Outcome) -> String {
    let rule = |r: Option<cooperation::Rule>| r.map(|r| r.tag().to_owned());
    match outcome.answer {
        Answer::Accepted(first, second) => {
            let rules: Vec<String> = [first, second].into_iter().filter_map(rule).collect();
            if rules.is_empty() {
                "accepted, with no transition".to_owned()
            } else {
                format!("accepted: {}", rules.join(" then "))
            }
        }
        Answer::Cleared(n) => format!("accepted: cleared {n} scene(s)"),
        Answer::Refused(refusal) => format!(
            "refused: {}",
            match refusal {
                Refusal::Field => "undefined constant (COOP-DEV-CONSTANTS.1)".to_owned(),
                Refusal::Interface => "unknown interface".to_owned(),
                Refusal::NoInterface => "no interface reports the module type".to_owned(),
                Refusal::ForeignScene =>
                    "another interface's scene (COOP-DEV-ID-REUSE.1)".to_owned(),
                Refusal::UnboundSequence =>
                    "a sequence the interface is not bound to (COOP-DEV-SEQUENCE.1)".to_owned(),
                Refusal::SequenceUnstated =>
                    "a new scene without its sequence (COOP-DEV-SEQUENCE.1)".to_owned(),
                Refusal::InitialPhase(r) => format!("cannot start there ({})", r.tag()),
                Refusal::Core(r) => r.tag().to_owned(),
                Refusal::Quota =>
                    "a new scene over its interface's quota (COOP-DEV-QUOTA.1)".to_owned(),
                Refusal::Other => "other".to_owned(),
            }
        ),
    }
}

impl RtcModel {
    /// Every live scene of a step as its interface reports it, one line each, and the
    /// interfaces' auto modes and any broken step property.
    #[must_use]
    pub fn describe_step(&self, step: &RtcStep) -> Vec<String> {
        let mut lines = Vec::new();
        for (id, scene) in step.core.scenes() {
            let at = step.owner(id).map(usize::from);
            let name = at
                .and_then(|at| self.names().get(at))
                .map_or("?", String::as_str);
            let view = at.and_then(|at| self.view(step, at));
            let mut line = format!(
                "{} via {name} ({}): {}, {}, operator {}{}",
                short(id),
                scene.module(),
                scene.phase(),
                if scene.module_decision() == cooperation::Decision::Activate {
                    "safe"
                } else {
                    "unsafe"
                },
                scene.operator_decision(),
                if scene.is_requested() {
                    ", requested"
                } else {
                    ""
                },
            );
            if let Some(view) = view {
                let _ = write!(
                    line,
                    " -> activated {}, force-activated {}, force-deactivated {}",
                    view.is_activated(id),
                    view.is_force_activated(id),
                    view.is_force_deactivated(id)
                );
            }
            lines.push(line);
        }
        if lines.is_empty() {
            lines.push("no live scene".to_owned());
        }
        let auto: Vec<String> = (0..self.bindings().len())
            .filter_map(|at| {
                let view = self.view(step, at)?;
                let on = if view.auto_mode_status().is_auto_mode {
                    "on"
                } else {
                    "off"
                };
                let binding = view.binding();
                // An interface bound to several sequences: each module's policy.
                let policies: Vec<String> = if binding.sequences.len() > 1 {
                    super::modules_of(binding)
                        .into_iter()
                        .map(|module| {
                            let policy = step
                                .core
                                .policy(module)
                                .map_or_else(|| "none".to_owned(), |p| p.to_string());
                            format!("{module} {policy}")
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                Some(if policies.is_empty() {
                    format!("{} {on}", binding.name)
                } else {
                    format!("{} {on} ({})", binding.name, policies.join(", "))
                })
            })
            .collect();
        lines.push(format!("auto mode: {}", auto.join(", ")));
        if step.broken.0 != 0 {
            lines.push(format!("broken: {}", step.broken.names().join(", ")));
        }
        lines
    }
}
