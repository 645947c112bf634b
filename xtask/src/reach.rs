//! `cargo xtask reach`: how far the exhaustive check gets, configuration by configuration,
//! with the checker's raw throughput on a trivial model beside it; the table of
//! `docs/reach.md`.
//!
//! The checker is built in release, and each configuration runs as its own child process
//! (`cooperation-models check … --summary`), so that its peak memory is its own.

use std::path::{Path, PathBuf};
use std::process::Command;

use cooperation_models::check::pins;
use cooperation_models::check::summary::{Summary, PREFIX};

/// The page the table is in.
pub const PAGE: &str = "docs/reach.md";

/// One row of the table.
struct Config {
    model: &'static str,
    bounds: &'static str,
    search: &'static str,
    args: &'static [&'static str],
    threads: &'static [usize],
    timeout_s: Option<u64>,
}

const fn config(
    model: &'static str,
    bounds: &'static str,
    search: &'static str,
    args: &'static [&'static str],
) -> Config {
    Config {
        model,
        bounds,
        search,
        args,
        threads: &[1, 2],
        timeout_s: None,
    }
}

/// The default table: every configuration CI checks, and the trivial model.
const QUICK: &[Config] = &[
    config(
        "trivial",
        "7^8 counters, 64 B",
        "BFS",
        &["--model", "trivial", "--bytes", "64"],
    ),
    config(
        "trivial",
        "7^8 counters, 2 KiB",
        "BFS",
        &["--model", "trivial"],
    ),
    config(
        "sequential",
        "1 × 2",
        "DFS, symmetry",
        &["--modules", "1", "--scenes", "2"],
    ),
    config(
        "sequential",
        "1 × 2",
        "BFS",
        &["--modules", "1", "--scenes", "2", "--no-symmetry"],
    ),
    config("sequential", "2 × 2", "DFS, symmetry", &["--scenes", "2"]),
    config(
        "sequential",
        "2 × 2",
        "BFS",
        &["--scenes", "2", "--no-symmetry"],
    ),
    config("sequential", "2 × 3 (CI)", "DFS, symmetry", &[]),
    config(
        "sequential, stalled steps kept (`--keep-stalled`)",
        "2 × 3",
        "DFS, symmetry",
        &["--keep-stalled"],
    ),
    config(
        "sequential, hashed table",
        "2 × 3 (CI)",
        "DFS, symmetry",
        &["--table", "hashed"],
    ),
    config(
        "sequential, hashed table",
        "1 × 3 (CI)",
        "BFS",
        &["--modules", "1", "--table", "hashed", "--no-symmetry"],
    ),
    config("rtc", "2 × 3 (CI)", "DFS, symmetry", &["--model", "rtc"]),
    config("network", "2 ids (CI)", "BFS", &["--model", "network"]),
    config(
        "network, 1 operator, status views",
        "2 ids (CI)",
        "BFS",
        &[
            "--model",
            "network",
            "--operators",
            "1",
            "--views",
            "statuses",
        ],
    ),
];

/// The larger configurations `--full` adds, on 2 threads, each stopped after `timeout_s`.
const FULL: &[Config] = &[
    large("sequential", "2 × 3", "BFS", &["--no-symmetry"], 240),
    large(
        "sequential",
        "3 × 3 (CI)",
        "DFS, symmetry",
        &["--modules", "3"],
        900,
    ),
    large(
        "sequential, stalled steps kept (`--keep-stalled`)",
        "3 × 3",
        "DFS, symmetry",
        &["--modules", "3", "--keep-stalled"],
        300,
    ),
    large(
        "network",
        "3 ids",
        "BFS",
        &["--model", "network", "--scenes", "3"],
        300,
    ),
    large(
        "sequential",
        "3 × 4",
        "DFS, symmetry",
        &["--modules", "3", "--scenes", "4"],
        600,
    ),
];

const fn large(
    model: &'static str,
    bounds: &'static str,
    search: &'static str,
    args: &'static [&'static str],
    timeout_s: u64,
) -> Config {
    Config {
        model,
        bounds,
        search,
        args,
        threads: &[2],
        timeout_s: Some(timeout_s),
    }
}

/// `reach [--full] [--only BOUNDS]`: measures the configurations and writes the table into
/// [`PAGE`]; without `--full`, the larger configurations' rows of an earlier run stay, marked.
/// `--only "3 × 4"` runs the configurations with those bounds alone and prints their rows
/// without writing.
///
/// # Errors
/// A bad option, or a build, a check or the page that fails.
pub fn run(root: &Path, args: &[String]) -> Result<bool, String> {
    let mut full = false;
    let mut only = None;
    let mut rest = args.iter();
    while let Some(flag) = rest.next() {
        match flag.as_str() {
            "--full" => full = true,
            "--only" => only = Some(rest.next().ok_or("--only needs bounds")?.clone()),
            other => return Err(format!("unknown option {other:?}")),
        }
    }
    let exe = checker(root)?;
    let configs = QUICK
        .iter()
        .chain(if full || only.is_some() { FULL } else { &[] })
        .filter(|c| only.as_ref().map_or(true, |o| c.bounds == o.as_str()));
    let mut table = String::from(
        "| model | bounds (modules × ids) | search | threads | unique states | generated | \
         time | unique/s | generated/s | peak RSS | bytes/unique state | complete |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for config in configs {
        for &threads in config.threads {
            let mut command = Command::new(&exe);
            command.arg("check").args(config.args);
            command.args(["--threads", &threads.to_string(), "--summary"]);
            if let Some(timeout) = config.timeout_s {
                command.args(["--timeout", &timeout.to_string()]);
            }
            eprintln!(
                "reach: {} {} {}, {threads} thread(s)",
                config.model, config.bounds, config.search
            );
            let row = match measure(&mut command)? {
                Measured::Summary(summary) => row(config, threads, &summary),
                Measured::Died { how, last } => died(config, threads, &how, &last),
            };
            eprint!("{row}");
            table += &row;
        }
    }
    let page = root.join(PAGE);
    if only.is_some() {
        println!("{table}");
        return Ok(true);
    }
    if !full {
        table += &earlier_rows(&page, FULL)?;
    }
    println!("{table}");
    splice(&page, &table)?;
    println!("wrote {PAGE}");
    Ok(true)
}

/// Builds the checker in release and answers its path.
fn checker(root: &Path) -> Result<PathBuf, String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let built = Command::new(cargo)
        .args(["build", "--release", "-p", "cooperation-models"])
        .current_dir(root)
        .status()
        .map_err(|e| format!("cannot build the checker: {e}"))?;
    if !built.success() {
        return Err(format!("building the checker failed ({built})"));
    }
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    Ok(target.join("release").join("cooperation-models"))
}

/// Every row of the reach table in `page` whose configuration is pinned
/// ([`pins::find`]) and whose count disagrees with its pin, in words.
#[must_use]
pub fn disagreements(page: &str) -> Vec<String> {
    let mut found = Vec::new();
    for line in page.lines().filter(|line| line.starts_with("| ")) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let [model, bounds, search, _, unique, generated, ..] = cells.as_slice() else {
            continue;
        };
        let bounds = bounds.trim_end_matches(" (CI)");
        let Some(pin) = pins::find(model, bounds, search) else {
            continue;
        };
        let number = |cell: &str| cell.replace(',', "").parse::<usize>().ok();
        let complete = cells.last().is_some_and(|cell| cell.starts_with("yes"));
        if !complete {
            continue;
        }
        if number(unique) != Some(pin.unique) {
            found.push(format!(
                "{PAGE}: {model} {bounds} {search} reached {unique} states; {} pins {}",
                pin.test, pin.unique
            ));
        }
        if let Some(pinned) = pin.generated {
            if number(generated) != Some(pinned) {
                found.push(format!(
                    "{PAGE}: {model} {bounds} {search} generated {generated}; {} pins {pinned}",
                    pin.test
                ));
            }
        }
    }
    found
}

/// What a child check came to.
enum Measured {
    Summary(Summary),
    /// It ended without a summary (killed, say for want of memory): how, and its last progress
    /// line.
    Died {
        how: String,
        last: String,
    },
}

/// Runs the child, passing its progress through and keeping the last progress line.
fn measure(command: &mut Command) -> Result<Measured, String> {
    use std::io::BufRead;
    let mut child = command
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run the check: {e}"))?;
    let mut last = String::new();
    if let Some(stderr) = child.stderr.take() {
        for line in std::io::BufReader::new(stderr)
            .lines()
            .map_while(Result::ok)
        {
            eprintln!("{line}");
            if line.starts_with("checking:") || line.starts_with("done:") {
                last = line;
            }
        }
    }
    let output = child
        .wait_with_output()
        .map_err(|e| format!("cannot run the check: {e}"))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let summary = stdout
        .lines()
        .find_map(|l| l.strip_prefix(PREFIX))
        .map(serde_json::from_str::<Summary>);
    Ok(match summary {
        Some(summary) => Measured::Summary(summary.map_err(|e| e.to_string())?),
        None => {
            use std::os::unix::process::ExitStatusExt;
            let how = match output.status.signal() {
                Some(9) => "killed (signal 9; out of memory?)".to_owned(),
                Some(signal) => format!("killed (signal {signal})"),
                None => format!("failed ({})", output.status),
            };
            Measured::Died { how, last }
        }
    })
}

/// The row of a check that died: what its last progress line said.
fn died(config: &Config, threads: usize, how: &str, last: &str) -> String {
    format!(
        "| {} | {} | {} | {threads} | — | — | — | — | — | — | — | no: {how}; last progress: {} |\n",
        config.model,
        config.bounds,
        config.search,
        if last.is_empty() { "none" } else { last }
    )
}

fn row(config: &Config, threads: usize, s: &Summary) -> String {
    let rate = |n: usize| n as f64 / s.seconds.max(1e-9);
    let (rss, per_state) = match s.peak_rss_bytes {
        Some(bytes) => (
            format!("{:.0} MiB", bytes as f64 / (1024.0 * 1024.0)),
            format!("{:.0}", bytes as f64 / s.unique.max(1) as f64),
        ),
        None => ("—".to_owned(), "—".to_owned()),
    };
    format!(
        "| {} | {} | {} | {threads} | {} | {} | {:.1} s | {} | {} | {rss} | {per_state} | {} |\n",
        config.model,
        config.bounds,
        config.search,
        thousands(s.unique),
        thousands(s.generated),
        s.seconds,
        thousands(rate(s.unique) as usize),
        thousands(rate(s.generated) as usize),
        match (&s.stopped, config.timeout_s) {
            _ if s.complete => "yes".to_owned(),
            (Some(time), Some(limit)) if time == "the time limit" => {
                format!("no (stopped at {limit} s)")
            }
            (Some(why), _) => format!("no (stopped by {why})"),
            (None, _) => "no".to_owned(),
        }
    )
}

/// `n` with a comma between each group of three digits.
pub(crate) fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// The rows of `file`'s table for `configs`, each marked in its last column as from an
/// earlier run.
fn earlier_rows(file: &Path, configs: &[Config]) -> Result<String, String> {
    const EARLIER: &str = " (an earlier run)";
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut rows = String::new();
    for config in configs {
        let key = format!(
            "| {} | {} | {} |",
            config.model, config.bounds, config.search
        );
        for line in text.lines().filter(|line| line.starts_with(&key)) {
            match line.strip_suffix(" |") {
                Some(cells) if !cells.ends_with(EARLIER) => {
                    rows += &format!("{cells}{EARLIER} |\n");
                }
                _ => rows += &format!("{line}\n"),
            }
        }
    }
    Ok(rows)
}

/// Replaces the text between `<!-- generated: reach -->` and the next `<!-- end generated -->`.
fn splice(file: &Path, table: &str) -> Result<(), String> {
    const START: &str = "<!-- generated: reach -->";
    const END: &str = "<!-- end generated -->";
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let start = text
        .find(START)
        .ok_or_else(|| format!("{}: no {START} marker", file.display()))?;
    let end = text[start..]
        .find(END)
        .map(|i| start + i)
        .ok_or_else(|| format!("{}: no {END} after {START}", file.display()))?;
    let new = format!("{}{START}\n{table}{}", &text[..start], &text[end..]);
    std::fs::write(file, new).map_err(|e| format!("{}: {e}", file.display()))
}
