//! Keeps `spec/cooperation.md`, the code and the tests in lockstep, mechanically.

use std::collections::{BTreeMap, BTreeSet};

use crate::spec_tables::*;
use cooperation::{merge, Decision, Invariant, Limits, OperatorDecision, Phase, Policy, Rule};

/// The tags the spec defines in section `number` (`## {number}.`); a tag defined twice fails.
fn section_tags(spec: &str, number: u32) -> BTreeSet<String> {
    let mut tags = BTreeSet::new();
    for tag in spec_text::tags(spec)
        .into_iter()
        .filter(|t| t.section == number)
    {
        assert!(
            tags.insert(tag.tag.clone()),
            "tag {} is defined twice",
            tag.tag
        );
    }
    tags
}

use spec_text::mentioned_tags;

/// The text of every `.rs` file under each of `dirs`, subdirectories included.
fn read_dirs(dirs: &[&str]) -> String {
    let mut text = String::new();
    for dir in dirs {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(dir);
        let files = spec_text::rust_sources(&root);
        assert!(!files.is_empty(), "no Rust files under {dir}");
        text.extend(files.into_iter().map(|(_, text)| text));
    }
    text
}

/// The shipped code: the core and its adapters (the AD API calls and the RTC deviations are
/// the adapters').
const SHIPPED: [&str; 2] = ["src", "adapters/src"];
/// The core's tests, the adapters' and the models' (the relay's scenarios run beside the models'
/// upstream peer): the places `cargo xtask docs` reads tests from too.
const TESTS: [&str; 3] = ["tests", "adapters/tests", "models/tests"];

fn test_name(tag: &str) -> String {
    tag.to_lowercase().replace(['-', '.'], "_")
}

#[test]
fn rule_tags_equal_the_rule_enum() {
    let spec_rules = section_tags(&spec(), 5);
    let code_rules: BTreeSet<String> = Rule::ALL.iter().map(|rule| rule.tag().to_owned()).collect();
    assert_eq!(spec_rules, code_rules);
    assert_eq!(code_rules.len(), Rule::ALL.len(), "rule tags are distinct");
}

#[test]
fn invariant_tags_equal_the_invariant_enum() {
    let spec_invariants = section_tags(&spec(), 8);
    let code: BTreeSet<String> = Invariant::ALL
        .iter()
        .map(|inv| inv.tag().to_owned())
        .collect();
    assert_eq!(spec_invariants, code);
}

#[test]
fn every_rule_and_definition_is_tagged_in_the_code() {
    let spec = spec();
    let source = read_dirs(&SHIPPED);
    let in_code = mentioned_tags(&source);
    for tag in section_tags(&spec, 5)
        .iter()
        .chain(&section_tags(&spec, 6))
        .chain(&section_tags(&spec, 8))
    {
        assert!(
            in_code.contains(tag),
            "{tag} is not marked `[{tag}]` anywhere in src/ or adapters/src/"
        );
    }
    let defined: BTreeSet<String> = (5..=9).flat_map(|n| section_tags(&spec, n)).collect();
    for tag in &in_code {
        assert!(
            defined.contains(tag),
            "the code mentions [{tag}], which the spec does not define"
        );
    }
}

#[test]
fn every_spec_reference_is_defined() {
    let spec = spec();
    let defined: BTreeSet<String> = (5..=9).flat_map(|n| section_tags(&spec, n)).collect();
    for tag in mentioned_tags(&spec) {
        assert!(
            defined.contains(&tag),
            "the spec refers to [{tag}], which it does not define"
        );
    }
}

#[test]
fn every_tag_has_a_test_named_after_it() {
    let spec = spec();
    let tests = read_dirs(&TESTS);
    for section in [5, 6, 8, 9] {
        for tag in section_tags(&spec, section) {
            let name = format!("fn {}()", test_name(&tag));
            assert!(
                tests.contains(&name),
                "no test `{name}` for [{tag}] (spec §{section})"
            );
        }
    }
}

/// The functions of `src/state.rs` that decide (the guards), as `(name, body lines)`: every
/// function whose name starts with `decide`, and the helpers they call to check.
fn decision_path(source: &str) -> Vec<(String, Vec<String>)> {
    const HELPERS: [&str; 3] = ["owned_scene", "command_failures", "check_batch_len"];
    let lines: Vec<&str> = source.lines().collect();
    let mut functions = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let Some(rest) = line.trim_start().strip_prefix("fn ") else {
            continue;
        };
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        if !(name.starts_with("decide") || HELPERS.contains(&name.as_str())) {
            continue;
        }
        // The body: to the line that closes the function, at the indentation it opened at.
        let indent = &line[..line.len() - line.trim_start().len()];
        let end = (start..lines.len())
            .find(|&at| lines[at] == format!("{indent}}}"))
            .expect("the function closes");
        functions.push((
            name,
            lines[start..=end].iter().map(|l| l.to_string()).collect(),
        ));
    }
    functions
}

/// Every rule's tag sits at its guard, in the function that decides it: a comment naming that
/// one tag, directly above the code that checks or chooses (an `if`, a match arm, the outcome
/// built). No comment on the decision path names two rules, so one combined comment cannot
/// stand for several guards.
#[test]
fn every_rule_is_tagged_at_its_guard() {
    let source = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../src/state.rs"))
        .expect("readable");
    let functions = decision_path(&source);
    assert!(
        functions.len() >= 8,
        "found {} deciding functions",
        functions.len()
    );
    let tag_in = |line: &str| -> Vec<String> {
        line.split('[')
            .skip(1)
            .filter_map(|part| part.split_once(']'))
            .map(|(tag, _)| tag.to_owned())
            .filter(|tag| tag.starts_with("COOP-"))
            .collect()
    };
    let mut at_guard = BTreeMap::<String, String>::new();
    for (name, body) in &functions {
        for (at, line) in body.iter().enumerate() {
            let comment = line.trim_start();
            if !comment.starts_with("//") {
                continue;
            }
            let tags = tag_in(comment);
            assert!(
                tags.len() <= 1,
                "`{name}` names several rules in one comment: {comment}"
            );
            let Some(tag) = tags.into_iter().next() else {
                continue;
            };
            let code = body[at + 1..]
                .iter()
                .map(|l| l.trim())
                .find(|l| !l.starts_with("//"))
                .unwrap_or_default();
            let guard = code.starts_with("if ")
                || code.contains("=>")
                || ["return ", "Ok(", "Err(", "Some(", "Rule::", "self.", "let "]
                    .iter()
                    .any(|start| code.starts_with(start));
            assert!(
                guard,
                "`{name}`: [{tag}] is followed by `{code}`, not a guard"
            );
            at_guard.insert(tag, name.clone());
        }
    }
    for rule in Rule::ALL {
        assert!(
            at_guard.contains_key(rule.tag()),
            "{} is not tagged at a guard of the decision path",
            rule.tag()
        );
    }
}

#[test]
fn merge_table_is_complete_and_matches_the_code() {
    let rows = table(&spec(), "| operator | policy | module | merged |");
    let mut seen = BTreeSet::new();
    for row in &rows {
        let [o, p, m, merged] = row.as_slice() else {
            panic!("4 cells: {row:?}")
        };
        let key = (
            operator(o),
            policy(p).expect("no '-' here"),
            decision(m).expect("no '-' here"),
        );
        assert!(seen.insert(key), "row {row:?} repeats");
        assert_eq!(
            merge(key.0, key.1, key.2),
            decision(merged).expect("a decision"),
            "{row:?}"
        );
    }
    let domain = OperatorDecision::ALL.len() * Policy::ALL.len() * Decision::ALL.len();
    assert_eq!(seen.len(), domain, "the table covers the whole domain");
}

#[test]
fn lifecycle_table_is_complete_and_matches_the_code() {
    let spec = spec();
    let rows = table(&spec, "| from \\ to |");
    let header = spec
        .lines()
        .find(|l| l.starts_with("| from \\ to |"))
        .expect("header");
    let columns: Vec<Phase> = header
        .trim_matches('|')
        .split('|')
        .skip(1)
        .map(|c| phase(c.trim()))
        .collect();
    assert_eq!(columns, Phase::ALL);
    let from: Vec<Phase> = rows.iter().map(|row| phase(&row[0])).collect();
    assert_eq!(from, Phase::ALL);
    for row in &rows {
        let from = phase(&row[0]);
        for (to, cell) in columns.iter().zip(&row[1..]) {
            let allowed = match cell.as_str() {
                "✓" => true,
                "✗" => false,
                other => panic!("cell {other:?}"),
            };
            // A terminal phase is never live, so its row forbids everything.
            assert_eq!(
                from.may_become(*to) && !from.is_terminal(),
                allowed,
                "{from} -> {to}"
            );
            assert_eq!(from.may_become(*to), allowed, "{from} -> {to}");
        }
    }
}

/// `Limits::default()` is the spec's §10 table, and the defaults the limits' field docs,
/// docs/trace-format.md's configuration table and docs/settings.md's layout repeat are the same
/// numbers.
#[test]
fn default_limits_are_the_specs() {
    let number = |text: &str| -> u64 {
        text.replace(' ', "")
            .parse()
            .unwrap_or_else(|_| panic!("not a number: {text:?}"))
    };
    let Limits {
        ttl_ms,
        max_scenes,
        retired_capacity,
        max_batch,
    } = Limits::default();
    let count = |n: usize| u64::try_from(n).expect("fits");
    let code: BTreeMap<String, u64> = [
        ("ttl_ms", ttl_ms),
        ("max_scenes", count(max_scenes)),
        ("retired_capacity", count(retired_capacity)),
        ("max_batch", count(max_batch)),
    ]
    .map(|(name, value)| (name.to_owned(), value))
    .into();
    let in_spec: BTreeMap<String, u64> = table(&spec(), "| Limit | Default | Beyond it |")
        .iter()
        .map(|row| (row[0].trim_matches('`').to_owned(), number(&row[1])))
        .collect();
    assert_eq!(in_spec, code, "spec §10");
    let read = |path: &str| {
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join(path),
        )
        .expect("readable")
    };
    let trace_format: BTreeMap<String, u64> = table(
        &read("docs/trace-format.md"),
        "| Field | Meaning | Default |",
    )
    .iter()
    .filter_map(|row| {
        let name = row[0].trim_matches('`').strip_prefix("limits.")?;
        Some((name.to_owned(), number(&row[2])))
    })
    .collect();
    assert_eq!(trace_format, code, "docs/trace-format.md");
    let settings: BTreeMap<String, u64> = table(
        &read("docs/settings.md"),
        "| Key (under the node key) | Value | Default |",
    )
    .iter()
    .filter_map(|row| {
        let key = row[0].trim_matches('`');
        let name = key.strip_prefix("ros__parameters.cooperation.limits.")?;
        Some((name.to_owned(), number(&row[2])))
    })
    .collect();
    assert_eq!(settings, code, "docs/settings.md");
    // The field docs: `pub NAME: TYPE,` preceded by a doc comment ending "Default N." or
    // "Default N ms.".
    let source = read("src/state/config.rs");
    let limits = source
        .split("pub struct Limits {")
        .nth(1)
        .and_then(|rest| rest.split("\n}").next())
        .expect("the Limits struct");
    let mut documented = BTreeMap::new();
    let mut default = None;
    for line in limits.lines().map(str::trim) {
        if let Some((_, rest)) = line.split_once("Default ") {
            default = Some(number(rest.trim_end_matches('.').trim_end_matches(" ms")));
        } else if let Some(field) = line.strip_prefix("pub ") {
            let name = field.split(':').next().expect("a field");
            documented.insert(
                name.to_owned(),
                default.take().expect("a documented default"),
            );
        }
    }
    assert_eq!(documented, code, "the field docs of Limits");
}
