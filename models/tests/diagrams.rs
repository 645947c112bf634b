//! The diagrams in the spec are the ones the code generates: a change of behaviour shows up
//! as a diagram diff, and a stale diagram fails here.

use cooperation_models::diagrams::{lifecycle, merge_flow, regenerate};

#[test]
fn the_specs_diagrams_are_generated_from_the_code() {
    let spec = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../spec/cooperation.md"
    ))
    .expect("the spec is readable");
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
        "spec/cooperation.md's diagrams are stale: run `cargo run -p cooperation-models -- diagrams`"
    );
}

/// The generators produce the same text every time (no iteration-order or other drift).
#[test]
fn the_diagrams_are_deterministic() {
    assert_eq!(lifecycle(), lifecycle());
    assert_eq!(merge_flow(), merge_flow());
    assert!(lifecycle().contains("running --> succeeded: Update (retires)"));
    assert!(
        !lifecycle().contains("waiting --> aborting"),
        "the lifecycle table forbids it"
    );
}
