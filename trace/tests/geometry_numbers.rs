//! The numbers of a geometry in a trace: a distance must fit a 32-bit float, and the floats
//! JSON has no number for are written as strings that keep their bits (`docs/trace-format.md`).

use cooperation_trace::*;

const CONFIG: &str = r#"{"config": {"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}}"#;

/// A trace that registers one velocity scene at `distance`, its position's `x` at `x`.
fn trace(distance: &str, x: &str) -> String {
    format!(
        "{CONFIG}\n{{\"input\": {{\"Register\": {{\"id\": \"00000000-0000-0000-0000-000000000001\", \
         \"module\": {{\"behavior\": \"lane-change\", \"sequence\": \"\"}}, \"decision\": \"activate\", \
         \"geometry\": {{\"Velocity\": {{\"pose\": {{\"position\": [{x}, 0.0, 0.0], \
         \"orientation\": [0.0, 0.0, 0.0, 1.0]}}, \"distance\": {distance}, \"status\": \"approaching\"}}}}}}}}}}\n"
    )
}

fn replayed(text: &str) -> Result<String, TraceError> {
    let mut out = Vec::new();
    replay(text.as_bytes(), &mut out, &Options::default(), true)?;
    Ok(String::from_utf8(out).expect("UTF-8"))
}

#[test]
fn non_finite_floats_replay_and_are_written_as_read() {
    for (distance, x) in [
        (r#""inf""#, r#""-inf""#),
        (r#""NaN:0x7fc00000""#, r#""NaN:0xfff8000000000001""#),
        (r#""-inf""#, "1.5"),
    ] {
        let out = replayed(&trace(distance, x)).expect("replays");
        assert!(out.contains(distance), "{distance}: {out}");
        assert!(x == "1.5" || out.contains(x), "{x}: {out}");
    }
}

#[test]
fn a_distance_beyond_a_32_bit_float_is_an_error() {
    let error = replayed(&trace("1e39", "0.0")).expect_err("out of range");
    assert_eq!(error.line, Some(2));
    assert!(error.to_string().contains("fits a 32-bit float"), "{error}");
    for bad in [r#""NaN""#, r#""nan""#, "null", r#""Infinity""#] {
        assert!(replayed(&trace(bad, "0.0")).is_err(), "{bad}");
    }
}
