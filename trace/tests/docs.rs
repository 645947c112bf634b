//! `docs/trace-format.md` stays true: its example records parse, and the outputs and errors it
//! shows are what the tool prints.

use std::path::Path;

use cooperation_trace::*;

fn doc() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/trace-format.md");
    std::fs::read_to_string(path).expect("docs/trace-format.md")
}

fn data(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    std::fs::read_to_string(path).expect("a checked-in trace")
}

/// The contents of every fenced block whose opening line is exactly "```{language}".
fn blocks(text: &str, language: &str) -> Vec<String> {
    let opening = format!("```{language}");
    let mut blocks = Vec::new();
    let mut current: Option<String> = None;
    for line in text.lines() {
        match &mut current {
            None if line == opening => current = Some(String::new()),
            Some(block) if line == "```" => {
                blocks.push(std::mem::take(block));
                current = None;
            }
            Some(block) => {
                block.push_str(line);
                block.push('\n');
            }
            None => {}
        }
    }
    blocks
}

/// The text block right after the marker `<!-- {marker} -->`.
fn shown_after(text: &str, marker: &str) -> String {
    let marker = format!("<!-- {marker} -->\n");
    let at = text.find(&marker).expect("the marker") + marker.len();
    blocks(&text[at..], "text")
        .into_iter()
        .next()
        .expect("a text block")
}

#[test]
fn example_records_parse() {
    let doc = doc();
    let examples = blocks(&doc, "jsonl");
    assert!(
        examples.len() >= 3,
        "the format's examples are jsonl blocks"
    );
    let mut records = 0;
    for block in examples {
        for (index, line) in block.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            parse_record(index + 1, line).unwrap_or_else(|e| panic!("{line}: {e}"));
            records += 1;
        }
    }
    assert!(records >= 8, "{records}");
}

#[test]
fn shown_replay_is_the_replay() {
    let mut out = Vec::new();
    replay(
        data("seed.jsonl").as_bytes(),
        &mut out,
        &Options::default(),
        false,
    )
    .unwrap();
    assert_eq!(
        shown_after(&doc(), "replay seed.jsonl"),
        String::from_utf8(out).unwrap()
    );
}

#[test]
fn shown_validation_is_the_validation() {
    let verdict = validate(
        data("policy-clobber-departs.jsonl").as_bytes(),
        &Options::default(),
    )
    .unwrap();
    assert_eq!(
        shown_after(&doc(), "validate policy-clobber-departs.jsonl"),
        verdict_text(&verdict)
    );
}

#[test]
fn shown_errors_are_the_errors() {
    let seed = data("seed.jsonl");
    let config = seed
        .lines()
        .find(|line| line.starts_with("{\"config\""))
        .unwrap();
    let observed = r#"{"id": "00000000-0000-0000-0000-000000000001", "module_decision": "activate", "operator_decision": "none", "cancellable": true}"#;
    let twice = observed.replace("true}", "true, \"cancellable\": false}");
    let mut not_utf8 = seed.clone().into_bytes();
    not_utf8.extend_from_slice(b"{\"at_ms\": 7\xff}\n");
    let traces = [
        seed.replacen("\"deactivate\"", "\"Maybe\"", 1).into_bytes(),
        seed.replacen(config, "# no config", 1).into_bytes(),
        format!("{seed}{{\"at_ms\": 599}}\n").into_bytes(),
        format!("{seed}{{\"observed\": [{observed}, {observed}]}}\n").into_bytes(),
        format!("{seed}{{\"at_ms\": 600{}}}\n", " ".repeat(1 << 20)).into_bytes(),
        format!("{seed}{{\"observed\": [{twice}]}}\n").into_bytes(),
        not_utf8,
    ];
    let doc = doc();
    for trace in traces {
        let error = replay(
            trace.as_slice(),
            std::io::sink(),
            &Options::default(),
            false,
        )
        .unwrap_err();
        let shown = format!("error: recording.jsonl: {error}\n");
        assert!(doc.contains(&shown), "{shown}");
    }
}

#[test]
fn the_shown_settings_error_is_the_error() {
    let text = "/**:\n  ros__parameters:\n    cooperation:\n      polices:\n        lane-change: optional\n";
    let error = cooperation_adapters::settings::parse_within(text, &MAX_LIMITS).unwrap_err();
    let shown = format!("error: cooperation.param.yaml: {error}\n");
    assert!(doc().contains(&shown), "{shown}");
}
