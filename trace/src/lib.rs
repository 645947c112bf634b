//! Replay and validation of cooperation traces.
//!
//! A trace is JSON lines: an optional first line with the configuration, then timestamped
//! records, each an input to the core (`{"at_ms": 1200, "input": {...}}`) or, for validation,
//! the statuses the real system reported (`{"at_ms": 1300, "observed": [...]}`). The format is
//! documented in `docs/trace-format.md`.
//!
//! [`replay`] applies every input with `State::apply` (an increase of `at_ms` becomes an
//! `Input::Tick` before the record) and prints, after each step, the rule that fired or
//! rejected, then every live scene's status and merged decision. [`validate`] compares each
//! observation with the statuses the core gives and reports the first departure, with the rule
//! of the step that last touched the departing scene.
//!
//! Everything works on any input without panicking: every malformed line is a typed
//! [`TraceError`] naming its line and field, lines are bounded by [`ReadLimits`], and memory
//! by the configuration's limits (at most [`MAX_LIMITS`]). No rule of the core is
//! re-implemented here: every decision is the core's.

#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

mod error;
mod json;
mod read;
mod record;
mod render;
mod replay;
mod strict;
mod validate;
mod version;

use std::io::{BufRead, Write};

pub use error::{ErrorKind, TraceError};
pub use read::{Lines, ReadLimits};
pub use record::{
    parse_config, parse_record, parse_record_of, parse_status, Event, Observation, Record,
    MAX_LIMITS,
};
pub use render::{scenes_table, step_json, step_text, verdict_json, verdict_text, Printer};
pub use replay::{Cause, Replayer, Sink, Step};
pub use validate::{compare, Departure, Difference, Field, Validator, Verdict};
pub use version::Version;

/// The white space JSON allows between tokens, and the only white space a blank line may
/// hold: space, tab, carriage return, line feed.
pub(crate) const JSON_SPACE: &[char] = &[' ', '\t', '\r', '\n'];

/// How to read a trace.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The bounds on lines.
    pub limits: ReadLimits,
    /// The configuration, when it comes from outside the trace (a `--config` or `--settings`
    /// file); then the trace must not have a `config` line.
    pub config: Option<cooperation::Config>,
}

/// What a finished replay went through.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Summary {
    /// Steps applied.
    pub steps: u64,
    /// Observations read.
    pub observations: u64,
    /// Lines read.
    pub lines: usize,
}

/// Reads `input` record by record, feeding each to a [`Replayer`] that reports to `sink`,
/// until the end or until the sink stops it.
///
/// # Errors
/// The first malformed line, or the sink's error.
pub fn run<R: BufRead>(
    input: R,
    options: &Options,
    sink: &mut dyn Sink,
) -> Result<(Replayer, Summary), TraceError> {
    let mut lines = Lines::new(input, options.limits);
    let mut replayer = Replayer::new(options.config.clone())?;
    // Version 1 until a first record says otherwise.
    let (mut version, mut first) = (Version::V1, true);
    while let Some((line, text)) = lines.next_line()? {
        let record = parse_record_of(version, line, text)?;
        if let Record::Version(given) = record {
            if !first {
                return Err(TraceError::at(line, ErrorKind::MisplacedVersion));
            }
            (version, first) = (given, false);
            continue;
        }
        first = false;
        if replayer.feed(line, record, sink)?.is_break() {
            break;
        }
    }
    let summary = Summary {
        steps: replayer.steps(),
        observations: replayer.observations(),
        lines: lines.line(),
    };
    Ok((replayer, summary))
}

/// Replays `input`, writing every step to `out` as a table, or as one JSON object per line
/// with `json`.
///
/// # Errors
/// The first malformed line, or a write error. The steps before it were written.
pub fn replay<R: BufRead, W: Write>(
    input: R,
    out: W,
    options: &Options,
    json: bool,
) -> Result<Summary, TraceError> {
    let mut printer = Printer::new(out, json);
    let (_, summary) = run(input, options, &mut printer)?;
    Ok(summary)
}

/// Validates `input`: replays it and compares every observation with the spec, stopping at
/// the first that departs.
///
/// # Errors
/// The first malformed line before the first departure.
pub fn validate<R: BufRead>(input: R, options: &Options) -> Result<Verdict, TraceError> {
    let mut validator = Validator::default();
    let (_, summary) = run(input, options, &mut validator)?;
    Ok(match validator.departure {
        Some(departure) => Verdict::Departs(departure),
        None => Verdict::Conforms {
            steps: summary.steps,
            observations: summary.observations,
        },
    })
}
