//! The example file `config/cooperation.param.yaml`, and `docs/settings.md` kept true.

use std::collections::BTreeSet;
use std::path::Path;

use super::*;
use cooperation::{Limits, State};
use cooperation_adapters::rtc;

/// A file of the repository, by its path from the repository's root.
fn read(path: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn the_example_file_parses_to_the_projects_defaults() {
    let config = settings::parse(&read("config/cooperation.param.yaml")).expect("it parses");
    let avoidance = |sequence| Module::with_sequence(Behavior::Avoidance, sequence);
    let expected: Vec<Module> = [avoidance(Sequence::Change), avoidance(Sequence::Return)]
        .into_iter()
        .chain(
            [
                Behavior::Crosswalk,
                Behavior::GoalPlanner,
                Behavior::Intersection,
                Behavior::LaneChange,
                Behavior::NoStoppingArea,
                Behavior::RearCheck,
                Behavior::Roundabout,
                Behavior::StartPlanner,
                Behavior::TrafficSignal,
                Behavior::UserDefinedAttentionArea,
                Behavior::VirtualTrafficLight,
            ]
            .map(Module::new),
        )
        .collect();
    assert_eq!(
        config.policies.keys().cloned().collect::<Vec<_>>(),
        expected
    );
    assert!(config.policies.values().all(|p| *p == Policy::Optional));
    assert_eq!(config.limits, Limits::default());
    assert!(State::new(config).is_ok());
}

#[test]
fn the_example_file_covers_every_module_the_standard_rtc_bindings_use() {
    let config = settings::parse(&read("config/cooperation.param.yaml")).unwrap();
    let bound: BTreeSet<Module> = rtc::Binding::standard()
        .into_iter()
        .flat_map(|binding| binding.modules().collect::<Vec<_>>())
        .collect();
    let configured: BTreeSet<Module> = config.policies.keys().cloned().collect();
    assert_eq!(configured, bound);
}

/// The errors `docs/settings.md` shows, each made by the text it stands for.
#[test]
fn the_errors_the_documentation_shows_are_the_errors() {
    let doc = read("docs/settings.md");
    let texts = [
        policies(&["        lane-change: maybe"]),
        policies(&[
            "        lane-change: optional",
            "      limits:",
            "        max_scenes: 0",
        ]),
        policies(&[
            "        lane-change: optional",
            "        lane-change: required",
        ]),
    ];
    for text in texts {
        let shown = settings::parse(&text).unwrap_err().to_string();
        assert!(doc.contains(&format!("\n{shown}\n")), "{shown}");
    }
}

/// Every kind of error the documentation's table lists is one the tests make, and the other
/// way round: the table's first column, against the kinds named in these tests.
#[test]
fn the_documentation_lists_every_kind_of_error() {
    let doc = read("docs/settings.md");
    let table: BTreeSet<String> = doc
        .split("## Errors")
        .nth(1)
        .expect("an Errors section")
        .lines()
        .filter_map(|line| line.strip_prefix("| `"))
        .flat_map(|cell| {
            let first = cell.split(" |").next().unwrap_or_default();
            first
                .split(", ")
                .map(|name| name.trim_matches('`').to_owned())
                .collect::<Vec<_>>()
        })
        .collect();
    let tests = [
        read("adapters/tests/settings/errors.rs"),
        read("adapters/tests/settings/errors_values.rs"),
        read("adapters/tests/settings/interfaces.rs"),
    ]
    .concat();
    let made: BTreeSet<String> = tests
        .split("SettingsErrorKind::")
        .skip(1)
        .map(|rest| {
            rest.chars()
                .take_while(char::is_ascii_alphanumeric)
                .collect()
        })
        .collect();
    assert_eq!(table, made);
    assert_eq!(table.len(), 29, "{table:?}");
}
