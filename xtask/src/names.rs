//! The code the pages name: every `` `Type::item` `` that the spec, the README or a page of
//! `docs/` writes names a type and an item that the workspace's Rust sources define, so that a
//! renamed or removed function cannot stay named in the text that describes it.
//!
//! The check is by name, not by scope: `item` must be defined somewhere in the sources (a
//! function, constant, type, module, enum variant or field), not necessarily on `Type`. That is
//! enough to catch what happens in practice, a rename or a removal, without a Rust parser.

use std::collections::BTreeSet;
use std::path::Path;

/// The folders of Rust sources whose definitions the pages may name.
pub const SOURCES: [&str; 8] = [
    "src",
    "adapters/src",
    "dds/src",
    "server/src",
    "cpp/src",
    "models/src",
    "trace/src",
    "xtask/src",
];

/// Pages that record past runs and name the code as it was then; they are not checked.
pub const RECORDS: [&str; 3] = [
    "docs/mutation.md",
    "docs/performance-history.md",
    "docs/performance-history-cpp.md",
];

/// Types of other crates and of the standard library that the pages name.
pub const FOREIGN: [&str; 4] = ["Arc", "DashMap", "DfsChecker", "Default"];

/// Methods a derived or standard trait gives a type of ours.
const DERIVED: [&str; 7] = [
    "clone",
    "cmp",
    "default",
    "eq",
    "fmt",
    "hash",
    "partial_cmp",
];

/// The names the sources define: `(types, items)`.
#[must_use]
pub fn definitions(root: &Path) -> (BTreeSet<String>, BTreeSet<String>) {
    let mut types = BTreeSet::new();
    let mut items = BTreeSet::new();
    for folder in SOURCES {
        for file in rust_files(&root.join(folder)) {
            let text = std::fs::read_to_string(file).unwrap_or_default();
            for line in text.lines() {
                define(line, &mut types, &mut items);
            }
        }
    }
    (types, items)
}

/// Every `.rs` file under `folder`, in a fixed order.
fn rust_files(folder: &Path) -> Vec<std::path::PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![folder.to_path_buf()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The leading identifier of `text`, if it starts with one.
fn identifier(text: &str) -> Option<&str> {
    let end = text
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(text.len());
    let name = text.get(..end)?;
    name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        .then_some(name)
}

/// What one line of Rust defines: the name after a defining keyword, and an enum variant or a
/// field (a line that starts with a name followed by `,`, `(`, `{`, `:` or `=`).
fn define(line: &str, types: &mut BTreeSet<String>, items: &mut BTreeSet<String>) {
    let words: Vec<&str> = line.split_whitespace().collect();
    for pair in words.windows(2) {
        if let [keyword, rest] = pair {
            let Some(name) = identifier(rest) else {
                continue;
            };
            match *keyword {
                "struct" | "enum" | "trait" | "type" | "union" => {
                    types.insert(name.to_owned());
                    items.insert(name.to_owned());
                }
                "fn" | "const" | "static" | "mod" => {
                    items.insert(name.to_owned());
                }
                _ => {}
            }
        }
    }
    let mut rest = line.trim_start();
    for visibility in ["pub(crate) ", "pub(super) ", "pub "] {
        rest = rest.strip_prefix(visibility).unwrap_or(rest);
    }
    if let Some(name) = identifier(rest) {
        let after = rest[name.len()..].trim_start();
        if after.starts_with([',', '(', '{', ':', '=']) && !after.starts_with("::") {
            items.insert(name.to_owned());
        }
    }
}

/// The `` `Type::item` `` paths a page writes (an optional `()` after them), with their lines.
#[must_use]
pub fn paths(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (at, line) in text.lines().enumerate() {
        for (index, quoted) in line.split('`').enumerate() {
            // The odd pieces are inside backticks.
            if index % 2 == 0 {
                continue;
            }
            let path = quoted.strip_suffix("()").unwrap_or(quoted);
            let segments: Vec<&str> = path.split("::").collect();
            let whole = segments.len() >= 2
                && segments
                    .iter()
                    .all(|s| identifier(s).is_some_and(|i| i == *s));
            if whole {
                found.push((at + 1, path.to_owned()));
            }
        }
    }
    found
}

/// Every `Type::item` a checked page names whose type or item the sources do not define, as
/// `page:line: message`. A path of more than two segments is checked only when it starts at one
/// of the workspace's crates (`cooperation_adapters::rtc::Rtc::find`); others name C++, ROS or
/// another crate's code.
#[must_use]
pub fn unknown(root: &Path) -> Vec<String> {
    let (types, items) = definitions(root);
    let mut pages: Vec<String> = std::fs::read_dir(root.join("docs"))
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|entry| entry.file_name().to_str().map(|n| format!("docs/{n}")))
        .filter(|page| page.ends_with(".md") && !RECORDS.contains(&page.as_str()))
        .collect();
    pages.extend(["README.md".to_owned(), "spec/cooperation.md".to_owned()]);
    pages.sort();
    let mut problems = Vec::new();
    for page in pages {
        let text = std::fs::read_to_string(root.join(&page)).unwrap_or_default();
        problems.extend(
            unknown_in(&text, &types, &items)
                .into_iter()
                .map(|(line, problem)| format!("{page}:{line}: {problem}")),
        );
    }
    problems
}

/// [`unknown`] for one page's text.
#[must_use]
pub fn unknown_in(
    text: &str,
    types: &BTreeSet<String>,
    items: &BTreeSet<String>,
) -> Vec<(usize, String)> {
    let mut problems = Vec::new();
    for (line, path) in paths(text) {
        let segments: Vec<&str> = path.split("::").collect();
        let (Some(&item), Some(&owner)) = (segments.last(), segments.iter().rev().nth(1)) else {
            continue;
        };
        // A longer path is ours only from one of our crates (`sip::Hasher::write` is not).
        let ours = segments.len() == 2
            || segments
                .first()
                .is_some_and(|c| c.starts_with("cooperation"));
        if !ours || !owner.starts_with(|c: char| c.is_ascii_uppercase()) || FOREIGN.contains(&owner)
        {
            continue;
        }
        if !types.contains(owner) {
            problems.push((line, format!("`{path}`: no type `{owner}` in the sources")));
        } else if !items.contains(item) && !DERIVED.contains(&item) {
            problems.push((
                line,
                format!("`{path}`: nothing named `{item}` in the sources"),
            ));
        }
    }
    problems
}
