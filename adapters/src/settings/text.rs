//! What the text must be before YAML reads it: characters YAML allows, and keys no longer than
//! YAML lets a key on one line be. The YAML parser takes a NUL for the end of the text and
//! reads a key over 1,024 characters as a value, so each is found here and named as itself.

/// The most characters of a key written on one line (an implicit key), as YAML 1.2 allows.
pub(super) const MAX_KEY_CHARS: usize = 1024;

/// Whether YAML 1.2 allows `c` in a text (`c-printable`): tab, line breaks, and every printable
/// character (no other C0 or C1 control, no DEL, no U+FFFE or U+FFFF).
const fn printable(c: char) -> bool {
    matches!(c,
        '\t' | '\n' | '\r' | ' '..='~' | '\u{85}' | '\u{a0}'..='\u{d7ff}' | '\u{e000}'..='\u{fffd}'
        | '\u{10000}'..='\u{10ffff}')
}

/// A place in the text: line and column (in characters), both from 1.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) struct At {
    pub(super) line: usize,
    pub(super) column: usize,
}

/// Each line of the text with its number from 1; `\r\n`, `\r` and `\n` end a line, as YAML
/// counts them.
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.split('\n')
        .flat_map(|line| {
            let line = line.strip_suffix('\r').unwrap_or(line);
            line.split('\r')
        })
        .enumerate()
        .map(|(index, line)| (index + 1, line))
}

/// The first character YAML does not allow, and where it is.
pub(super) fn unprintable(text: &str) -> Option<(At, char)> {
    lines(text).find_map(|(line, content)| {
        content
            .chars()
            .enumerate()
            .find(|&(_, c)| !printable(c))
            .map(|(index, c)| {
                let column = index + 1;
                (At { line, column }, c)
            })
    })
}

/// The first key on a line of its own longer than [`MAX_KEY_CHARS`], where it starts, and its
/// length in characters. A key is what stands before the line's first `: ` (or its final
/// `:`), after the indentation; a quoted key ends at its closing quote. Comment lines and list
/// items hold no key.
pub(super) fn long_key(text: &str) -> Option<(At, usize)> {
    lines(text).find_map(|(line, content)| {
        let indent = content.len() - content.trim_start_matches([' ', '\t']).len();
        let rest = content.get(indent..)?;
        // A comment, or a list item (no settings key is in a list).
        if rest.starts_with('#') || rest.starts_with("- ") {
            return None;
        }
        let len = key_chars(rest)?;
        (len > MAX_KEY_CHARS).then_some((
            At {
                line,
                column: indent + 1,
            },
            len,
        ))
    })
}

/// The characters of the key at the start of `rest`, if the line holds one.
fn key_chars(rest: &str) -> Option<usize> {
    let end = match rest.chars().next()? {
        quote @ ('"' | '\'') => {
            let close = rest.get(1..)?.find(quote)? + 1;
            let after = rest.get(close + 1..)?;
            after.starts_with(':').then_some(close + 1)?
        }
        _ => match rest.find(": ") {
            Some(at) => at,
            None => rest.strip_suffix(':').map(str::len)?,
        },
    };
    rest.get(..end).map(|key| key.chars().count())
}
