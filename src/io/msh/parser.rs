//! The byte-level reader of `.msh` files: tokens, lines, binary values, error positions.

use super::super::{line_of, IoError};
use super::GmshType;
use std::collections::HashMap;

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Version {
    V22,
    V41,
}

pub(super) struct Parser<'a> {
    pub(super) b: &'a [u8],
    pub(super) pos: usize,
    pub(super) version: Version,
    pub(super) binary: bool,
    /// Binary data is big-endian.
    pub(super) swap: bool,
    /// Size of `size_t` in 4.1 binary files.
    pub(super) size_t: usize,
    pub(super) physical_names: Vec<(i32, i32, String)>,
    /// (dim, entity tag) -> first physical tag (4.1).
    pub(super) entity_phys: HashMap<(i32, i32), i32>,
    /// Gmsh node tag -> index in `nodes`.
    pub(super) node_index: NodeIndex,
    /// Gmsh tag and (x, y, z) of each node, in file order.
    pub(super) nodes: Vec<(usize, [f64; 3])>,
    /// The elements kept (points excluded), in file order: their type and physical tag, and
    /// where their node indices (into `nodes`, in Gmsh's order) start in `element_nodes`.
    pub(super) elements: Vec<(GmshType, i32, usize)>,
    pub(super) element_nodes: Vec<usize>,
    pub(super) seen_nodes: bool,
    pub(super) seen_elements: bool,
}

impl<'a> Parser<'a> {
    pub(super) fn new(b: &'a [u8]) -> Self {
        Parser {
            b,
            pos: 0,
            version: Version::V41,
            binary: false,
            swap: false,
            size_t: 8,
            physical_names: Vec::new(),
            entity_phys: HashMap::new(),
            node_index: NodeIndex::default(),
            nodes: Vec::new(),
            elements: Vec::new(),
            element_nodes: Vec::new(),
            seen_nodes: false,
            seen_elements: false,
        }
    }

    // ---- errors -------------------------------------------------------------------------------

    pub(super) fn err_at(&self, offset: usize, message: String) -> IoError {
        // At the end of the file: the last line, not the empty one after its newline.
        let l = if offset >= self.b.len() && self.b.ends_with(b"\n") { self.b.len() - 1 } else { offset };
        IoError::Parse { line: line_of(self.b, l), offset: Some(offset), message }
    }
    pub(super) fn err_bin(&self, offset: usize, message: String) -> IoError {
        IoError::Parse { line: 0, offset: Some(offset), message }
    }

    // ---- ASCII --------------------------------------------------------------------------------

    pub(super) fn skip_ws(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// Next whitespace-separated token and its offset; `None` at end of file.
    pub(super) fn token(&mut self) -> Option<(&'a str, usize)> {
        self.skip_ws();
        let start = self.pos;
        while self.pos < self.b.len() && !self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return None;
        }
        // Non-UTF-8 bytes in a token are reported by the number parse that follows.
        Some((std::str::from_utf8(&self.b[start..self.pos]).unwrap_or("\u{fffd}"), start))
    }

    /// The next token parsed as a number; `what` names it in errors ("node tag in $Nodes").
    pub(super) fn num<T: std::str::FromStr>(&mut self, what: &str) -> Result<T, IoError> {
        self.num_named(|| what.to_string())
    }

    /// [`Parser::num`] with the name made only for an error (a name that counts the items: one
    /// `format!` per node would cost more than the number).
    pub(super) fn num_named<T: std::str::FromStr>(&mut self, what: impl FnOnce() -> String) -> Result<T, IoError> {
        match self.token() {
            None => Err(self.err_at(self.b.len(), format!("expected {}, found end of file", what()))),
            Some((t, at)) if t.starts_with('$') => {
                Err(self.err_at(at, format!("expected {}, found `{t}`: the section ends early", what())))
            }
            Some((t, at)) => t.parse().map_err(|_| self.err_at(at, format!("expected {}, found `{t}`", what()))),
        }
    }

    /// The rest of the current line (after skipping leading whitespace), without the newline.
    pub(super) fn rest_of_line(&mut self) -> (&'a str, usize) {
        while self.pos < self.b.len() && matches!(self.b[self.pos], b' ' | b'\t') {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.b.len() && self.b[self.pos] != b'\n' {
            self.pos += 1;
        }
        let line = std::str::from_utf8(&self.b[start..self.pos]).unwrap_or("\u{fffd}");
        (line.trim_end_matches('\r'), start)
    }

    pub(super) fn expect_end(&mut self, section: &str) -> Result<(), IoError> {
        let want = format!("$End{section}");
        match self.token() {
            Some((t, _)) if t == want => Ok(()),
            Some((t, at)) => Err(self.err_at(at, format!("expected `{want}` closing ${section}, found `{t}`"))),
            None => Err(self.err_at(self.b.len(), format!("expected `{want}` closing ${section}, found end of file"))),
        }
    }

    /// Before binary data: the one line break after the ASCII text before it.
    pub(super) fn skip_newline(&mut self) {
        if self.b.get(self.pos) == Some(&b'\r') {
            self.pos += 1;
        }
        if self.b.get(self.pos) == Some(&b'\n') {
            self.pos += 1;
        }
    }

    // ---- binary -------------------------------------------------------------------------------

    pub(super) fn bytes<const N: usize>(&mut self, what: &str) -> Result<[u8; N], IoError> {
        if self.pos + N > self.b.len() {
            return Err(self.err_bin(self.pos, format!("binary data ends early: expected {what}")));
        }
        let mut a = [0u8; N];
        a.copy_from_slice(&self.b[self.pos..self.pos + N]);
        self.pos += N;
        if self.swap {
            a.reverse();
        }
        Ok(a)
    }
    pub(super) fn bin_i32(&mut self, what: &str) -> Result<i32, IoError> {
        Ok(i32::from_le_bytes(self.bytes::<4>(what)?))
    }
    pub(super) fn bin_f64(&mut self, what: &str) -> Result<f64, IoError> {
        Ok(f64::from_le_bytes(self.bytes::<8>(what)?))
    }
    pub(super) fn bin_size(&mut self, what: &str) -> Result<usize, IoError> {
        let at = self.pos;
        let v = if self.size_t == 4 {
            u32::from_le_bytes(self.bytes::<4>(what)?) as u64
        } else {
            u64::from_le_bytes(self.bytes::<8>(what)?)
        };
        usize::try_from(v).map_err(|_| self.err_bin(at, format!("{what} {v} is too large")))
    }
    /// A binary i32 that must be a non-negative tag or count.
    pub(super) fn bin_tag(&mut self, what: &str) -> Result<usize, IoError> {
        let at = self.pos;
        let v = self.bin_i32(what)?;
        usize::try_from(v).map_err(|_| self.err_bin(at, format!("{what} is negative ({v})")))
    }

    // ---- values read either way (4.1) --------------------------------------------------------

    pub(super) fn int41(&mut self, what: &str) -> Result<i32, IoError> {
        if self.binary {
            self.bin_i32(what)
        } else {
            self.num(what)
        }
    }
    pub(super) fn size41(&mut self, what: &str) -> Result<usize, IoError> {
        if self.binary {
            self.bin_size(what)
        } else {
            self.num(what)
        }
    }
    pub(super) fn f64_41(&mut self, what: &str) -> Result<f64, IoError> {
        if self.binary {
            self.bin_f64(what)
        } else {
            self.num(what)
        }
    }
}

/// Gmsh node tags to indices in the parser's `nodes`: a table for the tags below a bound set by
/// the announced node count (Gmsh numbers nodes densely from 1, so this holds them all), a hash
/// map for the larger tags of sparsely numbered files. The bound is set once, before the first
/// node, and never exceeds twice the file's length: a false count cannot make the table large.
#[derive(Default)]
pub(super) struct NodeIndex {
    /// `dense[tag]`: the node's index, `usize::MAX` for a tag not seen; grown to the largest tag
    /// below `bound` seen.
    dense: Vec<usize>,
    bound: usize,
    sparse: HashMap<usize, usize>,
}

impl NodeIndex {
    /// Sets the table's bound for `count` announced nodes in a file of `len` bytes.
    pub(super) fn size_for(&mut self, count: usize, len: usize) {
        if self.dense.is_empty() && self.sparse.is_empty() {
            self.bound = count.min(len).saturating_mul(2).saturating_add(1024);
        }
    }

    /// Records `tag` at `index`; false (and nothing changed) when the tag is already there.
    pub(super) fn insert(&mut self, tag: usize, index: usize) -> bool {
        if tag >= self.bound {
            return match self.sparse.entry(tag) {
                std::collections::hash_map::Entry::Occupied(_) => false,
                std::collections::hash_map::Entry::Vacant(e) => {
                    e.insert(index);
                    true
                }
            };
        }
        if tag >= self.dense.len() {
            self.dense.resize(tag + 1, usize::MAX);
        }
        if self.dense[tag] != usize::MAX {
            return false;
        }
        self.dense[tag] = index;
        true
    }

    /// The index of node `tag`.
    #[inline]
    pub(super) fn get(&self, tag: usize) -> Option<usize> {
        if tag < self.bound {
            self.dense.get(tag).copied().filter(|&i| i != usize::MAX)
        } else {
            self.sparse.get(&tag).copied()
        }
    }
}
