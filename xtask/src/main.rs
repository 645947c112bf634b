//! `cargo xtask`: the repository's generated documentation, written and checked.
//!
//! ```text
//! cargo xtask docs [--check]          the spec's diagrams, docs/traceability.md,
//!                                     docs/witnesses.md and docs/counts.md; with --check,
//!                                     only compare; either way, also check that no page
//!                                     repeats a pinned count, that the reach table agrees
//!                                     with the pins, and that every `Type::item` a page
//!                                     names is defined in the sources
//! cargo xtask reach [--full] [--only BOUNDS]
//!                                     measure the reach table of docs/reach.md
//! ```
//!
//! Exit status: 0 done (or current), 1 stale or a check failed, 2 bad usage.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use xtask::{counts, diagrams, names, reach, traceability, witnesses};

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

const USAGE: &str = "usage:
  cargo xtask docs [--check]
  cargo xtask reach [--full] [--only BOUNDS]";

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// One generated page: writes it, or with `check` only compares. Whether it is current.
fn page(root: &Path, path: &str, text: &str, check: bool) -> Result<bool, String> {
    let file = root.join(path);
    let current = std::fs::read_to_string(&file).unwrap_or_default();
    if current == text {
        println!("{path} is current");
        return Ok(true);
    }
    if check {
        println!("{path} is stale: run `cargo xtask docs`");
        return Ok(false);
    }
    std::fs::write(&file, text).map_err(|e| format!("{path}: {e}"))?;
    println!("wrote {path}");
    Ok(true)
}

/// `docs [--check]`.
fn docs(args: &[String]) -> Result<bool, String> {
    let check = match args {
        [] => false,
        [flag] if flag == "--check" => true,
        _ => return Err(USAGE.to_owned()),
    };
    let root = root();
    let spec_path = "spec/cooperation.md";
    let spec = std::fs::read_to_string(root.join(spec_path)).map_err(|e| format!("{e}"))?;
    let mut ok = page(&root, spec_path, &diagrams::regenerate(&spec), check)?;
    let rows = traceability::rows(&root);
    let gaps = traceability::gaps(&rows);
    for gap in &gaps {
        println!("gap: {gap}");
    }
    ok &= gaps.is_empty();
    ok &= page(
        &root,
        traceability::PAGE,
        &traceability::markdown(&rows),
        check,
    )?;
    ok &= page(&root, witnesses::PAGE, &witnesses::page(), check)?;
    ok &= page(&root, counts::PAGE, &counts::page(), check)?;
    let performance = std::fs::read_to_string(root.join(reach::PAGE)).unwrap_or_default();
    let problems: Vec<String> = counts::repeated(&root)
        .into_iter()
        .chain(reach::disagreements(&performance))
        .chain(names::unknown(&root))
        .collect();
    for problem in &problems {
        println!("{problem}");
    }
    Ok(ok && problems.is_empty())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.split_first() {
        Some((command, rest)) if command == "docs" => docs(rest),
        Some((command, rest)) if command == "reach" => reach::run(&root(), rest),
        _ => Err(USAGE.to_owned()),
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(message) => {
            eprintln!("{message}");
            ExitCode::from(2)
        }
    }
}
