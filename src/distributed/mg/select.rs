//! Which unknowns a coarse level keeps, decided the same way on every rank: an independent set
//! of the graph of strong couplings, grown in rounds. In each round an undecided unknown whose
//! priority beats every undecided strong neighbour's is kept, then the undecided neighbours of
//! kept unknowns are dropped (they will be interpolated), with a halo exchange after each step.
//! Priorities are a hash of the global id with the id breaking ties, so the set depends on the
//! operator alone: not on the partition, the rank count or the order messages arrive in.

use super::along_lines::Mark;
use super::OwnedRows;
use crate::bc::P;
use crate::distributed::reduce::sum_in_rank_order;
use crate::multigrid::layout::Layout;

/// Not decided yet.
pub(super) const UNDECIDED: u8 = 0;
/// Kept on the coarse level.
pub(super) const KEPT: u8 = 1;
/// Interpolated from kept strong neighbours.
pub(super) const DROPPED: u8 = 2;
/// Not an unknown of the solve (an empty row: prescribed).
pub(super) const OUT: u8 = 3;

/// A coupling −a_ij is strong when it is at least this share of the smaller of its two rows'
/// largest couplings (see `strong`), on every level but the biharmonic's first in 3D.
pub(super) const THETA: f64 = 0.25;

/// The strong neighbours of each owned row (local columns): j ≠ i with −a_ij > 0 and
/// −a_ij ≥ θ min(sᵢ, sⱼ) (θ = `theta`; `THETA` but on the biharmonic's first 3D coarsening),
/// sᵢ the largest −a_ik of row i. A symmetric operator makes the relation
/// symmetric across ranks (sⱼ of a halo column comes from its owner), which the rounds of
/// `select` rely on to agree at partition boundaries.
pub(super) fn strong(m: &OwnedRows, theta: f64) -> Vec<Vec<u32>> {
    let (n, owned) = (m.halo.len(), m.halo.owned());
    let mut s = vec![0.0f64; n];
    for (i, si) in s.iter_mut().enumerate().take(owned) {
        let (cols, vals) = m.a.row(i);
        *si = cols.iter().zip(vals).filter(|(&j, _)| j as usize != i).map(|(_, &v)| -v).fold(0.0, f64::max);
    }
    m.halo.refresh(&mut s);
    (0..owned)
        .map(|i| {
            let (cols, vals) = m.a.row(i);
            cols.iter()
                .zip(vals)
                .filter(|(&j, &v)| j as usize != i && -v > 0.0 && -v >= theta * s[i].min(s[j as usize]))
                .map(|(&j, _)| j)
                .collect()
        })
        .collect()
}

/// The lines of a level as its selection reads them (the serial rule `multigrid::lsq::on_lines`,
/// on the biharmonic's 3D hierarchies under thin layers): an unknown on a line is dropped only
/// for a kept unknown on its own line, and at its line's ends also for one off every line (the
/// wall below the first layer), while it couples strongly along its line (else the general rule:
/// on deep levels a wing's lines couple each other along the chord more strongly than along
/// themselves); the lines are visited from the wall outward, so the first layer's unknown goes
/// for the wall's and every other unknown of a line stays, and the layers keep their lines level
/// by level.
#[derive(Clone, Copy)]
pub(super) struct OnLines<'a> {
    /// Where each local entry lies on the level's whole lines (`along_lines::marks`).
    pub(super) marks: &'a [Mark],
}

impl OnLines<'_> {
    /// Whether unknown `i`, whose strong neighbours are `near`, may be dropped for the kept
    /// strong neighbour `j` (`multigrid::lsq::on_lines`: `keeps_to_line`, `may_drop_for`).
    fn may_drop_for(&self, i: usize, near: &[u32], j: usize) -> bool {
        let (mi, mj) = (self.marks[i], self.marks[j]);
        let keeps = mi.on() && near.iter().any(|&u| self.marks[u as usize].line == mi.line);
        !keeps || mj.line == mi.line || (mi.end && !mj.on())
    }
}

/// The role of every local entry (`KEPT`, `DROPPED` or `OUT`; the halo's as its owners decided),
/// given the strong neighbours of the owned rows (collective). With `first` (flags of every local
/// entry) the entries it prescribes (P) beat every other in priority, so a prescribed unknown
/// with a row (a CLAMPED wall's vertex on the biharmonic's levels) is kept unless a prescribed
/// strong neighbour is: the serial selection visits the walls before the inside. With `lines` an
/// unknown on a line is dropped only as `OnLines` says, and a line's unknowns rank together, from
/// the wall outward, as the serial selection visits them.
pub(super) fn select(m: &OwnedRows, strong: &[Vec<u32>], first: Option<&[u8]>, lines: Option<OnLines>) -> Vec<u8> {
    let (n, owned) = (m.halo.len(), m.halo.owned());
    let mut state = vec![UNDECIDED; n];
    for (i, st) in state.iter_mut().enumerate().take(owned) {
        if m.a.row(i).0.is_empty() {
            *st = OUT;
        }
    }
    m.halo.refresh(&mut state);
    let prescribed = |j: usize| first.is_some_and(|f| f.get(j).is_some_and(|&f| f & P != 0));
    // A line's unknowns by its id, then nearest the wall first; the others by their own id. A
    // line's id is one of its unknowns' global ids, which no unknown off the lines shares.
    let rank = |j: usize| match lines.map(|l| l.marks[j]).filter(Mark::on) {
        Some(mark) => (mix(mark.line), u64::MAX - mark.place),
        None => (mix(m.gids[j]), m.gids[j]),
    };
    let priority = |j: usize| (prescribed(j), rank(j));
    // The strong neighbours unknown i may be dropped for.
    let may_drop: Vec<Vec<u32>> = (0..owned)
        .map(|i| match lines {
            Some(l) => strong[i].iter().copied().filter(|&j| l.may_drop_for(i, &strong[i], j as usize)).collect(),
            None => strong[i].clone(),
        })
        .collect();
    loop {
        let undecided = state[..owned].iter().filter(|&&s| s == UNDECIDED).count();
        if sum_in_rank_order(m.halo.comm(), &[undecided as f64])[0] == 0.0 {
            return state;
        }
        // Kept: an unknown that no undecided unknown it may be dropped for outranks.
        let keep: Vec<usize> = (0..owned)
            .filter(|&i| {
                state[i] == UNDECIDED
                    && may_drop[i].iter().all(|&j| state[j as usize] != UNDECIDED || priority(j as usize) < priority(i))
            })
            .collect();
        keep.into_iter().for_each(|i| state[i] = KEPT);
        m.halo.refresh(&mut state);
        for i in 0..owned {
            if state[i] == UNDECIDED && may_drop[i].iter().any(|&j| state[j as usize] == KEPT) {
                state[i] = DROPPED;
            }
        }
        m.halo.refresh(&mut state);
    }
}

/// A well-mixed 64-bit hash of a global id (SplitMix64's finaliser): neighbouring ids get
/// unrelated priorities, so the kept set is spread evenly instead of following the numbering.
pub(super) fn mix(id: u64) -> u64 {
    let mut z = id.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::mix;

    #[test]
    fn mix_spreads_neighbouring_ids() {
        assert_eq!(mix(0), 0xe220_a839_7b1d_cdaf);
    }
}
