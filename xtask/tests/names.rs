//! Every `Type::item` the spec, the README and the current pages of docs/ name is defined in the
//! sources, and a name that is not is reported.

use std::path::Path;

use xtask::names::{definitions, paths, unknown, unknown_in};

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn the_pages_name_only_code_that_exists() {
    assert_eq!(unknown(root()), Vec::<String>::new());
}

/// A function renamed in the code but not in the text, a removed type, and a removed variant are
/// each reported with their line; the names that exist, a foreign type and a C++ path are not.
#[test]
fn a_renamed_or_removed_name_is_reported() {
    let (types, items) = definitions(root());
    let text = "The owner states it (`StatusReport::in_sequence`), once.\n\
                Before, it was `Interface::update_cooperate_status_in`.\n\
                `NoSuchType::apply` and `RtcError::NoSuchRefusal`, beside `State::apply()`,\n\
                `Arc::make_mut`, `autoware::rtc_interface::RTCInterface`, `RtcError::SceneQuota`.\n";
    let found = unknown_in(text, &types, &items);
    let lines: Vec<usize> = found.iter().map(|(line, _)| *line).collect();
    assert_eq!(lines, [2, 3, 3], "{found:?}");
    assert!(
        found[0].1.contains("update_cooperate_status_in"),
        "{found:?}"
    );
    assert!(found[1].1.contains("no type `NoSuchType`"), "{found:?}");
    assert!(found[2].1.contains("NoSuchRefusal"), "{found:?}");
}

/// What counts as a path: backticked, `::`-separated identifiers, with an optional `()`.
#[test]
fn paths_are_backticked_identifiers_joined_by_colons() {
    let text = "`State::apply()` and `a::b::C` but not `x :: y`, `Vec<u8>::new`, `::leading` \
                or State::bare.";
    let found: Vec<String> = paths(text).into_iter().map(|(_, path)| path).collect();
    assert_eq!(found, ["State::apply", "a::b::C"]);
}
