//! Reading a trace line by line within fixed bounds.

use std::io::{BufRead, ErrorKind as IoErrorKind};

use crate::{ErrorKind, TraceError, JSON_SPACE};

/// The bounds on what a trace reader accepts. Memory for reading is one line's buffer, at most
/// `max_line_bytes`, reused for every line.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct ReadLimits {
    /// The longest line accepted, in bytes, without its line ending. Default 1 MiB.
    pub max_line_bytes: usize,
    /// The most lines accepted, blank and comment lines included. Default 10 000 000.
    pub max_lines: usize,
}

impl Default for ReadLimits {
    fn default() -> Self {
        Self {
            max_line_bytes: 1 << 20,
            max_lines: 10_000_000,
        }
    }
}

/// The record lines of a trace: every line but blank ones and `#` comments, with its number.
#[derive(Debug)]
pub struct Lines<R> {
    input: R,
    limits: ReadLimits,
    /// The current line, reused for every line.
    text: String,
    line: usize,
}

impl<R: BufRead> Lines<R> {
    /// A reader of `input` within `limits`.
    pub const fn new(input: R, limits: ReadLimits) -> Self {
        Self {
            input,
            limits,
            text: String::new(),
            line: 0,
        }
    }

    /// The number of the last line read (0 before the first).
    #[must_use]
    pub const fn line(&self) -> usize {
        self.line
    }

    /// The next record line, trimmed, and its number, or `None` at the end of the trace.
    ///
    /// # Errors
    /// A line too long, one line too many, a line that is not UTF-8, or a read error.
    pub fn next_line(&mut self) -> Result<Option<(usize, &str)>, TraceError> {
        let Some((start, end)) = self.next_record()? else {
            return Ok(None);
        };
        Ok(Some((
            self.line,
            self.text.get(start..end).unwrap_or_default(),
        )))
    }

    /// Reads lines up to the next record line; its trimmed range in `self.text`.
    fn next_record(&mut self) -> Result<Option<(usize, usize)>, TraceError> {
        loop {
            let line = self.line.saturating_add(1);
            let mut bytes = std::mem::take(&mut self.text).into_bytes();
            bytes.clear();
            if !self.read_line(line, &mut bytes)? {
                return Ok(None);
            }
            self.line = line;
            if line > self.limits.max_lines {
                return Err(TraceError::at(
                    line,
                    ErrorKind::TooManyLines {
                        limit: self.limits.max_lines,
                    },
                ));
            }
            self.text = String::from_utf8(bytes).map_err(|error| {
                let offset = error.utf8_error().valid_up_to();
                TraceError::at(line, ErrorKind::NotUtf8 { offset })
            })?;
            let mut text = self.text.as_str();
            if line == 1 {
                text = text.strip_prefix('\u{feff}').unwrap_or(text);
            }
            // Blank is JSON's white space only: other white space is neither blank nor JSON.
            let trimmed = text.trim_matches(JSON_SPACE);
            if !trimmed.is_empty() && !trimmed.starts_with('#') {
                let start = self.text.len() - text.trim_start_matches(JSON_SPACE).len();
                return Ok(Some((start, start + trimmed.len())));
            }
        }
    }

    /// Reads one line into `bytes`, without its `\n`. `false` at the end of the input.
    ///
    /// The limit is on the line without its ending, `\n` or `\r\n`: one byte more is read
    /// in case it is the `\r` of a `\r\n`, and refused if it is not.
    fn read_line(&mut self, line: usize, bytes: &mut Vec<u8>) -> Result<bool, TraceError> {
        let limit = self.limits.max_line_bytes;
        let too_long = || TraceError::at(line, ErrorKind::LineTooLong { limit });
        let mut read_any = false;
        loop {
            let available = match self.input.fill_buf() {
                Ok(available) => available,
                Err(error) if error.kind() == IoErrorKind::Interrupted => continue,
                Err(error) => {
                    return Err(TraceError::at(
                        line,
                        ErrorKind::Read {
                            message: error.to_string(),
                        },
                    ))
                }
            };
            if available.is_empty() {
                // The end of the input: a final `\r` is no line ending, and counts.
                if bytes.len() > limit {
                    return Err(too_long());
                }
                return Ok(read_any);
            }
            read_any = true;
            let newline = available.iter().position(|&byte| byte == b'\n');
            let content = newline.unwrap_or(available.len());
            if bytes.len().saturating_add(content) > limit.saturating_add(1) {
                return Err(too_long());
            }
            bytes.extend_from_slice(available.get(..content).unwrap_or_default());
            let used = newline.map_or(content, |at| at + 1);
            self.input.consume(used);
            if newline.is_some() {
                if bytes.len() > limit && bytes.last() != Some(&b'\r') {
                    return Err(too_long());
                }
                return Ok(true);
            }
        }
    }
}
