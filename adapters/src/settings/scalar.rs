//! What a scalar is, as YAML 1.2's core schema (and so ROS 2) reads it, and whole numbers.

use saphyr_parser::ScalarStyle;

use super::Found;

/// The type of a scalar: a quoted or block scalar is a string; a plain one is typed by its
/// text, as the core schema says.
pub(super) fn kind(text: &str, style: ScalarStyle) -> Found {
    if style != ScalarStyle::Plain {
        return Found::String;
    }
    match text {
        "" | "~" | "null" | "Null" | "NULL" => Found::Null,
        "true" | "True" | "TRUE" | "false" | "False" | "FALSE" => Found::Bool,
        _ if is_integer(text) => Found::Integer,
        _ if is_float(text) => Found::Float,
        _ => Found::String,
    }
}

/// `[-+]?[0-9]+`, `0o[0-7]+` or `0x[0-9a-fA-F]+`.
fn is_integer(text: &str) -> bool {
    if let Some(octal) = text.strip_prefix("0o") {
        return all_digits(octal, 8);
    }
    if let Some(hex) = text.strip_prefix("0x") {
        return all_digits(hex, 16);
    }
    all_digits(unsigned(text), 10)
}

/// `[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?`, `[-+]?\.(inf|Inf|INF)` or
/// `\.(nan|NaN|NAN)`.
fn is_float(text: &str) -> bool {
    if matches!(text, ".nan" | ".NaN" | ".NAN") {
        return true;
    }
    let text = unsigned(text);
    if matches!(text, ".inf" | ".Inf" | ".INF") {
        return true;
    }
    let (mantissa, exponent) = match text.find(['e', 'E']) {
        Some(at) => (text.get(..at), text.get(at + 1..)),
        None => (Some(text), None),
    };
    let Some(mantissa) = mantissa else {
        return false;
    };
    let mantissa_ok = match mantissa.split_once('.') {
        Some((whole, fraction)) => {
            (whole.is_empty() && !fraction.is_empty() && all_digits(fraction, 10))
                || (all_digits(whole, 10) && (fraction.is_empty() || all_digits(fraction, 10)))
        }
        None => all_digits(mantissa, 10),
    };
    let exponent_ok = exponent.map_or(true, |exponent| all_digits(unsigned(exponent), 10));
    mantissa_ok && exponent_ok
}

/// The text without one leading sign.
fn unsigned(text: &str) -> &str {
    text.strip_prefix(['-', '+']).unwrap_or(text)
}

/// Whether `text` is one or more digits of `radix`.
fn all_digits(text: &str, radix: u32) -> bool {
    !text.is_empty() && text.chars().all(|c| c.is_digit(radix))
}

/// The value of a scalar that [`kind`] reads as [`Found::Integer`], if it is from 0 to
/// `u64::MAX`.
pub(super) fn unsigned_integer(text: &str) -> Option<u64> {
    if let Some(octal) = text.strip_prefix("0o") {
        return u64::from_str_radix(octal, 8).ok();
    }
    if let Some(hex) = text.strip_prefix("0x") {
        return u64::from_str_radix(hex, 16).ok();
    }
    match text.strip_prefix('-') {
        // Minus zero is zero; anything else below zero is out of range.
        Some(digits) => digits.chars().all(|c| c == '0').then_some(0),
        None => unsigned(text).parse().ok(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_scalars_are_typed_by_the_core_schema() {
        for (text, found) in [
            ("", Found::Null),
            ("~", Found::Null),
            ("NULL", Found::Null),
            ("True", Found::Bool),
            ("false", Found::Bool),
            ("10000", Found::Integer),
            ("-3", Found::Integer),
            ("+3", Found::Integer),
            ("0x1F", Found::Integer),
            ("0o17", Found::Integer),
            ("1.5", Found::Float),
            ("1.", Found::Float),
            (".5", Found::Float),
            ("1e4", Found::Float),
            ("-1.5E-3", Found::Float),
            ("-.inf", Found::Float),
            (".NaN", Found::Float),
            ("optional", Found::String),
            ("10_000", Found::String),
            ("0x", Found::String),
            ("0o8", Found::String),
            ("1e", Found::String),
            (".", Found::String),
            ("e4", Found::String),
            ("yes", Found::String),
        ] {
            assert_eq!(kind(text, ScalarStyle::Plain), found, "{text:?}");
        }
        for style in [
            ScalarStyle::SingleQuoted,
            ScalarStyle::DoubleQuoted,
            ScalarStyle::Literal,
            ScalarStyle::Folded,
        ] {
            assert_eq!(kind("10000", style), Found::String);
            assert_eq!(kind("~", style), Found::String);
        }
    }

    #[test]
    fn whole_numbers_in_every_form() {
        for (text, value) in [
            ("0", Some(0)),
            ("-0", Some(0)),
            ("+7", Some(7)),
            ("007", Some(7)),
            ("0x10", Some(16)),
            ("0o10", Some(8)),
            ("18446744073709551615", Some(u64::MAX)),
            ("18446744073709551616", None),
            ("0x10000000000000000", None),
            ("-1", None),
        ] {
            assert_eq!(unsigned_integer(text), value, "{text:?}");
        }
    }
}
