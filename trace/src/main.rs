//! `cooperation-trace`: replays a cooperation trace, or validates observed statuses against
//! the spec. The work is the library's; this is the command line.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Write};
use std::process::ExitCode;

use cooperation_trace::{
    parse_config, replay, validate, verdict_json, verdict_text, Options, ReadLimits, TraceError,
    Verdict,
};

const USAGE: &str = "\
usage: cooperation-trace replay [--json] [--config FILE] TRACE
       cooperation-trace validate [--json] [--config FILE] TRACE

TRACE is a JSON-lines trace (docs/trace-format.md), or - for standard input.

replay     prints, after each step, the rule that fired (or the rejection and its rule), then
           every live scene's status and merged decision; --json prints one JSON object per
           step instead.
validate   replays the inputs and compares every `observed` record with the spec; prints the
           first departure (line, step, scene, field, expected and observed, the rule
           involved), or that the trace conforms; --json prints the verdict as JSON.
--config   the configuration (modules, default policies, limits) as a JSON file, for a trace
           without a `config` line.

exit codes: 0 the trace replayed / conforms; 1 it departs (validate); 2 malformed input or
usage.";

/// Exit code for malformed input, unreadable files and usage errors.
const MALFORMED: u8 = 2;

enum Mode {
    Replay,
    Validate,
}

struct Args {
    mode: Mode,
    json: bool,
    config: Option<String>,
    trace: String,
}

fn parse_args(args: &[String]) -> Result<Args, String> {
    let mut args = args.iter();
    let mode = match args.next().map(String::as_str) {
        Some("replay") => Mode::Replay,
        Some("validate") => Mode::Validate,
        Some(other) => return Err(format!("unknown command {other:?}")),
        None => return Err("a command is needed".into()),
    };
    let mut json = false;
    let mut config = None;
    let mut trace = None;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--json" => json = true,
            "--config" => match args.next() {
                Some(file) if config.is_none() => config = Some(file.clone()),
                Some(_) => return Err("--config is given twice".into()),
                None => return Err("--config needs a file".into()),
            },
            option if option.starts_with("--") => return Err(format!("unknown option {option:?}")),
            file if trace.is_none() => trace = Some(file.to_owned()),
            extra => return Err(format!("one trace only; {extra:?} is one too many")),
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

/// Reads a configuration file, at most one line's length of the trace.
fn read_config(path: &str, limit: usize) -> Result<cooperation::Config, String> {
    let file = File::open(path).map_err(|error| format!("{path}: {error}"))?;
    let mut text = String::new();
    let cap = u64::try_from(limit).unwrap_or(u64::MAX).saturating_add(1);
    file.take(cap)
        .read_to_string(&mut text)
        .map_err(|error| format!("{path}: {error}"))?;
    if text.len() > limit {
        return Err(format!("{path}: the file is longer than {limit} bytes"));
    }
    parse_config(&text).map_err(|error| format!("{path}: {error}"))
}

fn open(path: &str) -> Result<Box<dyn BufRead>, String> {
    if path == "-" {
        return Ok(Box::new(io::stdin().lock()));
    }
    let file = File::open(path).map_err(|error| format!("{path}: {error}"))?;
    Ok(Box::new(BufReader::new(file)))
}

fn fail(path: &str, error: &TraceError) -> ExitCode {
    eprintln!("error: {path}: {error}");
    ExitCode::from(MALFORMED)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|arg| arg == "--help" || arg == "-h") {
        println!("{USAGE}");
        return ExitCode::SUCCESS;
    }
    let args = match parse_args(&args) {
        Ok(args) => args,
        Err(message) => {
            eprintln!("error: {message} (see cooperation-trace --help)");
            return ExitCode::from(MALFORMED);
        }
    };
    let limits = ReadLimits::default();
    let config = match args
        .config
        .as_deref()
        .map(|path| read_config(path, limits.max_line_bytes))
    {
        None => None,
        Some(Ok(config)) => Some(config),
        Some(Err(message)) => {
            eprintln!("error: {message}");
            return ExitCode::from(MALFORMED);
        }
    };
    let input = match open(&args.trace) {
        Ok(input) => input,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::from(MALFORMED);
        }
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
                (Err(error), _) => fail(&args.trace, &error),
                (Ok(_), Err(error)) => {
                    eprintln!("error: cannot write the output: {error}");
                    ExitCode::from(MALFORMED)
                }
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
                (Err(message), _) => {
                    eprintln!("error: {message}");
                    ExitCode::from(MALFORMED)
                }
                (Ok(()), Verdict::Conforms { .. }) => ExitCode::SUCCESS,
                (Ok(()), Verdict::Departs(_)) => ExitCode::from(1),
            }
        }
    }
}
