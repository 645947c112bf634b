//! The traceability matrix, generated from the sources: for every tag of
//! `spec/cooperation.md`, its spec section, the places in `src/` and `adapters/src/` that carry it (file and
//! enclosing function), the model properties named after it, and the tests named after it.
//! `cargo xtask docs` writes it to `docs/traceability.md`; a test fails when the
//! checked-in matrix is stale or a rule lacks code, a property or a test.

use core::fmt::Write as _;
use std::path::Path;

use cooperation_models::model::spec::text;

/// The page.
pub const PAGE: &str = "docs/traceability.md";

/// One tag's row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    /// The tag, for example `COOP-CMD-UNKNOWN.1`.
    pub tag: String,
    /// The spec section it is defined in (its `##` number).
    pub section: u32,
    /// The spec subsection heading it sits under.
    pub heading: String,
    /// `file::function` places in `src/` and `adapters/src/` that carry `[tag]`.
    pub code: Vec<String>,
    /// Model properties named after it.
    pub properties: Vec<String>,
    /// Whether one of them is a safety (`always`) property, not only a reachability one.
    pub safety: bool,
    /// Tests named after it (`file::function`).
    pub tests: Vec<String>,
}

/// The tags of the spec's sections 5 (rules), 6 (definitions), 8 (invariants) and 9
/// (deviations), with the heading they sit under.
fn spec_tags(spec: &str) -> Vec<(String, u32, String)> {
    text::tags(spec)
        .into_iter()
        .filter(|tag| matches!(tag.section, 5 | 6 | 8 | 9))
        .map(|tag| (tag.tag, tag.section, tag.heading))
        .collect()
}

/// The name of the function a line sits in: the nearest `fn name` at or above it.
fn enclosing_function(lines: &[&str], at: usize) -> String {
    lines
        .iter()
        .take(at + 1)
        .rev()
        .find_map(|line| function_name(line))
        .unwrap_or_else(|| "(item)".to_owned())
}

/// The name a line declares if it starts a function (`fn`, `const fn`, each maybe with a
/// visibility: `pub`, `pub(crate)`, `pub(super)`).
fn function_name(line: &str) -> Option<String> {
    let mut rest = line.trim_start();
    if let Some(after) = rest.strip_prefix("pub") {
        rest = match after.strip_prefix('(') {
            Some(scope) => scope.split_once(')')?.1,
            None => after,
        }
        .trim_start();
    }
    let rest = rest.strip_prefix("const ").unwrap_or(rest);
    let rest = rest.strip_prefix("fn ")?;
    Some(rest.split(['(', '<']).next().unwrap_or(rest).to_owned())
}

/// The name of the item a doc comment at `at` documents: the first line after it that is not
/// a doc comment or an attribute.
fn documented_item(lines: &[&str], at: usize) -> String {
    let item = lines
        .iter()
        .skip(at)
        .map(|line| line.trim_start())
        .find(|line| !line.starts_with("///") && !line.starts_with("#["))
        .unwrap_or("");
    let mut words = item
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
        .skip_while(|w| {
            matches!(
                *w,
                "pub" | "crate" | "super" | "const" | "fn" | "struct" | "enum" | "impl"
            )
        });
    words.next().unwrap_or("(item)").to_owned()
}

/// Where a tag written on line `at` of `text` belongs: a doc comment (`///`) to the item it
/// documents, a plain comment (`//`) to the function it sits in; `None` for anything else.
fn place(lines: &[&str], at: usize) -> Option<String> {
    let line = lines.get(at)?.trim_start();
    if line.starts_with("//!") {
        None
    } else if line.starts_with("///") {
        Some(documented_item(lines, at))
    } else if line.starts_with("//") {
        Some(enclosing_function(lines, at))
    } else {
        None
    }
}

/// The tags a property's name is named after: the comma-separated tags before its first `:`
/// or ` is reachable`, each without what follows its first space (`COOP-X.1 (network)`).
fn names(property: &str) -> impl Iterator<Item = &str> {
    let head = property
        .split(':')
        .next()
        .unwrap_or_default()
        .trim_end_matches(" is reachable");
    head.split(',')
        .filter_map(|tag| tag.split_whitespace().next())
        .filter(|tag| tag.starts_with("COOP-"))
}

/// The shipped code: the core and its adapters.
const CODE: [&str; 2] = ["src", "adapters/src"];
/// The tests named after tags: the core's, the adapters' and the models'.
const TESTS: [&str; 3] = ["tests", "adapters/tests", "models/tests"];

/// Every row of the matrix, from the repository at `root`.
#[must_use]
pub fn rows(root: &Path) -> Vec<Row> {
    let spec = std::fs::read_to_string(root.join("spec/cooperation.md")).unwrap_or_default();
    // Every file by its path from the repository's root.
    let sources = |dirs: &[&str]| -> Vec<(String, String)> {
        dirs.iter()
            .flat_map(|dir| {
                text::rust_sources(&root.join(dir))
                    .into_iter()
                    .map(move |(name, text)| (format!("{dir}/{name}"), text))
            })
            .collect()
    };
    let code = sources(&CODE);
    let tests = sources(&TESTS);
    let always = |e: &stateright::Expectation| matches!(e, stateright::Expectation::Always);
    let properties: Vec<(&'static str, bool)> = cooperation_models::model::sequential::properties()
        .iter()
        .map(|p| (p.name, always(&p.expectation)))
        .chain(
            cooperation_models::model::network::properties()
                .iter()
                .map(|p| (p.name, always(&p.expectation))),
        )
        .chain(
            cooperation_models::model::rtc::properties()
                .iter()
                .map(|p| (p.name, always(&p.expectation))),
        )
        .chain(
            cooperation_models::model::engine::properties()
                .iter()
                .map(|p| (p.name, always(&p.expectation))),
        )
        .chain(
            cooperation_models::model::relay::properties()
                .iter()
                .map(|p| (p.name, always(&p.expectation))),
        )
        .collect();
    spec_tags(&spec)
        .into_iter()
        .map(|(tag, section, heading)| {
            let marker = format!("[{tag}]");
            let mut places = Vec::new();
            for (file, text) in &code {
                let lines: Vec<&str> = text.lines().collect();
                for (at, line) in lines.iter().enumerate() {
                    if !line.contains(&marker) {
                        continue;
                    }
                    if let Some(item) = place(&lines, at) {
                        let place = format!("{file}::{item}");
                        if !places.contains(&place) {
                            places.push(place);
                        }
                    }
                }
            }
            let family = tag.split('-').take(2).collect::<Vec<_>>().join("-");
            let matching: Vec<&(&str, bool)> = properties
                .iter()
                .filter(|(p, _)| {
                    names(p).any(|named| named == tag)
                        || (family == "COOP-INV" && p.starts_with("COOP-INV-*"))
                })
                .collect();
            let safety = matching.iter().any(|(_, always)| *always);
            let named: Vec<String> = matching.iter().map(|(p, _)| (*p).to_owned()).collect();
            let test_name = tag.to_lowercase().replace(['-', '.'], "_");
            let tested: Vec<String> = tests
                .iter()
                .filter(|(_, text)| {
                    text.contains(&format!("fn {test_name}("))
                        || text.contains(&format!("fn {test_name}_"))
                })
                .map(|(file, _)| format!("{file}::{test_name}"))
                .collect();
            Row {
                tag,
                section,
                heading,
                code: places,
                properties: named,
                safety,
                tests: tested,
            }
        })
        .collect()
}

/// What a rule row lacks: a rule of §5 needs code, a property and a test; every other tag code
/// (or, for a deviation, a test) and a test.
#[must_use]
pub fn gaps(rows: &[Row]) -> Vec<String> {
    let mut gaps = Vec::new();
    for row in rows {
        let needs_code = row.section != 9;
        let needs_property = row.section == 5;
        if needs_code && row.code.is_empty() {
            gaps.push(format!(
                "{}: no place in src/ or adapters/src/ carries [{}]",
                row.tag, row.tag
            ));
        }
        if needs_property && row.properties.is_empty() {
            gaps.push(format!("{}: no model property is named after it", row.tag));
        } else if needs_property && !row.safety {
            gaps.push(format!(
                "{}: its only model properties are reachability, which take the library's word \
                 for which rule fired",
                row.tag
            ));
        }
        if row.tests.is_empty() {
            gaps.push(format!("{}: no test is named after it", row.tag));
        }
    }
    gaps
}

/// The matrix as Markdown.
#[must_use]
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::from(
        "# Traceability\n\nGenerated by `cargo xtask docs` from \
         `spec/cooperation.md`, `src/`, `adapters/src/`, the models' properties and the tests; \
         `xtask/tests/traceability.rs` fails when this file is stale or a rule lacks code, a \
         property or a test. Do not edit by hand.\n\n\
         | Tag | Spec | Code | Model properties | Tests |\n|---|---|---|---|---|\n",
    );
    for row in rows {
        let list = |items: &[String]| {
            if items.is_empty() {
                "—".to_owned()
            } else {
                items
                    .iter()
                    .map(|i| format!("`{i}`"))
                    .collect::<Vec<_>>()
                    .join("<br>")
            }
        };
        let _ = writeln!(
            out,
            "| `{}` | §{} {} | {} | {} | {} |",
            row.tag,
            row.section,
            row.heading,
            list(&row.code),
            list(&row.properties),
            list(&row.tests)
        );
    }
    out
}
