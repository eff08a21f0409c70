//! A minimal JSON reader for delmesh's `--report` files.
//!
//! xtask keeps its dependencies to `anyhow` (plus `robust` for exact orientation), so
//! instead of serde this is a small recursive-descent parser of RFC 8259 JSON into a
//! [`Json`] tree, with path lookups (`get(&["recovery", "edge_points"])`). It reads
//! what delmesh writes (objects, arrays, numbers, strings, `null`) and rejects
//! anything malformed with the byte offset, which is all a report reader needs.

use anyhow::{bail, Context, Result};

/// A parsed JSON value. Object members keep their file order.
#[derive(Debug, Clone, PartialEq)]
pub enum Json {
    Null,
    Bool(bool),
    Number(f64),
    Str(String),
    Array(Vec<Json>),
    Object(Vec<(String, Json)>),
}

impl Json {
    /// Parses a whole document (trailing whitespace allowed, nothing else).
    pub fn parse(text: &str) -> Result<Json> {
        let mut p = Parser {
            s: text.as_bytes(),
            i: 0,
        };
        let v = p.value(0)?;
        p.ws();
        if p.i != p.s.len() {
            bail!("JSON: unexpected `{}` at byte {}", p.s[p.i] as char, p.i);
        }
        Ok(v)
    }

    /// The member `key` of an object.
    pub fn member(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Object(m) => m.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// Follows object members along `path`.
    pub fn get(&self, path: &[&str]) -> Option<&Json> {
        path.iter().try_fold(self, |v, k| v.member(k))
    }

    /// The number at `path`, as an error naming the path when it is missing.
    pub fn number(&self, path: &[&str]) -> Result<f64> {
        match self.get(path) {
            Some(Json::Number(x)) => Ok(*x),
            Some(other) => bail!("JSON: `{}` is not a number: {other:?}", path.join(".")),
            None => bail!("JSON: no `{}`", path.join(".")),
        }
    }

    /// A non-negative integer at `path`.
    pub fn count(&self, path: &[&str]) -> Result<u64> {
        let x = self.number(path)?;
        if x < 0.0 || x.fract() != 0.0 || x > 2f64.powi(53) {
            bail!("JSON: `{}` = {x} is not a count", path.join("."));
        }
        Ok(x as u64)
    }
}

/// Nesting limit: a report is a few levels deep; this stops a runaway recursion.
const MAX_DEPTH: usize = 64;

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\t' | b'\n' | b'\r') {
            self.i += 1;
        }
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn expect(&mut self, b: u8) -> Result<()> {
        self.ws();
        if self.peek() != Some(b) {
            bail!("JSON: expected `{}` at byte {}", b as char, self.i);
        }
        self.i += 1;
        Ok(())
    }

    fn literal(&mut self, word: &str, v: Json) -> Result<Json> {
        if self.s[self.i..].starts_with(word.as_bytes()) {
            self.i += word.len();
            Ok(v)
        } else {
            bail!("JSON: bad literal at byte {}", self.i)
        }
    }

    fn value(&mut self, depth: usize) -> Result<Json> {
        if depth > MAX_DEPTH {
            bail!("JSON: nested deeper than {MAX_DEPTH} levels");
        }
        self.ws();
        match self.peek() {
            Some(b'{') => {
                self.i += 1;
                let mut members = Vec::new();
                self.ws();
                if self.peek() == Some(b'}') {
                    self.i += 1;
                    return Ok(Json::Object(members));
                }
                loop {
                    self.ws();
                    let key = self.string()?;
                    self.expect(b':')?;
                    members.push((key, self.value(depth + 1)?));
                    self.ws();
                    match self.peek() {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Ok(Json::Object(members));
                        }
                        _ => bail!("JSON: expected `,` or `}}` at byte {}", self.i),
                    }
                }
            }
            Some(b'[') => {
                self.i += 1;
                let mut items = Vec::new();
                self.ws();
                if self.peek() == Some(b']') {
                    self.i += 1;
                    return Ok(Json::Array(items));
                }
                loop {
                    items.push(self.value(depth + 1)?);
                    self.ws();
                    match self.peek() {
                        Some(b',') => self.i += 1,
                        Some(b']') => {
                            self.i += 1;
                            return Ok(Json::Array(items));
                        }
                        _ => bail!("JSON: expected `,` or `]` at byte {}", self.i),
                    }
                }
            }
            Some(b'"') => Ok(Json::Str(self.string()?)),
            Some(b't') => self.literal("true", Json::Bool(true)),
            Some(b'f') => self.literal("false", Json::Bool(false)),
            Some(b'n') => self.literal("null", Json::Null),
            Some(b'-' | b'0'..=b'9') => self.number(),
            Some(c) => bail!("JSON: unexpected `{}` at byte {}", c as char, self.i),
            None => bail!("JSON: unexpected end"),
        }
    }

    fn number(&mut self) -> Result<Json> {
        let start = self.i;
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_digit() || matches!(c, b'-' | b'+' | b'.' | b'e' | b'E'))
        {
            self.i += 1;
        }
        let text = std::str::from_utf8(&self.s[start..self.i])?;
        // JSON numbers are a subset of what Rust's f64 parser takes, except that it also
        // accepts `inf`/`nan` words, which cannot occur here (only the bytes above).
        let v: f64 = text
            .parse()
            .ok()
            .with_context(|| format!("JSON: bad number `{text}` at byte {start}"))?;
        Ok(Json::Number(v))
    }

    fn string(&mut self) -> Result<String> {
        if self.peek() != Some(b'"') {
            bail!("JSON: expected a string at byte {}", self.i);
        }
        self.i += 1;
        let mut out = String::new();
        loop {
            let start = self.i;
            while self.peek().is_some_and(|c| c != b'"' && c != b'\\') {
                self.i += 1;
            }
            out.push_str(std::str::from_utf8(&self.s[start..self.i])?);
            match self.peek() {
                Some(b'"') => {
                    self.i += 1;
                    return Ok(out);
                }
                Some(b'\\') => {
                    let esc = *self
                        .s
                        .get(self.i + 1)
                        .context("JSON: unterminated string")?;
                    self.i += 2;
                    out.push(match esc {
                        b'"' => '"',
                        b'\\' => '\\',
                        b'/' => '/',
                        b'b' => '\u{8}',
                        b'f' => '\u{c}',
                        b'n' => '\n',
                        b'r' => '\r',
                        b't' => '\t',
                        b'u' => {
                            let hex = self
                                .s
                                .get(self.i..self.i + 4)
                                .context("JSON: short \\u escape")?;
                            self.i += 4;
                            let code = u32::from_str_radix(std::str::from_utf8(hex)?, 16)?;
                            // Surrogate pairs are not needed for delmesh's ASCII keys.
                            char::from_u32(code).unwrap_or('\u{fffd}')
                        }
                        c => bail!("JSON: bad escape `\\{}`", c as char),
                    });
                }
                _ => bail!("JSON: unterminated string"),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_a_delmesh_report() {
        // Shape of `delmesh mesh --report` (crates/delmesh/src/mesh3d.rs, report_json).
        let text = r#"{
  "points": 3389,
  "tetrahedra": 11673,
  "recovery": {"surface_points": 2775, "steps": [{"edges": {"missing_edges": 0}}], "edge_points": 12, "face_points": 3},
  "generation": null,
  "seconds": {"boundary recovery": 0.183327491, "output arrays": 6.08e-4}
}
"#;
        let j = Json::parse(text).unwrap();
        assert_eq!(j.count(&["points"]).unwrap(), 3389);
        assert_eq!(j.count(&["recovery", "edge_points"]).unwrap(), 12);
        assert_eq!(
            j.number(&["seconds", "boundary recovery"]).unwrap(),
            0.183327491
        );
        assert_eq!(j.number(&["seconds", "output arrays"]).unwrap(), 6.08e-4);
        assert_eq!(j.get(&["generation"]), Some(&Json::Null));
        assert!(matches!(
            j.get(&["recovery", "steps"]),
            Some(Json::Array(a)) if a.len() == 1
        ));
        let err = j.number(&["seconds", "point generation"]).unwrap_err();
        assert!(
            err.to_string().contains("no `seconds.point generation`"),
            "{err}"
        );
        assert!(j.count(&["seconds", "output arrays"]).is_err());
    }

    #[test]
    fn strings_literals_and_errors() {
        let j = Json::parse(r#"[true, false, "a\"b\\c\u0041", -1.5e2, {}, []]"#).unwrap();
        assert_eq!(
            j,
            Json::Array(vec![
                Json::Bool(true),
                Json::Bool(false),
                Json::Str("a\"b\\cA".into()),
                Json::Number(-150.0),
                Json::Object(vec![]),
                Json::Array(vec![]),
            ])
        );
        for bad in [
            "{",
            "[1,]",
            "{\"a\" 1}",
            "tru",
            "1 2",
            "\"open",
            "{\"a\": 1,}",
            "",
        ] {
            assert!(Json::parse(bad).is_err(), "{bad}");
        }
        let deep = "[".repeat(100) + &"]".repeat(100);
        assert!(Json::parse(&deep).is_err());
    }
}
