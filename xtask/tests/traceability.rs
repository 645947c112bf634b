//! The traceability matrix in docs/ is generated from the sources and current, and every rule
//! of the spec has code, a model property and a test.

use std::path::Path;

use xtask::traceability::{gaps, markdown, rows, Row};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn every_rule_has_code_a_property_and_a_test() {
    let rows = rows(root());
    assert!(rows.iter().filter(|r| r.section == 5).count() == cooperation::Rule::ALL.len());
    assert_eq!(gaps(&rows), Vec::<String>::new());
}

#[test]
fn the_checked_in_matrix_is_current() {
    let text = std::fs::read_to_string(root().join("docs/traceability.md")).expect("readable");
    assert!(
        text == markdown(&rows(root())),
        "docs/traceability.md is stale: run `cargo xtask docs`"
    );
}

/// A rule that lost its property or its test is reported.
#[test]
fn a_missing_property_or_test_is_a_gap() {
    let mut rows = rows(root());
    let rule = rows
        .iter_mut()
        .find(|r: &&mut Row| r.section == 5)
        .expect("a rule");
    rule.properties.clear();
    rule.tests.clear();
    let found = gaps(&rows);
    assert_eq!(found.len(), 2, "{found:?}");
}

/// A rule whose only model property is its reachability is a gap: reachability takes the
/// library's word for which rule fired. Every rule has a safety property of its own today.
#[test]
fn a_rule_with_only_reachability_is_a_gap() {
    let mut rows = rows(root());
    assert!(rows.iter().filter(|r| r.section == 5).all(|r| r.safety));
    let rule = rows
        .iter_mut()
        .find(|r: &&mut Row| r.section == 5)
        .expect("a rule");
    rule.properties.retain(|p| p.ends_with("is reachable"));
    rule.safety = false;
    let found = gaps(&rows);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].contains("only model properties are reachability"),
        "{found:?}"
    );
}

/// A tag is placed on the function it sits in or documents, whatever that function's
/// visibility: `pub(super) fn finish` is `finish`, not `super`.
#[test]
fn a_restricted_function_is_named_by_its_name() {
    let rows = rows(root());
    let names: Vec<&String> = rows.iter().flat_map(|r| &r.code).collect();
    assert!(
        names
            .iter()
            .all(|name| !name.ends_with("::super") && !name.ends_with("::crate")),
        "{names:?}"
    );
    let success = rows
        .iter()
        .find(|r| r.tag == "COOP-RELAY-SUCCESS.1")
        .expect("the relay's success rule");
    assert_eq!(success.code, ["adapters/src/relay/operator.rs::finish"]);
}
