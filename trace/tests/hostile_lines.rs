//! Hostile lines and failing I/O: lines at and over the length limit, line endings, bytes
//! that are not UTF-8, white space that JSON does not know, byte-order marks, the limits of
//! the configuration, and readers and writers that fail.

use std::io::{self, BufReader, Read};

use cooperation_trace::*;

const CONFIG: &str = r#"{"config": {"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}}"#;

fn replay_text(text: &str) -> Result<Summary, TraceError> {
    replay(text.as_bytes(), io::sink(), &Options::default(), false)
}

fn replay_with(text: &[u8], limits: ReadLimits) -> Result<Summary, TraceError> {
    replay(
        text,
        io::sink(),
        &Options {
            limits,
            config: None,
        },
        false,
    )
}

fn limits(max_line_bytes: usize) -> ReadLimits {
    ReadLimits {
        max_line_bytes,
        max_lines: 1_000,
    }
}

/// The records of `text` as `Lines` gives them, read through a buffer of `capacity` bytes.
fn records(text: &[u8], limit: usize, capacity: usize) -> Result<Vec<(usize, String)>, TraceError> {
    let mut lines = Lines::new(BufReader::with_capacity(capacity, text), limits(limit));
    let mut found = Vec::new();
    while let Some((line, text)) = lines.next_line()? {
        found.push((line, text.to_owned()));
    }
    Ok(found)
}

#[test]
fn the_line_limit_excludes_the_line_ending() {
    let limit = CONFIG.len();
    // Every split of the line across reads, the `\r` and `\n` in different reads included.
    for capacity in [1, 2, 3, 7, limit - 1, limit, limit + 1, limit + 2, 4096] {
        for ending in ["\n", "\r\n"] {
            let text = format!("{CONFIG}{ending}{{\"at_ms\": 1}}{ending}");
            let found = records(text.as_bytes(), limit, capacity).expect(ending);
            assert_eq!(found.first().map(|(_, t)| t.as_str()), Some(CONFIG));
            assert_eq!(found.len(), 2);
            // One byte more is too long, whatever the ending.
            let text = format!("{CONFIG} {ending}");
            let error = records(text.as_bytes(), limit, capacity).unwrap_err();
            assert_eq!(
                (error.line, error.kind),
                (Some(1), ErrorKind::LineTooLong { limit }),
                "{capacity} {ending:?}"
            );
        }
        // At the end of the input, without a line ending.
        assert!(records(CONFIG.as_bytes(), limit, capacity).is_ok());
        // A `\r` not followed by `\n` is not a line ending: it counts.
        let text = format!("{CONFIG}\r");
        let error = records(text.as_bytes(), limit, capacity).unwrap_err();
        assert_eq!(error.kind, ErrorKind::LineTooLong { limit });
        let text = format!("{CONFIG}\r \n");
        let error = records(text.as_bytes(), limit, capacity).unwrap_err();
        assert_eq!(error.kind, ErrorKind::LineTooLong { limit });
    }
    // The default limit, 1 MiB, with CRLF endings.
    let padded = format!("{{\"at_ms\": 1{}}}", " ".repeat((1 << 20) - 12));
    assert_eq!(padded.len(), 1 << 20);
    let text = format!("{CONFIG}\r\n{padded}\r\n");
    assert!(replay_with(text.as_bytes(), ReadLimits::default()).is_ok());
    let text = format!("{CONFIG}\r\n {padded}\r\n");
    let error = replay_with(text.as_bytes(), ReadLimits::default()).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (Some(2), ErrorKind::LineTooLong { limit: 1 << 20 })
    );
}

#[test]
fn bytes_that_are_not_utf8_are_located() {
    for (text, line, offset) in [
        (&b"\xff\n"[..], 1, 0),
        (b"{}\n{\"at_ms\": \"\xc3\x28\"}\n", 2, 11),
        // A truncated sequence at the end of the line.
        (b"# ok\n\n{\"at_ms\": 1} \xe2\x82\n", 3, 13),
        // A UTF-16 byte-order mark.
        (b"\xff\xfe{\x00}\x00\n", 1, 0),
        // The UTF-8 byte-order mark is counted.
        (b"\xef\xbb\xbf{\"a\": \"\xed\xa0\x80\"}\n", 1, 10),
    ] {
        let error = records(text, 1 << 20, 4096).unwrap_err();
        assert_eq!(
            (error.line, error.kind.clone()),
            (Some(line), ErrorKind::NotUtf8 { offset }),
            "{text:?}"
        );
        let shown = error.to_string();
        assert!(
            shown.contains(&format!("byte {offset} ")) && shown.contains("not UTF-8"),
            "{shown}"
        );
    }
}

#[test]
fn blank_means_json_white_space() {
    // Spaces, tabs and carriage returns only: a line of them is blank.
    let found = records(b" \t \r\n\t\n{\"at_ms\": 1}\t \r\n", 1 << 20, 4096).unwrap();
    assert_eq!(found, [(3, "{\"at_ms\": 1}".to_owned())]);
    // Other white space is not JSON's: the line is not a record, nor blank.
    for space in [
        "\u{a0}", "\u{2028}", "\u{3000}", "\u{85}", "\x0b", "\x0c", "\u{feff}",
    ] {
        for line in [
            space.to_owned(),
            format!("{space}{{\"at_ms\": 1}}"),
            format!("{{\"at_ms\": 1}}{space}"),
        ] {
            let text = format!("{CONFIG}\n{line}\n");
            let error = replay_with(text.as_bytes(), ReadLimits::default()).unwrap_err();
            assert_eq!(error.line, Some(2), "{line:?}: {error}");
        }
    }
    // A comment after white space, and white space before the first line's mark.
    let found = records(b"\xef\xbb\xbf \t# note\n\t# note\n", 1 << 20, 4096).unwrap();
    assert!(found.is_empty());
    // Only the first line may start with the byte-order mark, and only once.
    for text in [
        format!("{CONFIG}\n\u{feff}{{\"at_ms\": 1}}\n"),
        format!("\u{feff}\u{feff}{CONFIG}\n"),
    ] {
        let error = replay_with(text.as_bytes(), ReadLimits::default()).unwrap_err();
        assert_eq!(error.kind, ErrorKind::NotAnObject, "{text:?}");
    }
}

#[test]
fn a_configuration_file_reads_like_a_config_line() {
    let body = r#"{"policies": [{"module": {"behavior": "lane-change", "sequence": ""}, "policy": "optional"}]}"#;
    let plain = parse_config(body).unwrap();
    for text in [
        format!("\u{feff}{body}"),
        format!("{body}\r\n"),
        format!("\r\n\t{body}\n\n"),
    ] {
        assert_eq!(parse_config(&text).as_ref(), Ok(&plain), "{text:?}");
    }
    for text in ["", "   ", "[]", "null", "\u{a0}{}", "{} {}"] {
        assert!(parse_config(text).is_err(), "{text:?}");
    }
}

#[test]
fn limits_above_the_ceiling_are_refused_and_the_ceiling_is_accepted() {
    let config = |limits: &str| {
        format!("{{\"config\": {{\"policies\": [], \"limits\": {limits}}}}}\n{{\"at_ms\": 0}}\n")
    };
    for (field, max) in [
        ("max_scenes", MAX_LIMITS.max_scenes),
        ("retired_capacity", MAX_LIMITS.retired_capacity),
        ("max_batch", MAX_LIMITS.max_batch),
    ] {
        let at_max = config(&format!("{{\"{field}\": {max}}}"));
        assert!(replay_with(at_max.as_bytes(), ReadLimits::default()).is_ok());
        let over = config(&format!("{{\"{field}\": {}}}", max + 1));
        let error = replay_with(over.as_bytes(), ReadLimits::default()).unwrap_err();
        assert!(
            matches!(error.kind, ErrorKind::LimitTooLarge { field: f, .. } if f == field),
            "{error}"
        );
        // A number beyond any integer is a JSON error at the field.
        let huge = config(&format!("{{\"{field}\": 1{}}}", "0".repeat(400)));
        let error = replay_with(huge.as_bytes(), ReadLimits::default()).unwrap_err();
        match error.kind {
            ErrorKind::Json { field: path, .. } => {
                assert_eq!(path, format!("config.limits.{field}"))
            }
            other => panic!("{other:?}"),
        }
    }
    // `ttl_ms` takes any u64; a zero limit of the others is the core's to refuse.
    for ttl in [0, u64::MAX] {
        let any = config(&format!("{{\"ttl_ms\": {ttl}}}"));
        assert!(replay_with(any.as_bytes(), ReadLimits::default()).is_ok());
    }
    let zero = config("{\"max_scenes\": 0}");
    let error = replay_with(zero.as_bytes(), ReadLimits::default()).unwrap_err();
    assert!(matches!(error.kind, ErrorKind::InvalidConfig(_)), "{error}");
}

#[test]
fn lines_are_bounded() {
    // A line one byte over the limit, and an endless one: refused without reading further.
    let limits = ReadLimits {
        max_line_bytes: 64,
        max_lines: 1_000,
    };
    let options = Options {
        limits,
        config: None,
    };
    // The second line is exactly one byte longer than the first, which is at the limit.
    let over = format!(
        "{CONFIG}\n{{\"at_ms\": 1{}}}\n",
        " ".repeat(CONFIG.len() - "{\"at_ms\": 1}".len() + 1)
    );
    assert!(replay_text(&over).is_ok());
    let config_limits = ReadLimits {
        max_line_bytes: CONFIG.len(),
        ..limits
    };
    let error = replay(
        over.as_bytes(),
        io::sink(),
        &Options {
            limits: config_limits,
            config: None,
        },
        false,
    )
    .unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (
            Some(2),
            ErrorKind::LineTooLong {
                limit: CONFIG.len()
            }
        )
    );
    let endless = io::repeat(b'x');
    let error = replay(BufReader::new(endless), io::sink(), &options, false).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (Some(1), ErrorKind::LineTooLong { limit: 64 })
    );
    // A giant line at the default limit (1 MiB), after a valid start.
    let giant = format!(
        "{CONFIG}\n{{\"at_ms\": 0}}\n{{\"observed\": [{}]}}\n",
        "0,".repeat(600_000)
    );
    let error = replay_text(&giant).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (Some(3), ErrorKind::LineTooLong { limit: 1 << 20 })
    );
    // Endless blank lines: refused at the default line limit.
    let error = replay(
        BufReader::new(io::repeat(b'\n')),
        io::sink(),
        &Options::default(),
        false,
    )
    .unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (
            Some(10_000_001),
            ErrorKind::TooManyLines { limit: 10_000_000 }
        )
    );
}

#[test]
fn lines_accept_crlf_bom_comments_and_a_missing_final_newline() {
    let text = format!(
        "\u{feff}# a comment\r\n\r\n   \n{CONFIG}\r\n  # indented comment\n{{\"at_ms\": 5}}"
    );
    let mut lines = Lines::new(text.as_bytes(), ReadLimits::default());
    assert_eq!(lines.next_line().unwrap(), Some((4, CONFIG)));
    assert_eq!(lines.next_line().unwrap(), Some((6, "{\"at_ms\": 5}")));
    assert_eq!(lines.next_line().unwrap(), None);
    assert_eq!(lines.line(), 6);
    let mut lines = Lines::new(&b"{}\n\xff\n"[..], ReadLimits::default());
    assert!(lines.next_line().unwrap().is_some());
    let error = lines.next_line().unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (Some(2), ErrorKind::NotUtf8 { offset: 0 })
    );
}

/// A reader that fails after its text.
struct Failing<'a>(&'a [u8]);

impl Read for Failing<'_> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if self.0.is_empty() {
            return Err(io::Error::other("disk on fire"));
        }
        let n = self.0.read(buf)?;
        Ok(n)
    }
}

#[test]
fn read_errors_name_the_line() {
    let text = format!("{CONFIG}\n{{\"at_ms\"");
    let error = replay(
        BufReader::new(Failing(text.as_bytes())),
        io::sink(),
        &Options::default(),
        false,
    )
    .unwrap_err();
    assert_eq!(error.line, Some(2));
    assert_eq!(
        error.kind,
        ErrorKind::Read {
            message: "disk on fire".into()
        }
    );
}

/// A sink whose output fails: the replay stops with a write error.
#[test]
fn write_errors_stop_the_replay() {
    struct Full;
    impl io::Write for Full {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::other("disk full"))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }
    // A step, whose report is written: an owner removing a scene it never registered.
    let removal = r#"{"input": {"Remove": {"id": "00000000-0000-0000-0000-000000000001", "module": {"behavior": "lane-change", "sequence": ""}}}}"#;
    let text = format!("{CONFIG}\n{removal}\n");
    let error = replay(text.as_bytes(), Full, &Options::default(), true).unwrap_err();
    assert_eq!(
        (error.line, error.kind),
        (
            None,
            ErrorKind::Write {
                message: "disk full".into()
            }
        )
    );
}
