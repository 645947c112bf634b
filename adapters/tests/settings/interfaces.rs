//! `cooperation.interfaces`: RTC interfaces besides the standard ones, each bound to a module
//! of the file; every refusal with its line, column, key and message.

use super::*;
use cooperation::Direction;
use cooperation_adapters::engine::{Engine, Options};
use cooperation_adapters::rtc::{Binding, Kind, ModuleType};
use cooperation_adapters::settings::{Expected, Found, Settings};

const INTERFACES: &str = "/**.ros__parameters.cooperation.interfaces";

/// A file with the policies of `intersection` and `dynamic-avoidance`, and `interfaces`
/// holding `entries` (indented by eight spaces), whose first entry is line 8.
fn with_interfaces(entries: &[&str]) -> String {
    let mut body = vec![
        "      policies:",
        "        intersection: optional",
        "        dynamic-avoidance: required",
        "      interfaces:",
    ];
    body.extend_from_slice(entries);
    cooperation(&body)
}

fn dynamic_avoidance() -> Module {
    module("dynamic-avoidance".parse().expect("an extension name"))
}

#[test]
fn each_interface_binds_a_module_of_the_file_in_name_order() {
    let text = with_interfaces(&[
        "        sampling_planner:",
        "          behavior: intersection",
        "          kind: velocity",
        "          module_type: 8",
        "        dynamic_obstacle_avoidance:",
        "          behavior: dynamic-avoidance",
        "          kind: steering-left",
    ]);
    let read = settings::read(&text).expect("the interfaces read");
    let expected = Settings {
        config: config(&[
            (module(Behavior::Intersection), Policy::Optional),
            (dynamic_avoidance(), Policy::Required),
        ]),
        interfaces: vec![
            Binding::new(
                "dynamic_obstacle_avoidance",
                ModuleType::None,
                dynamic_avoidance(),
                Kind::Steering(Direction::Left),
            ),
            Binding::new(
                "sampling_planner",
                ModuleType::Intersection,
                module(Behavior::Intersection),
                Kind::Velocity,
            ),
        ],
    };
    assert_eq!(read, expected);
    // `parse` reads and checks them, and gives the configuration alone.
    assert_eq!(settings::parse(&text), Ok(expected.config.clone()));
    // Dotted keys name the same parameters.
    let dotted = with_interfaces(&[
        "        sampling_planner.behavior: intersection",
        "        sampling_planner.kind: velocity",
        "        sampling_planner.module_type: 8",
        "        dynamic_obstacle_avoidance: {behavior: dynamic-avoidance, kind: steering-left}",
    ]);
    assert_eq!(settings::read(&dotted), Ok(expected.clone()));
    // A sequence makes the module that behaviour with it; none, the behaviour alone.
    let avoidance = cooperation(&[
        "      policies:",
        "        avoidance.return: optional",
        "      interfaces.shift_back: {behavior: avoidance, sequence: return, kind: steering}",
    ]);
    let read = settings::read(&avoidance).expect("a sequence");
    assert_eq!(
        read.interfaces,
        [Binding::new(
            "shift_back",
            ModuleType::None,
            sequence(Behavior::Avoidance, Sequence::Return),
            Kind::Steering(Direction::Unknown),
        )]
    );
    // No interfaces, or an empty map: the standard ones only.
    assert_eq!(
        settings::read(settings::BUILT_IN).map(|s| s.interfaces.len()),
        Ok(0)
    );
    let empty = with_interfaces(&[]).replace("interfaces:", "interfaces: {}");
    assert_eq!(settings::read(&empty).map(|s| s.interfaces.len()), Ok(0));
}

#[test]
fn an_engine_from_the_settings_takes_reports_through_the_interfaces_they_add() {
    let text = with_interfaces(&[
        "        dynamic_obstacle_avoidance: {behavior: dynamic-avoidance, kind: steering-left}",
    ]);
    let Settings { config, interfaces } = settings::read(&text).expect("read");
    let engine =
        Engine::with_interfaces(config, interfaces.clone(), Options::default()).expect("an engine");
    let bindings = engine.host().rtc().bindings();
    assert_eq!(bindings.len(), Binding::standard().len() + 1);
    assert_eq!(bindings.last(), interfaces.first());
    // The default quota, 215 (4,096 ÷ 19), is lowered to the table shared by 20 interfaces.
    assert_eq!(engine.host().rtc().scene_quota(), Some(4_096 / 20));
    // One given, not the default, is kept, or refused if it does not fit.
    let given = |scene_quota| Options {
        scene_quota,
        ..Options::default()
    };
    let config = settings::parse(&text).expect("read");
    let kept = Engine::with_interfaces(config.clone(), interfaces.clone(), given(100))
        .expect("100 × 20 fits");
    assert_eq!(kept.host().rtc().scene_quota(), Some(100));
    let error = Engine::with_interfaces(config, interfaces.clone(), given(214)).unwrap_err();
    assert!(
        error.to_string().contains("give a quota of at most 204"),
        "{error}"
    );
    // The same name twice is refused by the engine too (the file cannot say it twice).
    let twice = [interfaces.clone(), interfaces].concat();
    let config = settings::parse(&text).expect("read");
    let error = Engine::with_interfaces(config, twice, Options::default()).unwrap_err();
    assert_eq!(
        error.to_string(),
        "the RTC interfaces: the RTC interface name \"dynamic_obstacle_avoidance\" is bound twice"
    );
}

#[test]
fn an_interface_name_is_a_name_the_standard_bindings_do_not_have() {
    refused(
        &with_interfaces(&["        9lives: {behavior: intersection, kind: velocity}"]),
        (8, 9),
        &format!("{INTERFACES}.9lives"),
        &SettingsErrorKind::InvalidInterface {
            given: "9lives".into(),
        },
        "\"9lives\" is not an interface name: an ASCII letter, then ASCII letters, digits and \
         `_`, at most 128 bytes",
    );
    let long = format!(
        "        {}: {{behavior: intersection, kind: velocity}}",
        "a".repeat(129)
    );
    let error = settings::parse(&with_interfaces(&[&long])).expect_err("too long");
    assert!(
        matches!(error.kind, SettingsErrorKind::InvalidInterface { .. }),
        "{error}"
    );
    assert!(settings::parse(&with_interfaces(&[&long.replacen('a', "", 1)])).is_ok());
    refused(
        &with_interfaces(&["        intersection: {behavior: intersection, kind: velocity}"]),
        (8, 9),
        &format!("{INTERFACES}.intersection"),
        &SettingsErrorKind::StandardInterface {
            given: "intersection".into(),
        },
        "\"intersection\" is a standard interface, bound already; `interfaces` adds others",
    );
}

#[test]
fn an_interfaces_keys_and_values_are_checked_where_they_are_written() {
    let field = |name: &str| format!("{INTERFACES}.mine.{name}");
    refused(
        &with_interfaces(&["        mine: {behavior: intersection, kind: sideways}"]),
        (8, 46),
        &field("kind"),
        &SettingsErrorKind::UnknownKind {
            given: "sideways".into(),
        },
        "unknown kind \"sideways\"; expected one of `velocity`, `steering`, `steering-left`, \
         `steering-right`",
    );
    refused(
        &with_interfaces(&[
            "        mine: {behavior: intersection, kind: velocity, module_type: 20}",
        ]),
        (8, 69),
        &field("module_type"),
        &SettingsErrorKind::UnknownModuleType { given: "20".into() },
        "20 is no `tier4_rtc_msgs/Module` constant (0, NONE, to 19, ROUNDABOUT)",
    );
    refused(
        &with_interfaces(&[
            "        mine: {behavior: intersection, kind: velocity, module_type: \"8\"}",
        ]),
        (8, 69),
        &field("module_type"),
        &SettingsErrorKind::WrongType {
            expected: Expected::Integer,
            found: Found::String,
        },
        "expected a whole number, found a string",
    );
    refused(
        &with_interfaces(&["        mine: {behavior: 7, kind: velocity}"]),
        (8, 26),
        &field("behavior"),
        &SettingsErrorKind::WrongType {
            expected: Expected::Behavior,
            found: Found::Integer,
        },
        "expected a behaviour, found a whole number",
    );
    let error = settings::parse(&with_interfaces(&[
        "        mine: {behavior: Intersection, kind: velocity}",
    ]))
    .expect_err("not a behaviour");
    assert!(
        matches!(error.kind, SettingsErrorKind::InvalidBehavior(_)),
        "{error}"
    );
    refused(
        &with_interfaces(&["        mine: {behavior: intersection, kind: velocity, type: 8}"]),
        (8, 56),
        &field("type"),
        &SettingsErrorKind::UnknownKey {
            given: "type".into(),
            expected: &["behavior", "sequence", "kind", "module_type"],
        },
        "unknown key \"type\"; expected one of `behavior`, `sequence`, `kind`, `module_type`",
    );
    refused(
        &with_interfaces(&[
            "        mine: {behavior: intersection, kind: velocity}",
            "        mine.kind: steering",
        ]),
        (9, 20),
        &field("kind"),
        &SettingsErrorKind::Twice { first_line: 8 },
        "set twice, by two spellings of the key (first on line 8)",
    );
    refused(
        &with_interfaces(&["        mine: {behavior: {a: 1}, kind: velocity}"]),
        (8, 26),
        &field("behavior"),
        &SettingsErrorKind::WrongType {
            expected: Expected::Behavior,
            found: Found::Map,
        },
        "expected a behaviour, found a map",
    );
}

#[test]
fn an_interface_lacking_a_key_or_a_module_with_a_policy_is_refused_at_its_key() {
    refused(
        &with_interfaces(&["        mine: {kind: velocity}"]),
        (8, 15),
        &format!("{INTERFACES}.mine"),
        &SettingsErrorKind::MissingField { field: "behavior" },
        "the interface has no `behavior`",
    );
    refused(
        &with_interfaces(&["        mine:", "          behavior: intersection"]),
        (9, 11),
        &format!("{INTERFACES}.mine"),
        &SettingsErrorKind::MissingField { field: "kind" },
        "the interface has no `kind`",
    );
    refused(
        &with_interfaces(&["        mine: {behavior: crosswalk, kind: velocity}"]),
        (8, 15),
        &format!("{INTERFACES}.mine"),
        &SettingsErrorKind::Unbound {
            module: "crosswalk".into(),
        },
        "module \"crosswalk\" has no policy in `cooperation.policies`: the interface's scenes \
         could not register",
    );
}
