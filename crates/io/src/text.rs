//! Helpers shared by the line-oriented text formats (.node, .ele, .neigh, plain xyz).
//!
//! Reading: decode bytes as UTF-8 with a line-numbered error, strip `#` comments and skip blank
//! lines while keeping 1-based line numbers for messages. Writing: format `f64` so that it reads
//! back bit-exactly, which both TetGen/Triangle (`strtod`) and this crate's readers accept.

use std::io::Write;
use std::path::Path;

use crate::IoError;

/// Reads a whole file as UTF-8 text; invalid UTF-8 is a parse error naming the line.
pub(crate) fn read_text(path: &Path) -> Result<String, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let line = 1 + e.as_bytes()[..valid]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        IoError::parse(path, line, "file is not valid UTF-8 text")
    })
}

/// The lines that carry data: `(1-based line number, tokens)`, with everything from `#` on
/// removed and blank lines skipped. A leading byte-order mark is ignored.
pub(crate) fn data_lines(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> + '_ {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    text.lines().enumerate().filter_map(|(i, raw)| {
        let content = match raw.find('#') {
            Some(pos) => &raw[..pos],
            None => raw,
        };
        let tokens: Vec<&str> = content.split_whitespace().collect();
        (!tokens.is_empty()).then_some((i + 1, tokens))
    })
}

/// The number of the last line of `text` (at least 1), used for "unexpected end of file".
pub(crate) fn last_line(text: &str) -> usize {
    text.lines().count().max(1)
}

/// Parses a token as a finite `f64` coordinate; `axis` ("x", "y", "z") names it in messages.
pub(crate) fn parse_coord(
    token: &str,
    axis: &str,
    file: &Path,
    line: usize,
) -> Result<f64, IoError> {
    let value = token.parse::<f64>().map_err(|_| {
        IoError::parse(
            file,
            line,
            format!(
                "non-numeric token '{}' for the {axis} coordinate",
                shorten(token)
            ),
        )
    })?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(IoError::parse(
            file,
            line,
            format!("{axis} coordinate is not finite: '{}'", shorten(token)),
        ))
    }
}

/// Cuts very long tokens so a garbage file does not produce a megabyte-long message.
pub(crate) fn shorten(token: &str) -> String {
    const MAX: usize = 40;
    if token.chars().count() <= MAX {
        token.to_string()
    } else {
        let head: String = token.chars().take(MAX).collect();
        format!("{head}...")
    }
}

/// Writes `x` in the shortest form that parses back to the same bits.
///
/// Rust's `Display` for `f64` is shortest round-trip but never uses an exponent, so `1e-300`
/// would be written with 300 zeros; for magnitudes outside `[1e-5, 1e16)` the (equally shortest
/// round-trip) `LowerExp` form `1e-300` is used instead. `-0.0` is written as `-0`.
pub(crate) fn write_f64(w: &mut dyn Write, x: f64) -> std::io::Result<()> {
    let a = x.abs();
    if a != 0.0 && a.is_finite() && !(1e-5..1e16).contains(&a) {
        write!(w, "{x:e}")
    } else {
        write!(w, "{x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(x: f64) -> String {
        let mut v = Vec::new();
        write_f64(&mut v, x).unwrap();
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn formatting_is_short_and_exact() {
        assert_eq!(fmt(0.5), "0.5");
        assert_eq!(fmt(-0.0), "-0");
        assert_eq!(fmt(1e-300), "1e-300");
        assert_eq!(fmt(1e300), "1e300");
        assert_eq!(fmt(123456.25), "123456.25");
        assert_eq!(fmt(0.1 + 0.2), "0.30000000000000004");
        for x in [
            5e-324,
            f64::MIN_POSITIVE,
            f64::MAX,
            -f64::MAX,
            1e-5,
            1e16 - 2.0,
            1e16,
        ] {
            assert_eq!(
                fmt(x).parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{x:e}"
            );
        }
    }

    #[test]
    fn comments_and_blank_lines() {
        let lines: Vec<_> = data_lines("\u{feff}# c\n\n 1 2 # x\r\n\t\n3#4\n").collect();
        assert_eq!(lines, vec![(3, vec!["1", "2"]), (5, vec!["3"])]);
    }
}
