//! Periodic links across ranks (docs/DESIGN.md §5 "Across ranks"): the vertices a link joins
//! are one unknown in one process; across ranks each keeps its own row, and the solve runs on
//! the vectors whose tied vertices are equal.
//!
//! The vertices of a class (joined directly or through a chain of links) are each owned by
//! some rank; the class is owned by the owner of its lowest global id. A small vector per rank
//! holds one entry per class it owns, then one per class it holds an owned copy of, with halo
//! lists as the mesh's (`dist_mesh::halo_lists`): summing the copies into the class's owner
//! (`add_to_owners`), dividing and copying back (`refresh`) is the mean over the class, the
//! projection Π on the tied vectors, and with the lumped masses as weights the biharmonic's
//! merged S = Σ (K x)ᵥ / Σ Vᵥ.
//!
//! Resolving a link needs the vertices of both patches: every rank gathers the owned vertices
//! of the linked patches of all ranks (boundary curves or surfaces) and matches them as one
//! process does, so every rank finds the same pairs and the same faults.

use super::comm::Comm;
use super::dist_mesh::halo_lists;
use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::reduce::gather_varcount;
use crate::bc::{check_offset, match_by_offset, Link};
use crate::multigrid::group::{estimate_lambda_max, GroupOp};
use crate::multigrid::layout::Layout;
use crate::multigrid::level::Level;
use crate::sparse::CsrMatrix;
use crate::Mesh;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::Arc;

/// The classes of tied vertices a rank holds, and how to average over them.
#[derive(Debug)]
pub(crate) struct Ties {
    /// The layout of the tie vector: the classes this rank owns, then the others it holds an
    /// owned copy of.
    layout: HaloLayout,
    /// Each owned tied vertex (a local index) and its entry in the tie vector, ascending.
    members: Vec<(u32, u32)>,
    /// The global id of each of `members`.
    member_gids: Vec<u64>,
    /// Copies of each owned class.
    copies: Vec<f64>,
    /// The class (its lowest global id) of every local vertex that is tied.
    class_of: Vec<Option<u64>>,
    /// Pairs of classes (lower id first) that more than one cell edge of the whole mesh joins
    /// (the sides of a periodic seam), with the number of those edges.
    seams: HashMap<(u64, u64), f64>,
}

/// The biharmonic's weights at tied vertices: the lumped mass of each member and the summed
/// masses of each owned class.
#[derive(Debug)]
pub(crate) struct Weights {
    masses: Vec<f64>,
    sums: Vec<f64>,
}

/// The pairs of global ids the links join, and the owner rank of every linked vertex.
#[derive(Debug)]
pub(crate) struct Linked {
    pub(crate) pairs: Vec<[u64; 2]>,
    pub(crate) owner_of: HashMap<u64, usize>,
}

/// The pairs `links` make on the mesh (`mesh`: the rank's part in layout order, `gids` its
/// global ids, the first `owned` vertices owned): None without links (collective; the same on
/// every rank). Explicit pairs name global ids. Errors: an unusable offset, a vertex without
/// its partner (named by rank and global id), a pair naming a global id no rank has.
pub(crate) fn link_pairs(
    comm: &Arc<Comm>,
    mesh: &Mesh,
    gids: &[u64],
    owned: usize,
    links: &[Link],
) -> Result<Option<Linked>, DistError> {
    if links.is_empty() {
        return Ok(None);
    }
    let me = comm.rank();
    let mut pairs: Vec<[u64; 2]> = Vec::new();
    let mut owner_of: HashMap<u64, usize> = HashMap::new();
    for link in links {
        let &Link::ByOffset { a, b, offset, tol } = link else {
            if let Link::Pairs(p) = link {
                pairs.extend(pairs_by_ids(comm, gids, owned, p, &mut owner_of)?);
            }
            continue;
        };
        check_offset(mesh.dim(), a, b, offset, tol)
            .map_err(|e| DistError::new(me, DistErrorKind::Input, e.to_string()))?;
        let (ga, xa, ra) = gathered_patch(comm, mesh, gids, owned, a);
        let (gb, xb, rb) = gathered_patch(comm, mesh, gids, owned, b);
        // Points of both patches, a's first: index i names point i.
        let ids: Vec<u64> = ga.iter().chain(&gb).copied().collect();
        let xs: Vec<[f64; 3]> = xa.iter().chain(&xb).copied().collect();
        let ranks: Vec<usize> = ra.iter().chain(&rb).copied().collect();
        let va: Vec<u32> = (0..ga.len() as u32).collect();
        let vb: Vec<u32> = (ga.len() as u32..ids.len() as u32).collect();
        let name = |i: u32| format!("global id {}", ids[i as usize]);
        let matched = match_by_offset(mesh.dim(), [a, b], offset, tol, &va, &vb, |i| xs[i as usize], name);
        let found = matched
            .map_err(|(i, msg)| DistError::new(*ranks.get(i as usize).unwrap_or(&0), DistErrorKind::Input, msg))?;
        pairs.extend(found.iter().map(|&[p, q]| [ids[p as usize], ids[q as usize]]));
        ids.iter().zip(&ranks).for_each(|(&g, &r)| {
            owner_of.insert(g, r);
        });
    }
    Ok(Some(Linked { pairs, owner_of }))
}

impl Ties {
    /// The classes `linked` makes on the mesh (`mesh`: the rank's part in layout order, `gids`
    /// its global ids, the first `owned` vertices owned). Collective; the error (a halo list
    /// naming a class its owner does not hold) is one rank's.
    pub(crate) fn from_pairs(
        comm: &Arc<Comm>,
        mesh: &Mesh,
        gids: &[u64],
        owned: usize,
        linked: Linked,
    ) -> Result<Ties, DistError> {
        let me = comm.rank();
        let Linked { pairs, owner_of } = linked;
        let master = classes(&pairs);
        // Per class (by its lowest global id): its owner and its number of vertices.
        let mut size: BTreeMap<u64, usize> = BTreeMap::new();
        master.values().for_each(|&m| *size.entry(m).or_default() += 1);
        let class_owner = |m: u64| owner_of.get(&m).copied().unwrap_or(0);
        // The tie vector: owned classes by id, then the others held, by (owner, id).
        let mut held: Vec<u64> = (0..owned).filter_map(|v| master.get(&gids[v]).copied()).collect();
        held.extend(size.keys().filter(|&&m| class_owner(m) == me));
        held.sort_unstable_by_key(|&m| (class_owner(m) != me, class_owner(m), m));
        held.dedup();
        let owners: Vec<usize> = held.iter().map(|&m| class_owner(m)).collect();
        let order: Vec<u32> = (0..held.len() as u32).collect();
        let (layout, error) = halo_lists(comm, &order, &held, &owners);
        if let Some(e) = error {
            return Err(e);
        }
        let entry: HashMap<u64, u32> = held.iter().zip(0..).map(|(&m, i)| (m, i)).collect();
        let members: Vec<(u32, u32)> =
            (0..owned).filter_map(|v| master.get(&gids[v]).map(|m| (v as u32, entry[m]))).collect();
        let member_gids = members.iter().map(|&(v, _)| gids[v as usize]).collect();
        let copies = held[..layout.owned()].iter().map(|m| size[m] as f64).collect();
        let class_of: Vec<Option<u64>> = gids.iter().map(|g| master.get(g).copied()).collect();
        let seams = seams(comm, mesh, gids, &class_of, &master);
        Ok(Ties { layout, members, member_gids, copies, class_of, seams })
    }

    /// The lumped masses `mass` of the local vertices (owned ones read) as the weights of
    /// `merge_sources` (collective).
    pub(crate) fn weights(&self, mass: &[f64]) -> Weights {
        let masses: Vec<f64> = self.members.iter().map(|&(v, _)| mass[v as usize]).collect();
        let sums = self.sums(|k, v| masses[k] * v, &vec![1.0; mass.len()]);
        Weights { sums: sums[..self.layout.owned()].to_vec(), masses }
    }

    /// The tie vector with each owned class's Σ f(k, block[v]) over its members k (vertex v),
    /// every rank's copies added in rank order (collective).
    fn sums(&self, f: impl Fn(usize, f64) -> f64, block: &[f64]) -> Vec<f64> {
        let mut t = vec![0.0; self.layout.len()];
        for (k, &(v, e)) in self.members.iter().enumerate() {
            t[e as usize] += f(k, block[v as usize]);
        }
        self.layout.add_to_owners(&mut t);
        t
    }

    /// Every owned member of `block` takes its class's Σ f(k, value) / `div` (per owned class)
    /// (collective).
    fn spread(&self, block: &mut [f64], f: impl Fn(usize, f64) -> f64, div: &[f64]) {
        let mut t = self.sums(f, block);
        t.iter_mut().zip(div).for_each(|(t, d)| *t /= d);
        self.layout.refresh(&mut t);
        for &(v, e) in &self.members {
            block[v as usize] = t[e as usize];
        }
    }

    /// Π: every owned tied vertex of `block` takes the mean of its class (collective).
    pub(crate) fn average(&self, block: &mut [f64]) {
        self.spread(block, |_, v| v, &self.copies);
    }

    /// The biharmonic's S at tied vertices: Σ Vᵥ Sᵥ / Σ Vᵥ over the class, i.e. the class's
    /// summed K x over its summed mass (collective).
    pub(crate) fn merge_sources(&self, s: &mut [f64], w: &Weights) {
        self.spread(s, |k, v| w.masses[k] * v, &w.sums);
    }

    /// Every owned tied vertex of `block` takes its class's sum (collective).
    pub(crate) fn total(&self, block: &mut [f64]) {
        let ones = vec![1.0; self.copies.len()];
        self.spread(block, |_, v| v, &ones);
    }

    /// The spring analogy's K on the rank's part with each spring of a periodic seam shared:
    /// one process merges the two sides' edges into one spring, so each side's edge weighs
    /// 1/m of it (m the edges joining the two classes), and the diagonal is the rows' sum again.
    pub(crate) fn share_seam_springs(&self, k: &mut CsrMatrix) {
        for i in 0..k.nrows {
            let Some(ci) = self.class_of[i] else { continue };
            let range = k.row_ptr[i] as usize..k.row_ptr[i + 1] as usize;
            let mut changed = false;
            for p in range.clone() {
                let j = k.cols[p] as usize;
                let Some(cj) = self.class_of[j].filter(|_| j != i) else { continue };
                if let Some(m) = self.seams.get(&(ci.min(cj), ci.max(cj))) {
                    k.vals[p] /= m;
                    changed = true;
                }
            }
            if changed {
                let off: f64 = range.clone().filter(|&p| k.cols[p] as usize != i).map(|p| k.vals[p]).sum();
                range.filter(|&p| k.cols[p] as usize == i).for_each(|p| k.vals[p] = -off);
            }
        }
    }

    /// Every owned tied vertex of `block` takes the value of its class's first member, the
    /// vertex of the class's lowest global id, which one process reads for its merged unknown
    /// (collective). The class's owner owns that vertex.
    pub(crate) fn take_firsts(&self, block: &mut [f64]) {
        let mut t = vec![0.0; self.layout.len()];
        for (&(v, e), &g) in self.members.iter().zip(&self.member_gids) {
            if self.class_of[v as usize] == Some(g) {
                t[e as usize] = block[v as usize];
            }
        }
        self.layout.refresh(&mut t);
        for &(v, e) in &self.members {
            block[v as usize] = t[e as usize];
        }
    }

    /// Per class that has a vertex on this rank (owned or not), the lists `list(v)` of its
    /// members joined in the order of their global ids, as one process joins its merged
    /// unknown's vertices' lists (collective: every rank's owned members' nonempty lists are
    /// gathered; the classes are few, on the linked patches).
    pub(crate) fn joined_lists(&self, list: impl Fn(usize) -> Vec<[f64; 3]>) -> HashMap<u64, Vec<[f64; 3]>> {
        // Per member with a nonempty list: its class, its global id and its list's length.
        let (mut heads, mut values): (Vec<u64>, Vec<f64>) = (Vec::new(), Vec::new());
        for (&(v, _), &g) in self.members.iter().zip(&self.member_gids) {
            let l = list(v as usize);
            if let (Some(c), false) = (self.class_of[v as usize], l.is_empty()) {
                heads.extend([c, g, l.len() as u64]);
                values.extend(l.iter().flatten());
            }
        }
        let comm = self.layout.comm();
        let (heads, values) = (gather_varcount(comm, &heads), gather_varcount(comm, &values));
        let wanted: HashSet<u64> = self.class_of.iter().flatten().copied().collect();
        let mut by_member: BTreeMap<(u64, u64), Vec<[f64; 3]>> = BTreeMap::new();
        for (h, x) in heads.iter().zip(&values) {
            let mut points = x.chunks_exact(3).map(|p| [p[0], p[1], p[2]]);
            for head in h.chunks_exact(3) {
                let l: Vec<[f64; 3]> = points.by_ref().take(head[2] as usize).collect();
                if wanted.contains(&head[0]) {
                    by_member.insert((head[0], head[1]), l);
                }
            }
        }
        let mut out: HashMap<u64, Vec<[f64; 3]>> = HashMap::new();
        for ((c, _), l) in by_member {
            out.entry(c).or_default().extend(l);
        }
        out
    }

    /// The class (its lowest global id) of local vertex `v`, if it is tied.
    pub(crate) fn class_of(&self, v: usize) -> Option<u64> {
        self.class_of[v]
    }

    /// The owned tied vertices (local indices), ascending.
    pub(crate) fn members(&self) -> impl Iterator<Item = usize> + '_ {
        self.members.iter().map(|&(v, _)| v as usize)
    }

    /// Makes the prescribed values `dp` of the owned tied vertices their class's mean, after
    /// checking that the copies agree (to 1e-9 relative, as one process checks linked
    /// vertices): else the global id (`gids`, layout order) of a copy that differs
    /// (collective).
    pub(crate) fn agreed_values(&self, dp: &mut [f64], gids: &[u64]) -> Result<(), String> {
        let given: Vec<f64> = self.members.iter().map(|&(v, _)| dp[v as usize]).collect();
        self.average(dp);
        let differs = self.members.iter().zip(&given).find(|(&(v, _), &g)| {
            let m = dp[v as usize];
            (g - m).abs() > 1e-9 * (1.0 + g.abs().max(m.abs()))
        });
        match differs {
            Some((&(v, _), g)) => {
                Err(format!("global id {} is given {g}, its class {} on average", gids[v as usize], dp[v as usize]))
            }
            None => Ok(()),
        }
    }

    /// Makes the inverse Jacobi diagonal of every component of `level` the same at the copies
    /// of a class: 1 / the mean of their D. On the tied vectors a class's D is then the sum of
    /// its copies' row bounds, which bounds the summed row of the class, so the l1 bound's
    /// guarantee holds; the smoother's λmax is estimated again (collective).
    pub(crate) fn equalise_bounds(&self, level: &mut Level) {
        for inv in level.inv_d.iter_mut() {
            let mut d: Vec<f64> = inv.iter().map(|&x| if x > 0.0 { 1.0 / x } else { 0.0 }).collect();
            self.average(&mut d);
            for &(v, _) in &self.members {
                let d = d[v as usize];
                inv[v as usize] = if d > 0.0 { 1.0 / d } else { 0.0 };
            }
        }
        let comps = level.inv_d.len();
        level.lambda_max = (0..comps).map(|c| estimate_lambda_max(&GroupOp::new(level, c..c + 1, false))).collect();
    }
}

/// The class pairs (`class`: every tied global id's) more than one cell edge joins, with their
/// number of edges (collective): every rank's edges between tied vertices by global ids,
/// gathered, one each.
fn seams(
    comm: &Comm,
    mesh: &Mesh,
    gids: &[u64],
    class_of: &[Option<u64>],
    class: &HashMap<u64, u64>,
) -> HashMap<(u64, u64), f64> {
    let mut mine: Vec<u64> = Vec::new();
    for c in (0..mesh.num_cells()).filter(|&c| !mesh.cell_type(c).is_general()) {
        let cell = mesh.cell(c);
        for &[i, j] in mesh.cell_type(c).edges() {
            let (u, w) = (cell[i as usize] as usize, cell[j as usize] as usize);
            if class_of[u].is_some() && class_of[w].is_some() {
                mine.extend([gids[u].min(gids[w]), gids[u].max(gids[w])]);
            }
        }
    }
    let mut edges: Vec<[u64; 2]> =
        gather_varcount(comm, &mine).iter().flat_map(|l| l.chunks_exact(2).map(|e| [e[0], e[1]])).collect();
    edges.sort_unstable();
    edges.dedup();
    let mut count: HashMap<(u64, u64), f64> = HashMap::new();
    for [a, b] in edges {
        if let (Some(&ca), Some(&cb)) = (class.get(&a), class.get(&b)) {
            *count.entry((ca.min(cb), ca.max(cb))).or_default() += 1.0;
        }
    }
    count.retain(|_, m| *m > 1.0);
    count
}

/// The explicit pairs `p` of global ids, with the owner of each id they name added to
/// `owner_of` (collective; the same on every rank). Error: an id no rank owns.
fn pairs_by_ids(
    comm: &Comm,
    gids: &[u64],
    owned: usize,
    p: &[[u32; 2]],
    owner_of: &mut HashMap<u64, usize>,
) -> Result<Vec<[u64; 2]>, DistError> {
    let named: Vec<[u64; 2]> = p.iter().map(|&[a, b]| [u64::from(a), u64::from(b)]).collect();
    let wanted: HashSet<u64> = named.iter().flatten().copied().collect();
    let mine: Vec<u64> = gids[..owned].iter().copied().filter(|g| wanted.contains(g)).collect();
    for (r, ids) in gather_varcount(comm, &mine).into_iter().enumerate() {
        ids.into_iter().for_each(|g| {
            owner_of.insert(g, r);
        });
    }
    match named.iter().flatten().find(|g| !owner_of.contains_key(g)) {
        Some(g) => Err(DistError::new(
            0,
            DistErrorKind::Input,
            format!("a link pair names global id {g}, which no rank has: on a distributed mesh pairs name global ids"),
        )),
        None => Ok(named),
    }
}

/// The owned vertices of patch `p` on every rank: their global ids, positions and owner ranks,
/// in rank order (collective).
fn gathered_patch(
    comm: &Comm,
    mesh: &Mesh,
    gids: &[u64],
    owned: usize,
    p: i32,
) -> (Vec<u64>, Vec<[f64; 3]>, Vec<usize>) {
    let dim = mesh.dim();
    let mine: Vec<u32> = mesh.patch_vertices(p).into_iter().filter(|&v| (v as usize) < owned).collect();
    let ids: Vec<u64> = mine.iter().map(|&v| gids[v as usize]).collect();
    let xs: Vec<f64> = mine.iter().flat_map(|&v| mesh.point(v as usize)[..dim].to_vec()).collect();
    let all_ids = gather_varcount(comm, &ids);
    let all_xs = gather_varcount(comm, &xs);
    let ranks = all_ids.iter().enumerate().flat_map(|(r, l)| std::iter::repeat_n(r, l.len())).collect();
    let points = all_xs
        .iter()
        .flat_map(|l| l.chunks_exact(dim))
        .map(|c| {
            let mut x = [0.0; 3];
            x[..dim].copy_from_slice(c);
            x
        })
        .collect();
    (all_ids.into_iter().flatten().collect(), points, ranks)
}

/// The lowest global id of the class of every linked vertex (joined by `pairs`, directly or
/// through chains).
fn classes(pairs: &[[u64; 2]]) -> HashMap<u64, u64> {
    let mut parent: HashMap<u64, u64> = HashMap::new();
    fn root(parent: &mut HashMap<u64, u64>, g: u64) -> u64 {
        let mut r = g;
        while let Some(&p) = parent.get(&r).filter(|&&p| p != r) {
            r = p;
        }
        parent.insert(g, r);
        r
    }
    for &[a, b] in pairs {
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        // The lower id becomes the root, so a root is its class's lowest id.
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        parent.insert(hi, lo);
        parent.entry(lo).or_insert(lo);
    }
    let ids: Vec<u64> = parent.keys().copied().collect();
    ids.into_iter().map(|g| (g, root(&mut parent, g))).collect()
}
