//! Reading `spec/cooperation.md` and the sources as text: the spec's tables, its tags and the
//! sections they sit in, the tags a text mentions, and the Rust files under a directory.
//!
//! The one reader of these things: the model checker reads the spec's tables and writes the
//! traceability matrix with it, and the root crate's spec-sync tests include this very file.
//! It needs nothing but `std`.

use std::collections::BTreeSet;
use std::path::Path;

/// A tag the spec defines (`#### [TAG] …`), where it is defined.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tag {
    /// The tag, `COOP-REG-NEW.1`.
    pub tag: String,
    /// The number of the `## N.` section it sits in; 0 before the first.
    pub section: u32,
    /// The nearest `##` or `###` heading above it.
    pub heading: String,
}

/// Every tag the spec defines, in the order written.
#[must_use]
pub fn tags(spec: &str) -> Vec<Tag> {
    let mut section = 0;
    let mut heading = String::new();
    let mut tags = Vec::new();
    for line in spec.lines() {
        if let Some(rest) = line.strip_prefix("## ") {
            section = rest
                .split('.')
                .next()
                .and_then(|n| n.trim().parse().ok())
                .unwrap_or(0);
            heading = rest.trim().to_owned();
        } else if let Some(rest) = line.strip_prefix("### ") {
            heading = rest.trim().to_owned();
        } else if let Some((tag, _)) = line.strip_prefix("#### [").and_then(|r| r.split_once(']')) {
            tags.push(Tag {
                tag: tag.to_owned(),
                section,
                heading: heading.clone(),
            });
        }
    }
    tags
}

/// Every `[COOP-…]` tag written anywhere in `text`.
#[must_use]
pub fn mentioned_tags(text: &str) -> BTreeSet<String> {
    text.split('[')
        .skip(1)
        .filter_map(|rest| rest.split(']').next())
        .filter(|tag| tag.starts_with("COOP-") && !tag.contains(char::is_whitespace))
        .map(str::to_owned)
        .collect()
}

/// The rows of the first Markdown table whose header line starts with `header`, as trimmed
/// cells, the separator line skipped; `None` if there is no such table, or its second line is
/// not a separator.
#[must_use]
pub fn table_rows<'a>(spec: &'a str, header: &str) -> Option<Vec<Vec<&'a str>>> {
    let mut lines = spec.lines().skip_while(|line| !line.starts_with(header));
    lines.next()?;
    if !lines.next()?.starts_with("|---") {
        return None;
    }
    Some(
        lines
            .take_while(|line| line.starts_with('|'))
            .map(|line| line.trim_matches('|').split('|').map(str::trim).collect())
            .collect(),
    )
}

/// The `.rs` files under `dir`, subdirectories included, with their text, sorted by their
/// path relative to `dir` (`state.rs`, `rtc/adapter.rs`). Unreadable entries are left out.
#[must_use]
pub fn rust_sources(dir: &Path) -> Vec<(String, String)> {
    fn walk(root: &Path, dir: &Path, files: &mut Vec<(String, String)>) {
        for path in std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|entry| entry.path())
        {
            if path.is_dir() {
                walk(root, &path, files);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let name = path
                    .strip_prefix(root)
                    .unwrap_or(&path)
                    .to_string_lossy()
                    .replace('\\', "/");
                if let Ok(text) = std::fs::read_to_string(&path) {
                    files.push((name, text));
                }
            }
        }
    }
    let mut files = Vec::new();
    walk(dir, dir, &mut files);
    files.sort();
    files
}
