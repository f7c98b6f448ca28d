//! A cursor over one OpenFOAM file: whitespace and C/C++ comments skipped, words, numbers and
//! punctuation read with their line for errors, the `FoamFile` header read into its entries, and
//! raw bytes taken for binary lists.

use crate::io::{line_of, IoError};

/// The entries of a `FoamFile { … }` header that the reader uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Header {
    /// `format`: true for `binary`.
    pub binary: bool,
    /// `class` (`vectorField`, `faceList`, `faceCompactList`, `labelList`, `polyBoundaryMesh`).
    pub class: String,
    /// `location`, without its quotes; empty when absent.
    pub location: String,
    /// `note`, without its quotes (the owner file's `nPoints:… nCells:…`); empty when absent.
    pub note: String,
    /// Bytes of a label in binary data (`arch "…;label=32;…"`): 4 or 8.
    pub label_bytes: usize,
    /// Bytes of a scalar in binary data (`arch "…;scalar=64"`): 4 or 8.
    pub scalar_bytes: usize,
}

/// A position in one file's bytes; `file` names the file in errors.
pub(super) struct Cursor<'a> {
    pub bytes: &'a [u8],
    pub pos: usize,
    pub file: &'a str,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], file: &'a str) -> Cursor<'a> {
        Cursor { bytes, pos: 0, file }
    }

    /// A parse error at the cursor: the file, its line, what was expected.
    pub fn error(&self, message: impl std::fmt::Display) -> IoError {
        self.error_at(self.pos, message)
    }

    /// A parse error at byte `at`.
    pub fn error_at(&self, at: usize, message: impl std::fmt::Display) -> IoError {
        IoError::Parse { line: line_of(self.bytes, at), offset: Some(at), message: format!("{}: {message}", self.file) }
    }

    /// Skips whitespace, `// …` and `/* … */` comments.
    pub fn skip_blank(&mut self) {
        let b = self.bytes;
        loop {
            while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if b[self.pos..].starts_with(b"//") {
                self.pos += b[self.pos..].iter().position(|&c| c == b'\n').unwrap_or(b.len() - self.pos);
            } else if b[self.pos..].starts_with(b"/*") {
                let end = b[self.pos + 2..].windows(2).position(|w| w == b"*/");
                self.pos = end.map_or(b.len(), |e| self.pos + 2 + e + 2);
            } else {
                return;
            }
        }
    }

    /// The next byte after blanks, not consumed; `None` at the end.
    pub fn peek(&mut self) -> Option<u8> {
        self.skip_blank();
        self.bytes.get(self.pos).copied()
    }

    /// Consumes `c` after blanks, or fails naming `what` it opens or closes.
    pub fn expect(&mut self, c: u8, what: &str) -> Result<(), IoError> {
        match self.peek() {
            Some(x) if x == c => {
                self.pos += 1;
                Ok(())
            }
            Some(x) => Err(self.error(format!("`{}` expected {what}, found `{}`", c as char, x as char))),
            None => Err(self.error(format!("`{}` expected {what}, found the end of the file", c as char))),
        }
    }

    /// The next word or number: a run of bytes up to a blank, a bracket, a brace or `;`; a
    /// double-quoted string is one token (with its quotes).
    pub fn token(&mut self, what: &str) -> Result<&'a str, IoError> {
        self.skip_blank();
        let b = self.bytes;
        let start = self.pos;
        if b.get(start) == Some(&b'"') {
            let end = b[start + 1..].iter().position(|&c| c == b'"').ok_or_else(|| self.error("unclosed string"))?;
            self.pos = start + 1 + end + 1;
        } else {
            while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() && !b"(){};".contains(&b[self.pos]) {
                self.pos += 1;
            }
        }
        if self.pos == start {
            let found = b.get(start).map_or("the end of the file".to_string(), |&c| format!("`{}`", c as char));
            return Err(self.error(format!("{what} expected, found {found}")));
        }
        std::str::from_utf8(&b[start..self.pos]).map_err(|_| self.error_at(start, format!("{what}: not UTF-8 text")))
    }

    /// A non-negative integer (a count or an index) no larger than `max`.
    pub fn label(&mut self, what: &str, max: usize) -> Result<usize, IoError> {
        let start = self.pos;
        let t = self.token(what)?;
        match t.parse::<usize>() {
            Ok(v) if v <= max => Ok(v),
            Ok(v) => Err(self.error_at(start, format!("{what} {v} is out of range (at most {max})"))),
            Err(_) => Err(self.error_at(start, format!("{what} expected (a non-negative integer), found `{t}`"))),
        }
    }

    /// A signed integer (a neighbour or owner index, where −1 may mean "none").
    pub fn signed(&mut self, what: &str) -> Result<i64, IoError> {
        let start = self.pos;
        let t = self.token(what)?;
        t.parse::<i64>().map_err(|_| self.error_at(start, format!("{what} expected (an integer), found `{t}`")))
    }

    /// A finite floating-point number.
    pub fn scalar(&mut self, what: &str) -> Result<f64, IoError> {
        let start = self.pos;
        let t = self.token(what)?;
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error_at(start, format!("{what} expected (a finite number), found `{t}`"))),
        }
    }

    /// `n` raw bytes of a binary list, right after its `(`.
    pub fn raw(&mut self, n: usize, what: &str) -> Result<&'a [u8], IoError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len()).ok_or_else(|| {
            self.error(format!(
                "{what}: {n} bytes of binary data expected, the file ends after {}",
                self.bytes.len() - self.pos
            ))
        })?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    /// Skips the value of a dictionary entry up to its `;` (or a sub-dictionary in braces),
    /// brackets and braces nested.
    pub fn skip_entry(&mut self) -> Result<(), IoError> {
        let mut depth = 0usize;
        loop {
            match self.peek() {
                None => return Err(self.error("`;` expected to end the entry, found the end of the file")),
                Some(b'(' | b'{') => {
                    depth += 1;
                    self.pos += 1;
                }
                Some(c @ (b')' | b'}')) => {
                    if depth == 0 {
                        return Err(self.error(format!("`;` expected to end the entry, found `{}`", c as char)));
                    }
                    depth -= 1;
                    self.pos += 1;
                    if depth == 0 && c == b'}' {
                        return Ok(());
                    }
                }
                Some(b';') => {
                    self.pos += 1;
                    if depth == 0 {
                        return Ok(());
                    }
                }
                Some(_) => {
                    self.token("a value")?;
                }
            }
        }
    }

    /// Reads the `FoamFile { … }` header (it must come first): format, class, location and the
    /// label and scalar sizes of `arch`. Only little-endian binary data is read.
    pub fn header(&mut self) -> Result<Header, IoError> {
        let word = self.token("the `FoamFile` header")?;
        if word != "FoamFile" {
            return Err(self.error(format!("the `FoamFile` header expected first, found `{word}`")));
        }
        self.expect(b'{', "to open the FoamFile header")?;
        let mut h = Header { label_bytes: 4, scalar_bytes: 8, ..Header::default() };
        while self.peek() != Some(b'}') {
            let key = self.token("a header entry")?;
            let at = self.pos;
            let value = match key {
                "format" | "class" | "location" | "arch" | "note" => self.token(key)?.trim_matches('"'),
                _ => {
                    self.skip_entry()?;
                    continue;
                }
            };
            self.expect(b';', &format!("after the header's `{key}`"))?;
            match key {
                "format" => {
                    h.binary = match value {
                        "ascii" => false,
                        "binary" => true,
                        _ => return Err(self.error_at(at, format!("format `{value}`: `ascii` or `binary` expected"))),
                    }
                }
                "class" => h.class = value.to_string(),
                "location" => h.location = value.to_string(),
                "note" => h.note = value.to_string(),
                _ => self.arch(value, at, &mut h)?,
            }
        }
        self.expect(b'}', "to close the FoamFile header")?;
        Ok(h)
    }

    /// `arch "LSB;label=32;scalar=64"`: the byte order and the sizes of labels and scalars.
    fn arch(&self, value: &str, at: usize, h: &mut Header) -> Result<(), IoError> {
        for part in value.split(';').map(str::trim) {
            let bits = |v: &str| match v {
                "32" => Ok(4),
                "64" => Ok(8),
                _ => Err(self.error_at(at, format!("arch `{value}`: 32 or 64 bits expected"))),
            };
            if part == "MSB" {
                return Err(IoError::Unsupported(format!("{}: big-endian binary data (arch `{value}`)", self.file)));
            } else if let Some(v) = part.strip_prefix("label=") {
                h.label_bytes = bits(v)?;
            } else if let Some(v) = part.strip_prefix("scalar=") {
                h.scalar_bytes = bits(v)?;
            }
        }
        Ok(())
    }
}
