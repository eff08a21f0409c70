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
pub(crate) fn data_lines(text: &str) -> DataLines<'_> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    DataLines {
        inner: text_lines(text).enumerate(),
    }
}

/// The lines of `text`, ended by `\n`, `\r\n` or a lone `\r` (old Mac files: read as one
/// line of all the fields, "expected 2 to 4 header fields, found 39").
pub(crate) fn text_lines(text: &str) -> TextLines<'_> {
    TextLines {
        rest: (!text.is_empty()).then_some(text),
    }
}

/// The byte offset just after line `n` of `text` (numbered from 1, as [`text_lines`] counts
/// them, its end of line included), or the text's length.
pub(crate) fn end_of_line(text: &str, n: usize) -> usize {
    let mut lines = text_lines(text);
    for _ in 0..n {
        if lines.next().is_none() {
            break;
        }
    }
    lines
        .rest
        .map_or(text.len(), |rest| text.len() - rest.len())
}

/// The iterator of [`text_lines`].
pub(crate) struct TextLines<'t> {
    rest: Option<&'t str>,
}

impl<'t> Iterator for TextLines<'t> {
    type Item = &'t str;

    fn next(&mut self) -> Option<&'t str> {
        let text = self.rest?;
        match text.find(['\n', '\r']) {
            Some(at) => {
                let skip = if text[at..].starts_with("\r\n") { 2 } else { 1 };
                let after = &text[at + skip..];
                // (As `str::lines`: no empty line after the last end of line.)
                self.rest = (!after.is_empty()).then_some(after);
                Some(&text[..at])
            }
            None => {
                self.rest = None;
                Some(text)
            }
        }
    }
}

/// The iterator of [`data_lines`]: a named type so that readers can keep it in a struct.
pub(crate) struct DataLines<'t> {
    inner: std::iter::Enumerate<TextLines<'t>>,
}

impl<'t> Iterator for DataLines<'t> {
    type Item = (usize, Vec<&'t str>);

    fn next(&mut self) -> Option<Self::Item> {
        for (i, raw) in self.inner.by_ref() {
            let content = match raw.find('#') {
                Some(pos) => &raw[..pos],
                None => raw,
            };
            let tokens: Vec<&str> = content.split_whitespace().collect();
            if !tokens.is_empty() {
                return Some((i + 1, tokens));
            }
        }
        None
    }
}

/// Data lines read one section after another, for formats whose counts are in header lines
/// (`.poly`, `.smesh`, `.off`): running out of lines is an "unexpected end of file" error that
/// says what was expected.
pub(crate) struct LineCursor<'t> {
    lines: std::iter::Peekable<DataLines<'t>>,
    file: &'t Path,
    last_line: usize,
}

impl<'t> LineCursor<'t> {
    pub(crate) fn new(text: &'t str, file: &'t Path) -> Self {
        LineCursor {
            lines: data_lines(text).peekable(),
            file,
            last_line: last_line(text),
        }
    }

    /// The next data line; at the end of the file, an error saying `what` was expected
    /// (rendered only then: callers pass `format_args!`, which allocates nothing per line).
    pub(crate) fn next(
        &mut self,
        what: impl std::fmt::Display,
    ) -> Result<(usize, Vec<&'t str>), IoError> {
        self.lines.next().ok_or_else(|| self.eof(what))
    }

    /// The next data line, if any.
    pub(crate) fn next_opt(&mut self) -> Option<(usize, Vec<&'t str>)> {
        self.lines.next()
    }

    /// The "unexpected end of file" error, on the file's last line.
    pub(crate) fn eof(&self, what: impl std::fmt::Display) -> IoError {
        IoError::parse(
            self.file,
            self.last_line,
            format!("unexpected end of file: expected {what}"),
        )
    }

    /// The underlying iterator (for [`crate::node`]'s section parser).
    pub(crate) fn lines(&mut self) -> &mut std::iter::Peekable<DataLines<'t>> {
        &mut self.lines
    }
}

/// A whitespace-separated token scanner that keeps 1-based line numbers, for free-format files
/// (Medit `.mesh`, ASCII `.stl`) whose records need not follow line breaks. With `comments`,
/// `#` starts a comment that runs to the end of the line. It borrows the text and allocates
/// nothing, so huge files cost no more memory than their text.
pub(crate) struct Scanner<'t> {
    text: &'t str,
    pos: usize,
    line: usize,
    comments: bool,
}

impl<'t> Scanner<'t> {
    pub(crate) fn new(text: &'t str, comments: bool) -> Self {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        Scanner {
            text,
            pos: 0,
            line: 1,
            comments,
        }
    }

    /// Skips white space (and comments), leaving `pos` at the next token or the end.
    fn skip_blank(&mut self) {
        let bytes = self.text.as_bytes();
        while self.pos < bytes.len() {
            match bytes[self.pos] {
                // A line ends with `\n`, `\r\n` or a lone `\r` (as in `text_lines`).
                b'\n' => {
                    self.line += 1;
                    self.pos += 1;
                }
                b'\r' if bytes.get(self.pos + 1) != Some(&b'\n') => {
                    self.line += 1;
                    self.pos += 1;
                }
                b'#' if self.comments => {
                    while self.pos < bytes.len() && !matches!(bytes[self.pos], b'\n' | b'\r') {
                        self.pos += 1;
                    }
                }
                b if b.is_ascii_whitespace() => self.pos += 1,
                _ => break,
            }
        }
    }

    /// The next token and its line.
    pub(crate) fn next_token(&mut self) -> Option<(usize, &'t str)> {
        self.skip_blank();
        let bytes = self.text.as_bytes();
        let start = self.pos;
        while self.pos < bytes.len()
            && !bytes[self.pos].is_ascii_whitespace()
            && !(self.comments && bytes[self.pos] == b'#')
        {
            self.pos += 1;
        }
        (self.pos > start).then(|| (self.line, &self.text[start..self.pos]))
    }

    /// The rest of the current line (trimmed, comments not removed), consumed up to but not
    /// including the line break.
    pub(crate) fn rest_of_line(&mut self) -> &'t str {
        let bytes = self.text.as_bytes();
        let start = self.pos;
        while self.pos < bytes.len() && !matches!(bytes[self.pos], b'\n' | b'\r') {
            self.pos += 1;
        }
        self.text[start..self.pos].trim()
    }

    /// The line the scanner is on (of the last token read, or of the end of the file).
    pub(crate) fn line(&self) -> usize {
        self.line
    }
}

/// The number of the last line of `text` (at least 1), used for "unexpected end of file".
pub(crate) fn last_line(text: &str) -> usize {
    text_lines(text).count().max(1)
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

/// Parses a token as a non-negative count; `what` names it in messages.
pub(crate) fn parse_count(
    token: &str,
    what: &str,
    file: &Path,
    line: usize,
) -> Result<usize, IoError> {
    token.parse::<usize>().map_err(|_| {
        IoError::parse(
            file,
            line,
            format!(
                "expected a non-negative integer for the {what}, found '{}'",
                shorten(token)
            ),
        )
    })
}

/// Parses a token as an integer of type `T` (`i32` markers, `i64` indices); `what` names it.
pub(crate) fn parse_int<T: std::str::FromStr>(
    token: &str,
    what: &str,
    file: &Path,
    line: usize,
) -> Result<T, IoError> {
    token.parse::<T>().map_err(|_| {
        IoError::parse(
            file,
            line,
            format!(
                "expected an integer for the {what}, found '{}'",
                shorten(token)
            ),
        )
    })
}

/// Three coordinates `x y z` from three tokens, each finite.
pub(crate) fn parse_point3(tokens: &[&str], file: &Path, line: usize) -> Result<[f64; 3], IoError> {
    Ok([
        parse_coord(tokens[0], "x", file, line)?,
        parse_coord(tokens[1], "y", file, line)?,
        parse_coord(tokens[2], "z", file, line)?,
    ])
}

/// Turns a point number as the file writes it (`raw`, numbered from `base`) into a 0-based
/// index, or an error naming the valid range.
pub(crate) fn point_ref(
    raw: i64,
    base: i64,
    n_points: usize,
    file: &Path,
    line: usize,
) -> Result<u32, IoError> {
    let i = raw
        .checked_sub(base)
        .filter(|&i| i >= 0 && (i as u64) < n_points as u64);
    match i {
        Some(i) => Ok(i as u32),
        None if n_points == 0 => Err(IoError::parse(
            file,
            line,
            format!("point {raw} does not exist (there are no points)"),
        )),
        None => Err(IoError::parse(
            file,
            line,
            format!(
                "point {raw} does not exist (points are numbered {base} to {})",
                base + n_points as i64 - 1
            ),
        )),
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

/// Writes `x` in decimal (what `write!(w, "{x}")` writes, without the formatting machinery:
/// the mesh writers write millions of indices).
pub(crate) fn write_u64(w: &mut dyn Write, mut x: u64) -> std::io::Result<()> {
    let mut digits = [0u8; 20];
    let mut at = digits.len();
    loop {
        at -= 1;
        digits[at] = b'0' + (x % 10) as u8;
        x /= 10;
        if x == 0 {
            break;
        }
    }
    w.write_all(&digits[at..])
}

/// [`write_f64`] into a `String`, for numbers that end up inside names.
pub(crate) fn format_f64(x: f64) -> String {
    let mut v = Vec::new();
    write_f64(&mut v, x).expect("writing to a Vec cannot fail; a bug in delmesh");
    String::from_utf8(v).expect("numbers are ASCII; a bug in delmesh")
}

#[cfg(test)]
mod tests {
    use super::{end_of_line, text_lines};

    #[test]
    fn lines_end_at_any_line_break() {
        let text = "a\r\nb\rc\n\nd";
        assert_eq!(
            text_lines(text).collect::<Vec<_>>(),
            ["a", "b", "c", "", "d"]
        );
        assert_eq!(text_lines("a\n").collect::<Vec<_>>(), ["a"]);
        assert_eq!(text_lines("").count(), 0);
        assert_eq!(end_of_line(text, 1), 3);
        assert_eq!(end_of_line(text, 2), 5);
        assert_eq!(end_of_line(text, 5), text.len());
        assert_eq!(end_of_line(text, 9), text.len());
    }

    use super::*;

    fn fmt(x: f64) -> String {
        format_f64(x)
    }

    #[test]
    fn integers_are_written_as_by_format() {
        for x in [
            0,
            7,
            10,
            99,
            100,
            123_456_789,
            u64::from(u32::MAX),
            u64::MAX,
        ] {
            let mut v = Vec::new();
            write_u64(&mut v, x).unwrap();
            assert_eq!(String::from_utf8(v).unwrap(), x.to_string());
        }
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
