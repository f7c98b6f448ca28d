//! The columns A e_j of a level's operator, one unit vector after another, as `apply` forms
//! them but only at the rows that can hold anything other than +0: the rows of the matrix
//! applied in one pass that hold column j, or for the biharmonic's two passes the rows of K
//! that hold a column k of K whose row k holds column j (S is +0 but there). Every row formed
//! is the product's own sum (`free_rows`' row, `source_row`), and a row of +0 terms sums to +0,
//! so each column is bitwise `apply`'s: the coarsest level's dense matrix (`CoarseSolve`) at
//! the cost of its nonzeros instead of one product of the whole level per unknown.

use super::level::LevelOperator;
use crate::bc::P;
use crate::sparse::CsrMatrix;

/// The columns of one level's operator; `None` from `new` where `apply` is not formed row by
/// row from the vector alone (the fused sweep, a distributed level's exchange between the
/// passes).
pub(crate) struct Columns<'a> {
    op: &'a LevelOperator,
    /// The transpose of the matrix applied in one pass, or of K for the two passes: row j
    /// lists the rows that hold column j.
    t: CsrMatrix,
    /// The unit vector (zero but at the column being formed).
    e: Vec<f64>,
    /// The biharmonic's S, zero but at the rows `in_s` lists.
    s: Vec<f64>,
    in_s: Vec<u32>,
    /// Per row, the call that last formed it (0 none).
    mark: Vec<u32>,
    calls: u32,
}

impl<'a> Columns<'a> {
    pub(crate) fn new(op: &'a LevelOperator) -> Option<Columns<'a>> {
        let two_pass = op.one_pass().is_none();
        if two_pass && (op.fuse.is_some() || op.source_halo.is_some()) {
            return None;
        }
        let t = op.one_pass().unwrap_or(&op.k).transpose();
        let n = op.n();
        Some(Columns { op, t, e: vec![0.0; n], s: vec![0.0; n], in_s: Vec::new(), mark: vec![0; n], calls: 0 })
    }

    /// y = A e_j with the rows flagged P zero, as `apply(flags, e_j, y)` gives it. `y` is zero
    /// but at the rows `written` lists (the last column's of this `y`); they are listed anew.
    pub(crate) fn column(&mut self, j: usize, flags: &[u8], y: &mut [f64], written: &mut Vec<u32>) {
        written.iter().for_each(|&i| y[i as usize] = 0.0);
        written.clear();
        if self.calls == u32::MAX {
            self.mark.iter_mut().for_each(|m| *m = 0);
            self.calls = 0;
        }
        self.calls += 1;
        let Columns { op, t, e, s, in_s, mark, calls } = self;
        let stamp = *calls;
        // The matrix the rows are formed with: A in one pass, else K over S.
        let m = op.one_pass().unwrap_or(&op.k);
        e[j] = 1.0;
        let mut row = |i: u32, u: &[f64], mark: &mut [u32]| {
            if mark[i as usize] != stamp {
                mark[i as usize] = stamp;
                let i = i as usize;
                y[i] = if flags[i] & P != 0 { 0.0 } else { m.row_dot(i, u) };
                written.push(i as u32);
            }
        };
        match op.one_pass() {
            Some(_) => t.row(j).0.iter().for_each(|&i| row(i, e, mark)),
            None => {
                in_s.iter().for_each(|&k| s[k as usize] = 0.0);
                in_s.clear();
                for &k in t.row(j).0 {
                    s[k as usize] = op.source_row(flags, k as usize, e, 0, None);
                    in_s.push(k);
                }
                for &k in in_s.iter() {
                    t.row(k as usize).0.iter().for_each(|&i| row(i, s, mark));
                }
            }
        }
        e[j] = 0.0;
    }
}
