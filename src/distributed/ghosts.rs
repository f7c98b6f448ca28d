//! The ghost layer completed by the library: every cell another rank owns around the vertices in
//! a rank's owned cells, fetched from its owner with its vertices (global ids, coordinates,
//! owners), its type or polyhedron faces, its region and the tagged faces on it. A host may give
//! each rank its owned cells alone, or with any part of its ghost layer.
//!
//! Who shares a vertex is found by a rendezvous on its global id: rank g mod size hears from
//! every rank that has global id g in an owned cell and tells each of them the others. Each
//! rank then sends each of its owned cells to every other rank sharing one of its corners, in
//! its own cell order. The completed part is the same whatever ghost cells the host gave: the
//! host's owned cells in its order, then the fetched cells by owner rank and the owner's order
//! (a ghost cell the host gave is replaced by its owner's copy), then any host ghost cells no
//! rank sent (a thicker layer than needed); the tagged faces likewise. So a partition given with
//! or without its ghost layer is solved bitwise the same.

use super::comm::Comm;
use super::error::{DistError, DistErrorKind};
use super::reduce::all_to_all;
use crate::geometry::CellType;
use crate::mesh::faces_in;
use crate::MeshData;
use std::collections::hash_map::Entry;
use std::collections::{HashMap, HashSet};
use std::ops::Range;

/// A rank's part with its ghost layer completed.
pub(crate) struct Completed {
    /// The host's vertices first (in its order), then the fetched ones by global id; the
    /// cells and tagged faces in the order the module's header gives.
    pub data: MeshData,
    /// Global id of each vertex of `data`.
    pub gids: Vec<u64>,
    /// Owner rank of each vertex of `data`.
    pub owners: Vec<usize>,
    /// Whether each cell of `data` is this rank's.
    pub owned_cell: Vec<bool>,
}

/// A cell by its sorted global vertex ids.
fn cell_key(corners: impl Iterator<Item = u64>) -> Vec<u64> {
    let mut k: Vec<u64> = corners.collect();
    k.sort_unstable();
    k
}

/// The part `local` (validated; `gids`, `owners` per vertex, `owned_cell` per cell) with the
/// cells other ranks own around the vertices of its owned cells (collective). The error (one
/// rank's, to be agreed) names a cell two ranks both own.
pub(crate) fn complete(
    comm: &Comm,
    local: &MeshData,
    gids: &[u64],
    owners: &[usize],
    owned_cell: &[bool],
) -> (Completed, Option<DistError>) {
    let nv = local.num_vertices();
    let mut in_owned = vec![false; nv];
    (0..local.num_cells())
        .filter(|&c| owned_cell[c])
        .for_each(|c| local.cell(c).iter().for_each(|&v| in_owned[v as usize] = true));
    let sharers = sharers(comm, gids, &in_owned);
    let outgoing = outgoing(comm.size(), local, gids, owners, owned_cell, &sharers);
    let incoming = all_to_all(comm, &outgoing);
    merge(comm.rank(), local, (gids, owners, &in_owned), owned_cell, &incoming)
}

/// For each vertex in an owned cell, the other ranks that have it in an owned cell, ascending
/// (collective: one rendezvous by global id).
fn sharers(comm: &Comm, gids: &[u64], in_owned: &[bool]) -> Vec<Vec<usize>> {
    let size = comm.size();
    let home = |g: u64| (g % size as u64) as usize;
    let mut send = vec![Vec::new(); size];
    for (&g, _) in gids.iter().zip(in_owned).filter(|(_, &o)| o) {
        send[home(g)].push(g);
    }
    let heard = all_to_all(comm, &send);
    let mut holders: HashMap<u64, Vec<usize>> = HashMap::new();
    for (rank, list) in heard.iter().enumerate() {
        list.iter().for_each(|&g| holders.entry(g).or_default().push(rank));
    }
    // Per asking rank, per global id it sent: the number of other holders, then their ranks.
    let replies: Vec<Vec<u64>> = heard
        .iter()
        .enumerate()
        .map(|(rank, list)| {
            let mut r = Vec::new();
            for g in list {
                let others = holders.get(g).map(Vec::as_slice).unwrap_or_default();
                r.push(others.len().saturating_sub(1) as u64);
                r.extend(others.iter().filter(|&&o| o != rank).map(|&o| o as u64));
            }
            r
        })
        .collect();
    let answers = all_to_all(comm, &replies);
    let mut at = vec![0usize; size];
    let mut out = vec![Vec::new(); gids.len()];
    for (v, &g) in gids.iter().enumerate().filter(|(v, _)| in_owned[*v]) {
        let (d, a) = (home(g), &answers[home(g)]);
        let n = a.get(at[d]).map_or(0, |&n| n as usize);
        let list = a.get(at[d] + 1..at[d] + 1 + n).unwrap_or_default();
        out[v] = list.iter().filter_map(|&r| usize::try_from(r).ok()).collect();
        at[d] += 1 + n;
    }
    out
}

/// What this rank sends each rank: `[vertices, cells, faces]` counts, then the vertex records
/// (global id, owner, coordinates' bits), the cell records (VTK type, region, corners' global
/// ids, for a polyhedron its faces by global ids) and the tagged face records (patch, global
/// ids), each list length-prefixed.
fn outgoing(
    size: usize,
    local: &MeshData,
    gids: &[u64],
    owners: &[usize],
    owned_cell: &[bool],
    sharers: &[Vec<usize>],
) -> Vec<Vec<u64>> {
    let faces_of = tagged_faces_of_cells(local);
    let spans = local.polyhedron_spans(local.num_vertices()).unwrap_or_default();
    let mut cells = vec![Vec::new(); size];
    let mut verts: Vec<Vec<u32>> = vec![Vec::new(); size];
    let mut faces: Vec<Vec<u32>> = vec![Vec::new(); size];
    let mut counts = vec![0u64; size];
    for c in (0..local.num_cells()).filter(|&c| owned_cell[c]) {
        let corners = local.cell(c);
        let mut dests: Vec<usize> = corners.iter().flat_map(|&v| sharers[v as usize].iter().copied()).collect();
        dests.sort_unstable();
        dests.dedup();
        for &r in dests.iter().filter(|&&r| r < size) {
            let out = &mut cells[r];
            out.push(u64::from(local.cell_types[c].vtk_id()));
            out.push(i64::from(local.regions.get(c).copied().unwrap_or(0)) as u64);
            push_list(out, corners.iter().map(|&v| gids[v as usize]));
            match spans.get(c).cloned().flatten() {
                Some(span) => {
                    let list = &local.polyhedron_faces[span];
                    out.push(u64::from(list[0]));
                    faces_in(list).for_each(|f| push_list(out, f.iter().map(|&v| gids[v as usize])));
                }
                None => out.push(0),
            }
            counts[r] += 1;
            verts[r].extend_from_slice(corners);
            faces[r].extend(faces_of.get(&c).map(Vec::as_slice).unwrap_or_default());
        }
    }
    let dim = local.dim;
    (0..size)
        .map(|r| {
            let (v, f) = (&mut verts[r], &mut faces[r]);
            v.sort_unstable();
            v.dedup();
            f.sort_unstable();
            f.dedup();
            let mut msg = vec![v.len() as u64, counts[r], f.len() as u64];
            for &x in v.iter() {
                msg.extend([gids[x as usize], owners[x as usize] as u64]);
                msg.extend(local.point(x as usize)[..dim].iter().map(|x| x.to_bits()));
            }
            msg.extend_from_slice(&cells[r]);
            for &t in f.iter() {
                msg.push(i64::from(local.face_patch[t as usize]) as u64);
                push_list(&mut msg, local.face(t as usize).iter().map(|&v| gids[v as usize]));
            }
            msg
        })
        .collect()
}

/// Appends a length and the values.
fn push_list(out: &mut Vec<u64>, values: impl ExactSizeIterator<Item = u64>) {
    out.push(values.len() as u64);
    out.extend(values);
}

/// The tagged faces on each owned or ghost cell (a face is on a cell when all its vertices are
/// the cell's).
fn tagged_faces_of_cells(local: &MeshData) -> HashMap<usize, Vec<u32>> {
    let mut cells_at: Vec<Vec<usize>> = vec![Vec::new(); local.num_vertices()];
    (0..local.num_cells()).for_each(|c| local.cell(c).iter().for_each(|&v| cells_at[v as usize].push(c)));
    let mut out: HashMap<usize, Vec<u32>> = HashMap::new();
    for f in 0..local.num_faces() {
        let face = local.face(f);
        let Some(&first) = face.first() else { continue };
        for &c in &cells_at[first as usize] {
            if face.iter().all(|v| local.cell(c).contains(v)) {
                out.entry(c).or_default().push(f as u32);
            }
        }
    }
    out
}

/// The completed part as it is built: cells and faces appended in order.
struct Part {
    data: MeshData,
    regions: Vec<i32>,
    owned: Vec<bool>,
    /// The tagged faces so far, by patch and sorted global ids.
    seen: HashSet<(i32, Vec<u64>)>,
}

impl Part {
    fn cell(&mut self, ty: CellType, corners: &[u32], region: i32, owned: bool, polyhedron: Option<&[u32]>) {
        let d = &mut self.data;
        d.cell_types.push(ty);
        d.cell_vertices.extend_from_slice(corners);
        d.cell_offsets.push(d.cell_vertices.len() as u32);
        d.polyhedron_faces.extend_from_slice(polyhedron.unwrap_or_default());
        self.regions.push(region);
        self.owned.push(owned);
    }

    /// The host's cell `c` (`spans`: where its polyhedron faces lie).
    fn host_cell(&mut self, local: &MeshData, spans: &[Option<Range<usize>>], c: usize, owned: bool) {
        let poly = spans.get(c).cloned().flatten().map(|s| &local.polyhedron_faces[s]);
        self.cell(local.cell_types[c], local.cell(c), local.regions.get(c).copied().unwrap_or(0), owned, poly);
    }

    /// A tagged face (its local vertices and their global ids), unless it is there already.
    fn face(&mut self, patch: i32, vertices: &[u32], gids: Vec<u64>) {
        if self.seen.insert((patch, cell_key(gids.into_iter()))) {
            self.data.push_face(vertices, patch);
        }
    }
}

/// The first face (in the host's order) that the host tags on a ghost cell its owner sent, with
/// a vertex in an owned cell (where the tag sets this rank's conditions), and that no rank that
/// sent a cell tags alike (another patch, or none; `owners_faces`: the fetched faces by patch
/// and sorted global ids): the ranks would hold different conditions at its vertices.
/// `ghost_owner` gives the owner of a host cell replaced by its owner's copy (None for the
/// others), `touches_owned` whether a face has a vertex in an owned cell, `host_face` a face's
/// patch, local vertices and global ids.
fn ghost_face_clash(
    me: usize,
    faces_of: &HashMap<usize, Vec<u32>>,
    on_owned: &HashSet<u32>,
    owners_faces: &HashSet<(i32, Vec<u64>)>,
    ghost_owner: impl Fn(usize) -> Option<usize>,
    touches_owned: impl Fn(usize) -> bool,
    host_face: impl Fn(usize) -> (i32, Vec<u32>, Vec<u64>),
) -> Option<DistError> {
    let mut on_fetched: Vec<(u32, usize)> = faces_of
        .iter()
        .filter_map(|(&c, faces)| ghost_owner(c).map(|owner| (faces, owner)))
        .flat_map(|(faces, owner)| faces.iter().map(move |&f| (f, owner)))
        .filter(|(f, _)| !on_owned.contains(f) && touches_owned(*f as usize))
        .collect();
    on_fetched.sort_unstable();
    on_fetched.into_iter().find_map(|(f, owner)| {
        let (patch, _, g) = host_face(f as usize);
        let key = cell_key(g.iter().copied());
        (!owners_faces.contains(&(patch, key))).then(|| {
            let msg = format!(
                "the face of global ids {g:?} is tagged with patch {patch} on rank {me}, on a ghost cell rank {owner} \
                 owns, which tags it otherwise or not at all"
            );
            DistError::new(me, DistErrorKind::Inconsistent, msg)
        })
    })
}

/// Reads the lists of `msg` from `at`.
struct Reader<'a> {
    msg: &'a [u64],
    at: usize,
}

impl Reader<'_> {
    /// True once every value is read (a count beyond the message reads nothing more).
    fn done(&self) -> bool {
        self.at >= self.msg.len()
    }

    fn one(&mut self) -> u64 {
        let x = self.msg.get(self.at).copied().unwrap_or(0);
        self.at += 1;
        x
    }

    fn list(&mut self) -> &[u64] {
        let n = self.one() as usize;
        let start = self.at.min(self.msg.len());
        self.at = (self.at + n).min(self.msg.len());
        &self.msg[start..self.at]
    }
}

/// A fetched cell: its owner rank, VTK type, region, corners and (polyhedra) faces by global id.
struct Fetched {
    owner: usize,
    ty: CellType,
    region: i32,
    corners: Vec<u64>,
    faces: Vec<Vec<u64>>,
}

/// The completed part from the host's and the fetched cells (see the module's header for the
/// order; per host vertex its global id, owner and whether it lies in an owned cell). A fetched
/// cell this rank owns too is an error, and so is a face tagged on a ghost cell that no owner
/// tags alike.
fn merge(
    me: usize,
    local: &MeshData,
    (gids, owners, in_owned): (&[u64], &[usize], &[bool]),
    owned_cell: &[bool],
    incoming: &[Vec<u64>],
) -> (Completed, Option<DistError>) {
    let dim = local.dim;
    let mut index: HashMap<u64, u32> = gids.iter().zip(0..).map(|(&g, i)| (g, i)).collect();
    let mut extra: Vec<(u64, usize, Vec<f64>)> = Vec::new();
    let mut fetched: Vec<Fetched> = Vec::new();
    let mut fetched_faces: Vec<(i32, Vec<u64>)> = Vec::new();
    for (owner, msg) in incoming.iter().enumerate() {
        let mut r = Reader { msg, at: 0 };
        let (nv, nc, nf) = (r.one(), r.one(), r.one());
        for _ in 0..nv {
            if r.done() {
                break;
            }
            let (g, o) = (r.one(), r.one());
            let x: Vec<f64> = (0..dim).map(|_| f64::from_bits(r.one())).collect();
            if let Entry::Vacant(e) = index.entry(g) {
                e.insert(u32::MAX);
                extra.push((g, usize::try_from(o).unwrap_or(usize::MAX), x));
            }
        }
        for _ in 0..nc {
            if r.done() {
                break;
            }
            let ty = CellType::general_from_vtk(r.one() as i64).unwrap_or(CellType::Polyhedron);
            let region = r.one() as i64 as i32;
            let corners = r.list().to_vec();
            let n = r.one();
            let faces = (0..n).map_while(|_| (!r.done()).then(|| r.list().to_vec())).collect();
            fetched.push(Fetched { owner, ty, region, corners, faces });
        }
        for _ in 0..nf {
            if r.done() {
                break;
            }
            let patch = r.one() as i64 as i32;
            fetched_faces.push((patch, r.list().to_vec()));
        }
    }
    extra.sort_by_key(|e| e.0);
    let n_host = gids.len() as u32;
    for (i, e) in extra.iter().enumerate() {
        index.insert(e.0, n_host + i as u32);
    }
    let at = |g: &u64| index.get(g).copied().unwrap_or(0);
    let mut data = MeshData::new(dim);
    data.coords = local.coords.clone();
    extra.iter().for_each(|e| data.coords.extend_from_slice(&e.2));
    let mut all_gids = gids.to_vec();
    all_gids.extend(extra.iter().map(|e| e.0));
    let mut all_owners = owners.to_vec();
    all_owners.extend(extra.iter().map(|e| e.1));

    let host_key = |c: usize| cell_key(local.cell(c).iter().map(|&v| gids[v as usize]));
    let owned_keys: HashSet<Vec<u64>> = (0..local.num_cells()).filter(|&c| owned_cell[c]).map(host_key).collect();
    let mut error = None;
    let spans = local.polyhedron_spans(local.num_vertices()).unwrap_or_default();
    let mut part = Part { data, regions: Vec::new(), owned: Vec::new(), seen: HashSet::new() };
    (0..local.num_cells()).filter(|&c| owned_cell[c]).for_each(|c| part.host_cell(local, &spans, c, true));
    let mut fetched_keys = HashMap::with_capacity(fetched.len());
    for cell in &fetched {
        let key = cell_key(cell.corners.iter().copied());
        if owned_keys.contains(&key) && error.is_none() {
            let msg = format!("the cell of global ids {key:?} is owned by rank {me} and by another rank");
            error = Some(DistError::new(me, DistErrorKind::Inconsistent, msg));
        }
        fetched_keys.insert(key, cell.owner);
        let poly: Option<Vec<u32>> = (cell.ty == CellType::Polyhedron).then(|| {
            let mut list = vec![cell.faces.len() as u32];
            for f in &cell.faces {
                list.push(f.len() as u32);
                list.extend(f.iter().map(at));
            }
            list
        });
        let corners: Vec<u32> = cell.corners.iter().map(at).collect();
        part.cell(cell.ty, &corners, cell.region, false, poly.as_deref());
    }
    (0..local.num_cells())
        .filter(|&c| !owned_cell[c] && !fetched_keys.contains_key(&host_key(c)))
        .for_each(|c| part.host_cell(local, &spans, c, false));

    // Tagged faces: the host's on its owned cells, the fetched ones, then the host's others,
    // each face (by its global ids and patch) once.
    let faces_of = tagged_faces_of_cells(local);
    let on_owned: HashSet<u32> =
        faces_of.iter().filter(|(c, _)| owned_cell[**c]).flat_map(|(_, f)| f.iter().copied()).collect();
    let host_face = |f: usize| {
        let face = local.face(f);
        (local.face_patch[f], face.to_vec(), face.iter().map(|&v| gids[v as usize]).collect::<Vec<u64>>())
    };
    for f in (0..local.num_faces()).filter(|&f| on_owned.contains(&(f as u32))) {
        let (p, v, g) = host_face(f);
        part.face(p, &v, g);
    }
    for (p, g) in &fetched_faces {
        let v: Vec<u32> = g.iter().map(at).collect();
        part.face(*p, &v, g.clone());
    }
    for f in (0..local.num_faces()).filter(|&f| !on_owned.contains(&(f as u32))) {
        let (p, v, g) = host_face(f);
        part.face(p, &v, g);
    }
    if error.is_none() {
        let owners_faces = fetched_faces.iter().map(|(p, g)| (*p, cell_key(g.iter().copied()))).collect();
        let ghost_owner = |c: usize| (!owned_cell[c]).then(|| host_key(c)).and_then(|k| fetched_keys.get(&k).copied());
        let touches_owned = |f: usize| local.face(f).iter().any(|&v| in_owned[v as usize]);
        error = ghost_face_clash(me, &faces_of, &on_owned, &owners_faces, ghost_owner, touches_owned, host_face);
    }
    let Part { mut data, regions, owned, .. } = part;
    if regions.iter().any(|&r| r != 0) || !local.regions.is_empty() {
        data.regions = regions;
    }
    (Completed { data, gids: all_gids, owners: all_owners, owned_cell: owned }, error)
}
