//! The biharmonic's rows along the lines across wall layers on the distributed levels (2D, as
//! serially: docs/DESIGN.md §5, "Wall layers"): a dropped unknown on a line interpolates from
//! the kept unknowns around it on its line, cubic in the distance along the line, by the serial
//! levels' function (`multigrid::lsq::rows_on_line`).
//!
//! A rank's lines are segments of the whole lines: a partition boundary cuts a line into one
//! segment per rank (`lines`). The rows need the whole line, so the segments are joined across
//! ranks: a segment's end continues across the cut when its nearest neighbour beyond the end (the
//! serial rule that extends a line at its ends, `multigrid::lsq::end_neighbour`) is a halo
//! entry on a line of its owner. The segments so linked take the least global id among them as
//! their label (a few rounds of halo exchanges, each taking the least over the links), and each
//! segment is sent to the rank the label hashes to, which chains them into the whole line,
//! orients it from its end of lower global id, extends it at its ends by their kept neighbours
//! beyond them, computes the rows and sends each to the owner of its unknown. A line's rows
//! thus depend on the whole line alone, not on the ranks that hold its pieces. The same joining
//! tells the 3D selection where each unknown lies on the whole lines that end at a wall
//! (`marks`, read by `select::OnLines`).

use super::select::mix;
use super::OwnedRows;
use crate::distributed::reduce::{all_to_all, max_over_ranks};
use crate::multigrid::layout::Layout;
use crate::multigrid::lines::Lines;
use crate::multigrid::lsq::{end_neighbour, rows_on_line};
use std::collections::{BTreeMap, HashMap};

/// A P row in global terms: (coarse global id, its owner rank, weight) per entry.
type GlobalRow = Vec<(u64, usize, f64)>;

/// No global id: an end without a neighbour beyond it.
const NONE: u64 = u64::MAX;

/// Words of one entry in a message: global id, owner, kept, position.
const ENTRY: usize = 6;

/// Most rounds of the labels' exchange: a line crosses at most this many partition boundaries
/// before its segments stop sharing one label (they then join as far as the label reaches).
const MAX_ROUNDS: usize = 16;

/// One entry of a line as the rank that chains it sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    gid: u64,
    owner: usize,
    kept: bool,
    at: [f64; 3],
}

impl Entry {
    fn words(&self) -> [u64; ENTRY] {
        [
            self.gid,
            self.owner as u64,
            u64::from(self.kept),
            self.at[0].to_bits(),
            self.at[1].to_bits(),
            self.at[2].to_bits(),
        ]
    }

    fn read(w: &[u64]) -> Entry {
        let at = [f64::from_bits(w[3]), f64::from_bits(w[4]), f64::from_bits(w[5])];
        Entry { gid: w[0], owner: w[1] as usize, kept: w[2] == 1, at }
    }
}

/// A segment as sent to the rank that chains its line: its entries in order, and at each end
/// the nearest neighbour beyond it (None: none on the far side within reach).
#[derive(Clone, Debug)]
struct Segment {
    entries: Vec<Entry>,
    beyond: [Option<Entry>; 2],
}

/// Per owned unknown of `m` (the biharmonic's K on a level), its row of P along its line, or None
/// where the least-squares fit decides (collective over `m`'s ranks). `lines` are the level's
/// segments over its owned unknowns, `at` the positions of its local entries and `kept(i)` whether
/// local entry i is a kept unknown.
pub(super) fn rows(
    m: &OwnedRows,
    at: &[[f64; 3]],
    lines: &Lines,
    kept: impl Fn(usize) -> bool,
) -> Vec<Option<GlobalRow>> {
    let size = m.halo.comm().size();
    // Each whole line's rows, sent to the owners of the dropped unknowns: (global id, entries,
    // then (column, owner, weight) per entry).
    let mut back: Vec<Vec<u64>> = vec![Vec::new(); size];
    for line in joined(m, at, lines, kept) {
        let ext: Vec<usize> = (0..line.len()).collect();
        let rel = |v: usize, u: usize| {
            let (p, q) = (line[v].at, line[u].at);
            [q[0] - p[0], q[1] - p[1], q[2] - p[2]]
        };
        let coarse = |u: usize| line[u].kept.then_some((line[u].gid, line[u].owner));
        rows_on_line(
            &ext,
            &rel,
            coarse,
            |_, _| true,
            |v, row| {
                let to = &mut back[line[v].owner];
                to.extend([line[v].gid, row.len() as u64]);
                row.iter().for_each(|&((g, o), w)| to.extend([g, o as u64, w.to_bits()]));
            },
        );
    }
    let mut out: Vec<Option<GlobalRow>> = vec![None; m.halo.owned()];
    for_owned(m, &back, 3, |i, w| {
        out[i] = Some(w.chunks_exact(3).map(|e| (e[0], e[1] as usize, f64::from_bits(e[2]))).collect());
    });
    out
}

/// Where a local entry lies on the whole lines of its level (`marks`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Mark {
    /// The least global id of the entry's whole line (`NONE` off every line).
    pub(super) line: u64,
    /// Its place on the line counted from the wall's end.
    pub(super) place: u64,
    /// Whether it ends its whole line (a segment's end at a cut does not).
    pub(super) end: bool,
}

impl Mark {
    /// Whether the entry is on a line.
    pub(super) fn on(&self) -> bool {
        self.line != NONE
    }
}

/// Where each local entry of `m` lies on the whole lines of its level (collective over `m`'s
/// ranks): the segments `lines` joined across ranks as the rows along them are (`rows`), each
/// line counted from its end beyond which the wall lies (`wall(i)`: local entry i is a
/// prescribed unknown, the serial lines' boundary), or from its end of lower global id where the
/// wall lies beyond both ends or neither; the halo's marks are their owners'.
pub(super) fn marks(m: &OwnedRows, at: &[[f64; 3]], lines: &Lines, wall: impl Fn(usize) -> bool) -> Vec<Mark> {
    let size = m.halo.comm().size();
    let mut back: Vec<Vec<u64>> = vec![Vec::new(); size];
    // Each whole line extended at its ends by the walls beyond them (`joined`'s kept ends).
    for ext in joined(m, at, lines, wall) {
        let (first, last) = (usize::from(ext[0].kept), ext.len() - 1 - usize::from(ext[ext.len() - 1].kept));
        // Only a wall's layers: a chain of flat cells off the walls (a coarse extrusion's
        // triangles, thin along the span) meanders, and the partition moves it.
        if first > last || (first == 0 && last == ext.len() - 1) {
            continue;
        }
        let line = &ext[first..=last];
        let reversed = ext[ext.len() - 1].kept && !ext[0].kept;
        let id = line.iter().map(|e| e.gid).min().unwrap_or(NONE);
        for (p, e) in line.iter().enumerate() {
            let place = if reversed { line.len() - 1 - p } else { p };
            let end = p == 0 || p + 1 == line.len();
            back[e.owner].extend([e.gid, 3, id, place as u64, u64::from(end)]);
        }
    }
    let mut line = vec![NONE; m.halo.len()];
    let mut place = vec![0u64; m.halo.len()];
    let mut end = vec![0u8; m.halo.len()];
    for_owned(m, &back, 1, |i, w| {
        (line[i], place[i], end[i]) = (w[0], w[1], u8::from(w[2] == 1));
    });
    m.halo.refresh(&mut line);
    m.halo.refresh(&mut place);
    m.halo.refresh(&mut end);
    (0..m.halo.len()).map(|i| Mark { line: line[i], place: place[i], end: end[i] == 1 }).collect()
}

/// Sends each rank's `send` (records of a global id, a length and that many entries of `words`
/// words each, addressed to the id's owner) and gives `put` each owned entry's received words
/// (collective).
fn for_owned(m: &OwnedRows, send: &[Vec<u64>], words: usize, mut put: impl FnMut(usize, &[u64])) {
    let (comm, owned) = (m.halo.comm(), m.halo.owned());
    let (me, owners) = (comm.rank(), m.halo.owner_ranks());
    let local_of: HashMap<u64, usize> = m.gids.iter().zip(0..).map(|(&g, i)| (g, i)).collect();
    for got in &all_to_all(comm, send) {
        let mut w = &got[..];
        while w.len() >= 2 {
            let (gid, len) = (w[0], w[1] as usize);
            let take = (words * len).min(w.len() - 2);
            if let Some(&i) = local_of.get(&gid).filter(|&&i| i < owned && owners[i] == me) {
                put(i, &w[2..2 + take]);
            }
            w = &w[2 + take..];
        }
    }
}

/// The whole lines of `m`'s level whose chaining falls to this rank (collective over `m`'s
/// ranks): the segments `lines` (over its owned unknowns, at the positions `at` of its local
/// entries) joined across cuts, each oriented from its end of lower global id and extended at its
/// ends by the neighbours beyond them that are `kept` (`chain`).
fn joined(m: &OwnedRows, at: &[[f64; 3]], lines: &Lines, kept: impl Fn(usize) -> bool) -> Vec<Vec<Entry>> {
    let (comm, owned, n) = (m.halo.comm(), m.halo.owned(), m.halo.len());
    let size = comm.size();
    let owners = m.halo.owner_ranks();
    let rel = |v: usize, u: usize| {
        let (p, q) = (at[v], at[u]);
        [q[0] - p[0], q[1] - p[1], q[2] - p[2]]
    };
    let entry = |v: usize| Entry { gid: m.gids[v], owner: owners[v], kept: kept(v), at: at[v] };
    // Whether each local entry is on a line of its owner.
    let mut on_line = vec![0u8; n];
    lines.unknowns.iter().for_each(|&v| on_line[v as usize] = 1);
    m.halo.refresh(&mut on_line);
    // Each segment's neighbours beyond its ends (any, kept or not) and whether they continue it
    // across a cut.
    let segments: Vec<(Segment, [bool; 2])> = (0..lines.len())
        .map(|l| {
            let line = lines.line(l);
            let last = line.len() - 1;
            let beyond = |end: usize, inner: usize| {
                end_neighbour(m.a.row(line[end] as usize).0, line, end, inner, &rel, |_| true, |u| m.gids[u])
            };
            let ends = [beyond(0, 1), beyond(last, last.wrapping_sub(1))];
            let cut = ends.map(|u| u.is_some_and(|u| u >= owned && on_line[u] == 1));
            let entries = line.iter().map(|&v| entry(v as usize)).collect();
            (Segment { entries, beyond: ends.map(|u| u.map(entry)) }, cut)
        })
        .collect();

    // Labels: the least global id over the segments linked across cuts.
    let mut label = vec![NONE; n];
    let mut seg_label: Vec<u64> =
        segments.iter().map(|(s, _)| s.entries.iter().map(|e| e.gid).min().unwrap_or(NONE)).collect();
    let local_of: HashMap<u64, usize> = m.gids.iter().zip(0..).map(|(&g, i)| (g, i)).collect();
    for _ in 0..MAX_ROUNDS {
        for (l, &lab) in seg_label.iter().enumerate() {
            lines.line(l).iter().for_each(|&v| label[v as usize] = lab);
        }
        m.halo.refresh(&mut label);
        let mut changed = false;
        for ((seg, cut), lab) in segments.iter().zip(seg_label.iter_mut()) {
            for (b, &c) in seg.beyond.iter().zip(cut) {
                if let (Some(b), true) = (b, c) {
                    let there = local_of.get(&b.gid).map_or(NONE, |&u| label[u]);
                    if there < *lab {
                        *lab = there;
                        changed = true;
                    }
                }
            }
        }
        if max_over_ranks(comm, f64::from(u8::from(changed))) == 0.0 {
            break;
        }
    }

    // Each segment to the rank of its label.
    let mut send: Vec<Vec<u64>> = vec![Vec::new(); size];
    for ((seg, _), &lab) in segments.iter().zip(&seg_label) {
        let to = &mut send[(mix(lab) % size as u64) as usize];
        to.extend([lab, seg.entries.len() as u64]);
        for b in &seg.beyond {
            match b {
                Some(e) => to.extend(e.words()),
                None => to.extend([NONE; ENTRY]),
            }
        }
        seg.entries.iter().for_each(|e| to.extend(e.words()));
    }
    let received = all_to_all(comm, &send);
    let mut by_label: BTreeMap<u64, Vec<Segment>> = BTreeMap::new();
    for words in &received {
        let mut w = &words[..];
        while w.len() >= 2 + 2 * ENTRY {
            let (lab, len) = (w[0], w[1] as usize);
            let end = |k: usize| Some(Entry::read(&w[2 + k * ENTRY..2 + (k + 1) * ENTRY])).filter(|e| e.gid != NONE);
            let beyond = [end(0), end(1)];
            let body = &w[2 + 2 * ENTRY..];
            let take = (len * ENTRY).min(body.len());
            let entries = body[..take].chunks_exact(ENTRY).map(Entry::read).collect();
            by_label.entry(lab).or_default().push(Segment { entries, beyond });
            w = &body[take..];
        }
    }
    by_label.into_values().flat_map(chain).collect()
}

/// The whole lines of one label's segments: each segment's ends linked to the segments whose end
/// entry lies beyond them, both ways, the chains read from an unlinked end, each oriented from its
/// end of lower global id and extended at its ends by their kept neighbours beyond them. Segments
/// that close a cycle stay apart (none occurs across wall layers).
fn chain(mut segs: Vec<Segment>) -> Vec<Vec<Entry>> {
    // A fixed order, whichever ranks sent them.
    segs.sort_by_key(|s| s.entries.first().map_or(NONE, |e| e.gid));
    let end_gid = |s: &Segment, k: usize| if k == 0 { s.entries[0].gid } else { s.entries[s.entries.len() - 1].gid };
    let at_end: HashMap<u64, usize> =
        segs.iter().enumerate().rev().flat_map(|(i, s)| [(end_gid(s, 1), i), (end_gid(s, 0), i)]).collect();
    // link[i][k]: the segment and end that end k of segment i continues into. Two segments link
    // when each end's neighbour beyond it is the other's end; a segment of one unknown (a line's
    // only kept unknown on its rank) has no direction to look beyond it, and takes the first two
    // segments that continue into it.
    let mut link: Vec<[Option<(usize, usize)>; 2]> = vec![[None; 2]; segs.len()];
    let mut into_single: Vec<Vec<(usize, usize)>> = vec![Vec::new(); segs.len()];
    for (i, s) in segs.iter().enumerate().filter(|(_, s)| s.entries.len() > 1) {
        for (k, beyond) in s.beyond.iter().enumerate() {
            let Some((b, &j)) = beyond.and_then(|b| Some((b.gid, at_end.get(&b.gid)?))).filter(|&(_, &j)| j != i)
            else {
                continue;
            };
            let t = &segs[j];
            if t.entries.len() == 1 {
                into_single[j].push((i, k));
                continue;
            }
            let kj = usize::from(end_gid(t, 0) != b);
            if t.beyond[kj].is_some_and(|b| b.gid == end_gid(s, k)) {
                link[i][k] = Some((j, kj));
            }
        }
    }
    for (j, from) in into_single.iter().enumerate() {
        for (kj, &(i, k)) in from.iter().take(2).enumerate() {
            link[j][kj] = Some((i, k));
            link[i][k] = Some((j, kj));
        }
    }
    let mut used = vec![false; segs.len()];
    let mut lines = Vec::new();
    for start in 0..segs.len() {
        if used[start] {
            continue;
        }
        // Walk to an unlinked end, then read the chain from there.
        let (mut i, mut k) = (start, 0);
        let mut steps = 0;
        while let Some((j, kj)) = link[i][k] {
            (i, k) = (j, 1 - kj);
            steps += 1;
            if steps > segs.len() {
                break;
            }
        }
        let cycle = steps > segs.len();
        let (first, mut from) = if cycle { ((start, 0), (start, 0)) } else { ((i, k), (i, k)) };
        let mut line: Vec<Entry> = Vec::new();
        let mut ends = [segs[first.0].beyond[first.1], None];
        loop {
            let (i, k) = from;
            used[i] = true;
            let s = &segs[i];
            if k == 0 {
                line.extend(&s.entries);
            } else {
                line.extend(s.entries.iter().rev());
            }
            ends[1] = s.beyond[1 - k];
            match link[i][1 - k] {
                Some((j, kj)) if !cycle && !used[j] => from = (j, kj),
                _ => break,
            }
        }
        if line.len() > 1 && line[0].gid > line[line.len() - 1].gid {
            line.reverse();
            ends.swap(0, 1);
        }
        // The ends extended by their kept neighbours beyond them (the serial lines' ends).
        let mut ext: Vec<Entry> = ends[0].filter(|e| e.kept).into_iter().collect();
        ext.extend(line);
        ext.extend(ends[1].filter(|e| e.kept));
        lines.push(ext);
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(gid: u64, kept: bool) -> Entry {
        Entry { gid, owner: (gid % 3) as usize, kept, at: [0.0, gid as f64, 0.0] }
    }

    fn gids(line: &[Entry]) -> Vec<u64> {
        line.iter().map(|e| e.gid).collect()
    }

    /// A line 10..=15 above a wall vertex 1, cut into three segments on three ranks: the lower
    /// one in order, the middle one a single unknown, the upper one reversed. They chain into the
    /// whole line from its lower global id, extended by the kept wall vertex; a segment whose
    /// neighbour beyond does not look back stays apart.
    #[test]
    fn segments_chain_into_the_whole_line() {
        let seg = |ids: &[u64], beyond: [Option<Entry>; 2]| Segment {
            entries: ids.iter().map(|&g| at(g, g % 2 == 0)).collect(),
            beyond,
        };
        let lower = seg(&[10, 11], [Some(at(1, true)), Some(at(12, true))]);
        let middle = seg(&[12], [None, None]);
        let upper = seg(&[15, 14, 13], [None, Some(at(12, true))]);
        let lines = chain(vec![upper.clone(), middle, lower.clone()]);
        assert_eq!(lines.len(), 1);
        assert_eq!(gids(&lines[0]), [1, 10, 11, 12, 13, 14, 15]);

        // Two segments linked both ways, the end beyond the upper one not kept.
        let lower = seg(&[10, 11, 12], [Some(at(1, true)), Some(at(13, false))]);
        let upper = seg(&[15, 14, 13], [Some(at(16, false)), Some(at(12, true))]);
        let lines = chain(vec![upper.clone(), lower.clone()]);
        assert_eq!(gids(&lines[0]), [1, 10, 11, 12, 13, 14, 15]);

        // The upper segment looks beyond itself elsewhere: no link.
        let upper = seg(&[15, 14, 13], [None, Some(at(20, true))]);
        let lines = chain(vec![upper, lower]);
        assert_eq!(lines.len(), 2);
        assert_eq!(gids(&lines[0]), [1, 10, 11, 12]);
        assert_eq!(gids(&lines[1]), [20, 13, 14, 15]);
    }
}
