//! `cooperation-trace`: replays a cooperation trace, or validates observed statuses against
//! the spec. The work is the library's; this is the command line.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Write};
use std::process::ExitCode;

use cooperation_trace::{
    parse_config, replay, validate, verdict_json, verdict_text, ErrorKind, Options, ReadLimits,
    TraceError, Verdict, MAX_LIMITS,
};

const USAGE: &str = "\
usage: cooperation-trace replay [--json] [--config FILE | --settings FILE] TRACE
       cooperation-trace validate [--json] [--config FILE | --settings FILE] TRACE

TRACE is a JSON-lines trace (docs/trace-format.md), or - for standard input.

replay     prints, after each step, the rule that fired (or the rejection and its rule), then
           every live scene's status and merged decision; --json prints one JSON object per
           step instead.
validate   replays the inputs and compares every `observed` record with the spec; prints the
           first departure (line, step, scene, field, expected and observed, the rule
           involved), or that the trace conforms; --json prints the verdict as JSON.
--config   the configuration (modules, default policies, limits) as a JSON file, for a trace
           without a `config` line.
--settings the configuration as a ROS 2 parameter file (docs/settings.md), in place of
           --config.

exit codes: 0 the trace replayed / conforms; 1 it departs (validate); 2 malformed input,
an unreadable file, output that cannot be written (standard output closed, a broken pipe) or
bad usage.";

/// Exit code for malformed input, unreadable files, output that cannot be written and usage
/// errors: the tool could not do what it was asked.
const MALFORMED: u8 = 2;

/// At most this many characters of an argument are quoted in a message.
const QUOTED: usize = 64;

/// An argument, quoted and cut short if long.
fn quoted(arg: &str) -> String {
    match arg.char_indices().nth(QUOTED) {
        None => format!("{arg:?}"),
        Some((end, _)) => format!("{:?}…", arg.get(..end).unwrap_or_default()),
    }
}

/// Writes `error: message` on standard error. Nothing is left to say if that fails.
fn report(message: &str) -> ExitCode {
    let _ = writeln!(io::stderr().lock(), "error: {message}");
    ExitCode::from(MALFORMED)
}

/// Whether standard output was closed when the tool started. The Rust runtime then opens
/// `/dev/null` in its place, read-write, and everything written would be lost without an
/// error; `>/dev/null` from a shell opens it write-only, and is output thrown away on purpose.
#[cfg(unix)]
fn stdout_closed() -> bool {
    use std::os::fd::AsFd;
    use std::os::unix::fs::{FileTypeExt, MetadataExt};
    let Ok(fd) = io::stdout().as_fd().try_clone_to_owned() else {
        return false;
    };
    let mut out = File::from(fd);
    let (Ok(meta), Ok(null)) = (out.metadata(), std::fs::metadata("/dev/null")) else {
        return false;
    };
    meta.file_type().is_char_device()
        && meta.rdev() == null.rdev()
        && out.read(&mut [0_u8; 1]).is_ok()
}

#[cfg(not(unix))]
fn stdout_closed() -> bool {
    false
}

enum Mode {
    Replay,
    Validate,
}

struct Args {
    mode: Mode,
    json: bool,
    config: Option<Source>,
    trace: String,
}

/// Where the configuration comes from, when not from the trace.
enum Source {
    /// `--config FILE`: JSON.
    Json(String),
    /// `--settings FILE`: a ROS 2 parameter file.
    Settings(String),
}

fn parse_args(args: &[String]) -> Result<Args, String> {
    let mut args = args.iter();
    let mode = match args.next().map(String::as_str) {
        Some("replay") => Mode::Replay,
        Some("validate") => Mode::Validate,
        Some(other) => return Err(format!("unknown command {}", quoted(other))),
        None => return Err("a command is needed".into()),
    };
    let mut json = false;
    let mut config = None;
    let mut trace = None;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--json" => json = true,
            option @ ("--config" | "--settings") => {
                let Some(file) = args.next() else {
                    return Err(format!("{option} needs a file"));
                };
                let source = if option == "--config" {
                    Source::Json(file.clone())
                } else {
                    Source::Settings(file.clone())
                };
                config = match (config, source) {
                    (None, source) => Some(source),
                    (Some(Source::Json(_)), Source::Json(_)) => {
                        return Err("--config is given twice".into())
                    }
                    (Some(Source::Settings(_)), Source::Settings(_)) => {
                        return Err("--settings is given twice".into())
                    }
                    (Some(_), _) => {
                        return Err("--config and --settings both give the configuration; \
                                    give one"
                            .into())
                    }
                };
            }
            option if option.starts_with("--") => {
                return Err(format!("unknown option {}", quoted(option)))
            }
            file if trace.is_none() => trace = Some(file.to_owned()),
            extra => return Err(format!("one trace only; {} is one too many", quoted(extra))),
        }
    }
    let trace = trace.ok_or("a trace file is needed (or - for standard input)")?;
    Ok(Args {
        mode,
        json,
        config,
        trace,
    })
}

/// Reads a configuration file (`--config` or `--settings`), at most one line's length of the
/// trace. A settings file's limits are bounded as a `config` line's are.
fn read_config(source: &Source, limit: usize) -> Result<cooperation::Config, String> {
    match source {
        Source::Json(path) => {
            parse_config(&read_text(path, limit)?).map_err(|error| format!("{path}: {error}"))
        }
        Source::Settings(path) => {
            cooperation_adapters::settings::parse_within(&read_text(path, limit)?, &MAX_LIMITS)
                .map_err(|error| format!("{path}: {error}"))
        }
    }
}

/// A file's text: UTF-8, at most `limit` bytes.
fn read_text(path: &str, limit: usize) -> Result<String, String> {
    let file = File::open(path).map_err(|error| format!("{path}: {error}"))?;
    let mut bytes = Vec::new();
    let cap = u64::try_from(limit).unwrap_or(u64::MAX).saturating_add(1);
    file.take(cap)
        .read_to_end(&mut bytes)
        .map_err(|error| format!("{path}: {error}"))?;
    if bytes.len() > limit {
        return Err(format!("{path}: the file is longer than {limit} bytes"));
    }
    String::from_utf8(bytes).map_err(|error| {
        let offset = error.utf8_error().valid_up_to();
        format!("{path}: the file is not UTF-8 at byte {offset}")
    })
}

fn open(path: &str) -> Result<Box<dyn BufRead>, String> {
    if path == "-" {
        return Ok(Box::new(io::stdin().lock()));
    }
    let file = File::open(path).map_err(|error| format!("{path}: {error}"))?;
    Ok(Box::new(BufReader::new(file)))
}

fn fail(path: &str, error: &TraceError) -> ExitCode {
    report(&format!("{path}: {error}"))
}

/// The error for output that cannot be written.
const CLOSED: &str = "cannot write the output: standard output is closed";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|arg| arg == "--help" || arg == "-h") {
        if stdout_closed() {
            return report(CLOSED);
        }
        return match writeln!(io::stdout().lock(), "{USAGE}") {
            Ok(()) => ExitCode::SUCCESS,
            Err(error) => report(&format!("cannot write the output: {error}")),
        };
    }
    let args = match parse_args(&args) {
        Ok(args) => args,
        Err(message) => return report(&format!("{message} (see cooperation-trace --help)")),
    };
    if stdout_closed() {
        return report(CLOSED);
    }
    let limits = ReadLimits::default();
    let config = match args
        .config
        .as_ref()
        .map(|source| read_config(source, limits.max_line_bytes))
    {
        None => None,
        Some(Ok(config)) => Some(config),
        Some(Err(message)) => return report(&message),
    };
    let input = match open(&args.trace) {
        Ok(input) => input,
        Err(message) => return report(&message),
    };
    let options = Options { limits, config };
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    match args.mode {
        Mode::Replay => {
            let result = replay(input, &mut out, &options, args.json);
            // Whatever was replayed before an error is shown before the error.
            let flushed = out.flush();
            match (result, flushed) {
                // The output's failure is not the trace's.
                (Err(error), _) if matches!(error.kind, ErrorKind::Write { .. }) => {
                    report(&error.to_string())
                }
                (Err(error), _) => fail(&args.trace, &error),
                (Ok(_), Err(error)) => report(&format!("cannot write the output: {error}")),
                (Ok(_), Ok(())) => ExitCode::SUCCESS,
            }
        }
        Mode::Validate => {
            let verdict = match validate(input, &options) {
                Ok(verdict) => verdict,
                Err(error) => return fail(&args.trace, &error),
            };
            let text = if args.json {
                verdict_json(&verdict)
            } else {
                Ok(verdict_text(&verdict))
            };
            let written = text.map_err(|error| error.to_string()).and_then(|text| {
                out.write_all(text.as_bytes())
                    .and_then(|()| out.flush())
                    .map_err(|error| format!("cannot write the output: {error}"))
            });
            match (written, verdict) {
                (Err(message), _) => report(&message),
                (Ok(()), Verdict::Conforms { .. }) => ExitCode::SUCCESS,
                (Ok(()), Verdict::Departs(_)) => ExitCode::from(1),
            }
        }
    }
}
