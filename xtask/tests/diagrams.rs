//! The diagrams in the spec are the ones the code generates: a change of behaviour shows up
//! as a diagram diff, and a stale diagram fails here. And the generated diagrams say what the
//! spec's own tables say: the lifecycle diagram has exactly the edges of the lifecycle table
//! (§7), and the merge flow gives every row of the merged-decision table (§6.2).

use std::collections::{BTreeMap, BTreeSet};

use xtask::diagrams::{lifecycle, merge_flow, regenerate};

fn spec() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../spec/cooperation.md"
    ))
    .expect("the spec is readable")
}

/// The header and the rows of the spec's table whose header row starts with `header`, as
/// trimmed cells.
fn table(spec: &str, header: &str) -> (Vec<String>, Vec<Vec<String>>) {
    let cells = |line: &str| -> Vec<String> {
        line.trim_matches('|')
            .split('|')
            .map(|cell| cell.trim().to_owned())
            .collect()
    };
    let mut lines = spec.lines().skip_while(|line| !line.starts_with(header));
    let head = cells(lines.next().expect("the table is in the spec"));
    assert!(lines.next().is_some_and(|l| l.starts_with("|---")));
    let rows = lines
        .take_while(|line| line.starts_with('|'))
        .map(cells)
        .collect();
    (head, rows)
}

#[test]
fn the_specs_diagrams_are_generated_from_the_code() {
    let spec = spec();
    assert!(
        spec.contains(&lifecycle()),
        "the lifecycle diagram is not embedded"
    );
    assert!(
        spec.contains(&merge_flow()),
        "the merge flow is not embedded"
    );
    assert!(
        regenerate(&spec) == spec,
        "spec/cooperation.md's diagrams are stale: run `cargo xtask docs`"
    );
}

/// The generated lifecycle's edges, built from the spec's words alone: the ✓ cells of the
/// lifecycle table (§7) for the live phases, an update to a terminal phase retiring the scene
/// (`[COOP-OWN-FINISH.1]`), registration into waiting (`[COOP-REG-NEW.1]`), removal and expiry
/// from every live phase (`[COOP-OWN-REMOVE.1]`, `[COOP-TIME-EXPIRE.1]`).
#[test]
fn the_lifecycle_diagram_is_the_specs_table() {
    const TERMINAL: [&str; 2] = ["succeeded", "failed"];
    let (header, rows) = table(&spec(), "| from \\ to |");
    let mut expected = BTreeSet::from(["[*] --> waiting: Register".to_owned()]);
    for row in &rows {
        let from = row[0].as_str();
        let live = !TERMINAL.contains(&from);
        for (to, cell) in header.iter().zip(row).skip(1) {
            match (cell.as_str(), live) {
                ("✗", _) => {}
                ("✓", true) if TERMINAL.contains(&to.as_str()) => {
                    expected.insert(format!("{from} --> {to}: Update (retires)"));
                }
                ("✓", true) => {
                    expected.insert(format!("{from} --> {to}: Update"));
                }
                (cell, _) => panic!("{from} -> {to}: {cell:?} (a terminal row allows nothing)"),
            }
        }
        if live {
            expected.insert(format!("{from} --> removed: Remove (retires)"));
            expected.insert(format!("{from} --> expired: Tick past the TTL (retires)"));
        }
    }
    assert_eq!(rows.len(), 5, "one row per phase");
    for end in TERMINAL.iter().chain(&["removed", "expired"]) {
        expected.insert(format!("{end} --> [*]"));
    }
    let diagram = lifecycle();
    let mut lines = diagram.lines().map(str::trim);
    assert_eq!(lines.next(), Some("stateDiagram-v2"));
    let generated: BTreeSet<String> = lines.map(str::to_owned).collect();
    assert_eq!(generated, expected);
}

/// Every row of the spec's merged-decision table (§6.2), followed through the generated flow
/// from its first question, ends at the row's merged decision.
#[test]
fn the_merge_flow_gives_the_specs_table() {
    let flow = merge_flow();
    let mut questions: BTreeMap<&str, &str> = BTreeMap::new();
    let mut answers: BTreeMap<&str, &str> = BTreeMap::new();
    let mut edges: BTreeMap<(&str, &str), &str> = BTreeMap::new();
    for line in flow.lines().skip(1).map(str::trim) {
        if let Some((from, rest)) = line.split_once(" -- ") {
            let (value, to) = rest.split_once(" --> ").expect("an edge");
            assert!(edges.insert((from, value), to).is_none(), "{line}");
        } else if let Some((node, rest)) = line.split_once("([") {
            answers.insert(node, rest.trim_end_matches("])"));
        } else if let Some((node, rest)) = line.split_once('{') {
            questions.insert(node, rest.trim_end_matches('}'));
        } else {
            panic!("not a node or an edge: {line}");
        }
    }
    let (header, rows) = table(&spec(), "| operator | policy | module | merged |");
    assert_eq!(header, ["operator", "policy", "module", "merged"]);
    assert_eq!(rows.len(), 16);
    for row in &rows {
        let [operator, policy, module, merged] = row.as_slice() else {
            panic!("4 cells: {row:?}")
        };
        let mut node = "n0";
        let mut asked = 0;
        while let Some(question) = questions.get(node) {
            let value = match *question {
                "operator decision?" => operator,
                "cooperation policy?" => policy,
                "module decision?" => module,
                other => panic!("unknown question {other:?}"),
            };
            node = edges
                .get(&(node, value.as_str()))
                .unwrap_or_else(|| panic!("{node} has no branch {value:?}: {row:?}"));
            asked += 1;
            assert!(asked <= 3, "each variable is asked at most once");
        }
        assert_eq!(answers.get(node), Some(&merged.as_str()), "{row:?}");
    }
}
