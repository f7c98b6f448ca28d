//! The columns A e_j of a level's operator applied in one pass (`LevelOperator::one_pass`), one
//! unit vector after another, as `apply` forms them but only at the rows of A that hold column
//! j: every other row's sum has only terms +0 or −0, from +0, so it is +0. Each row formed is
//! `free_rows`' own sum, so each column is bitwise `apply`'s: the coarsest level's dense matrix
//! (`CoarseSolve`) at the cost of A's nonzeros instead of one product of the whole level per
//! unknown. The biharmonic's two passes over K reach nearly every row of a dense coarsest
//! level through S, where the rows picked one by one cost more than the product's two passes.

use super::level::LevelOperator;
use crate::bc::P;
use crate::sparse::CsrMatrix;

/// The columns of one level's operator; `None` from `new` where it is not applied in one pass.
pub(crate) struct Columns<'a> {
    /// The matrix applied.
    a: &'a CsrMatrix,
    /// Its transpose: row j lists the rows that hold column j.
    t: CsrMatrix,
    /// The unit vector (zero but at the column being formed).
    e: Vec<f64>,
}

impl<'a> Columns<'a> {
    pub(crate) fn new(op: &'a LevelOperator) -> Option<Columns<'a>> {
        let a = op.one_pass()?;
        Some(Columns { a, t: a.transpose(), e: vec![0.0; a.nrows] })
    }

    /// y = A e_j with the rows flagged P zero, as `apply(flags, e_j, y)` gives it. `y` is zero
    /// but at the rows `written` lists (the last column's of this `y`); they are listed anew.
    pub(crate) fn column(&mut self, j: usize, flags: &[u8], y: &mut [f64], written: &mut Vec<u32>) {
        written.iter().for_each(|&i| y[i as usize] = 0.0);
        written.clear();
        self.e[j] = 1.0;
        for &i in self.t.row(j).0 {
            let i = i as usize;
            y[i] = if flags[i] & P != 0 { 0.0 } else { self.a.row_dot(i, &self.e) };
            written.push(i as u32);
        }
        self.e[j] = 0.0;
    }
}
