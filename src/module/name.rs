//! User-extension names: behaviours and sequences beyond the AD API's built-in ones.
//!
//! The AD API's factor messages say any name is available for user extensions. A name is kept
//! inline, in a fixed-size array, so that a [`Module`](super::Module) stays `Copy` and a state
//! holding one needs no allocation.

use core::fmt;

/// The bytes in one word of a name: a third of [`Extension::MAX_LEN`].
const WORD: usize = 8;

/// The name of a user-extension behaviour or sequence.
///
/// A valid name is 1 to [`Extension::MAX_LEN`] bytes of ASCII lower-case letters, digits and
/// `-`, starts with a letter, and is not a built-in name of its kind (parsing a built-in name
/// gives the built-in value, so every string names one value). Upper case, `_`, `/`, `.` and
/// white space are refused: the built-in names are all lower-case words joined by `-`, and `/`
/// separates a behaviour from its sequence in [`Module`](super::Module)'s display.
///
/// An `Extension` is made only by parsing ([`Behavior::named`](super::Behavior::named),
/// [`Sequence::named`](super::Sequence::named) or `str::parse`), so one always holds a valid
/// name.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Extension {
    /// The name's bytes, then zeros, in three words. Zero is not a name byte, so the order of
    /// the arrays is the order of the names.
    words: [[u8; WORD]; 3],
}

impl Extension {
    /// The longest name, in bytes. With it, a [`Module`](super::Module) is 50 bytes, and a
    /// rejection that names two modules stays small enough to return by value.
    pub const MAX_LEN: usize = 24;

    /// The name, if `text` is a valid one (built-in names are checked by the caller).
    pub(super) const fn new(text: &str) -> Result<Self, NameProblem> {
        let given = text.as_bytes();
        if given.is_empty() {
            return Err(NameProblem::Empty);
        }
        if given.len() > Self::MAX_LEN {
            return Err(NameProblem::TooLong { len: given.len() });
        }
        // Every byte of the name, then zeros, shifted into three big-endian words.
        let mut words = [0_u64; 3];
        let (mut rest, mut at) = (given, 0);
        while at < Self::MAX_LEN {
            let byte = match rest {
                [byte, tail @ ..] => {
                    rest = tail;
                    *byte
                }
                [] => 0,
            };
            let allowed = match byte {
                b'a'..=b'z' => true,
                b'0'..=b'9' | b'-' => at > 0,
                0 => at >= given.len(),
                _ => false,
            };
            if !allowed {
                return Err(NameProblem::Character { at });
            }
            let [first, second, third] = words;
            words = match at / WORD {
                0 => [first << 8 | byte as u64, second, third],
                1 => [first, second << 8 | byte as u64, third],
                _ => [first, second, third << 8 | byte as u64],
            };
            at += 1;
        }
        let [first, second, third] = words;
        Ok(Self {
            words: [
                first.to_be_bytes(),
                second.to_be_bytes(),
                third.to_be_bytes(),
            ],
        })
    }

    /// The name.
    #[must_use]
    pub fn as_str(&self) -> &str {
        // Only ASCII is ever stored.
        core::str::from_utf8(self.as_bytes()).unwrap_or_default()
    }

    /// The name's bytes: what module order compares, without checking them again as text.
    pub(crate) fn as_bytes(&self) -> &[u8] {
        let bytes = self.words.as_flattened();
        let len = bytes
            .iter()
            .position(|&byte| byte == 0)
            .unwrap_or(Self::MAX_LEN);
        bytes.get(..len).unwrap_or_default()
    }
}

impl core::hash::Hash for Extension {
    /// The three words, each as one integer. (A derived hash feeds the hasher each word's
    /// length and bytes apart: eight calls where three do.)
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        for word in self.words {
            state.write_u64(u64::from_ne_bytes(word));
        }
    }
}

impl fmt::Debug for Extension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Extension({:?})", self.as_str())
    }
}

impl fmt::Display for Extension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Why a string is not a behaviour or sequence name.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum NameProblem {
    /// The empty string. (The AD API's `UNKNOWN` behaviour is `""`; the empty sequence is
    /// [`Sequence::Empty`](super::Sequence::Empty), and parses.)
    Empty,
    /// Longer than [`Extension::MAX_LEN`] bytes.
    TooLong {
        /// Its length in bytes.
        len: usize,
    },
    /// The byte at this offset is not allowed there: not a lower-case ASCII letter, digit or
    /// `-`, or, first, not a letter.
    Character {
        /// The byte offset, from 0.
        at: usize,
    },
}

impl fmt::Display for NameProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::Empty => f.write_str("it is empty"),
            Self::TooLong { len } => write!(f, "it has {len} bytes, over {}", Extension::MAX_LEN),
            Self::Character { at: 0 } => {
                f.write_str("it does not start with a lower-case ASCII letter")
            }
            Self::Character { at } => write!(
                f,
                "byte {at} is not a lower-case ASCII letter, digit or '-'"
            ),
        }
    }
}

/// Whether two strings are equal, in a `const fn`.
pub(super) const fn same(a: &str, b: &str) -> bool {
    let (mut a, mut b) = (a.as_bytes(), b.as_bytes());
    loop {
        match (a, b) {
            ([], []) => return true,
            ([x, a_tail @ ..], [y, b_tail @ ..]) if *x == *y => {
                a = a_tail;
                b = b_tail;
            }
            _ => return false,
        }
    }
}
