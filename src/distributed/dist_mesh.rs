//! A distributed mesh from what a host has on each rank: its local vertices with global ids,
//! its cells (owned ones and ghost ones), its tagged faces, its cell regions. Made collectively;
//! every check of the serial mesh runs on each rank's part, and the cross-rank checks follow.

use super::agreement::agree;
use super::comm::Comm;
use super::error::{DistError, DistErrorKind};
use super::ghosts;
use super::halo::HaloLayout;
use super::ownership;
use super::reduce::{all_to_all, gather};
use crate::{FaceMeshData, Mesh, MeshData, MeshError};
use mpi::topology::Communicator;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

/// One rank's part of a mesh spread over the ranks of a communicator, with who owns each vertex,
/// the global numbering and the halo exchange lists.
///
/// The rank's local part is the host's cells with the ghost layer the library completes: every
/// cell another rank owns around the vertices of the rank's owned cells, fetched from its owner
/// with the vertices the host lacks. Its vertices are kept in layout order: the vertices it owns
/// first (by global id), then the others grouped by owner rank (by global id within a group).
/// The methods that take or return per-vertex arrays use the host's vertices in the host's
/// order, the one given to [`new`](Self::new); the fetched vertices are the library's own.
#[derive(Clone, Debug)]
pub struct DistributedMesh {
    comm: Arc<Comm>,
    /// The local part in layout order, validated.
    mesh: Mesh,
    /// Layout position → the host's local vertex index (from `host_vertices` on: the vertices
    /// the library fetched with the ghost layer, in global id order).
    host_index: Vec<u32>,
    /// The vertices the host gave.
    host_vertices: usize,
    /// Whether each cell of the local part is this rank's (not a ghost).
    owned_cells: Vec<bool>,
    /// Global id of each vertex, layout order.
    global_ids: Vec<u64>,
    /// Owner rank of each vertex, layout order.
    owners: Vec<usize>,
    /// Global number of each vertex, layout order (owned vertices numbered by this rank,
    /// halo vertices by their owners).
    global_numbers: Vec<u64>,
    /// Vertices over all ranks.
    global_vertices: u64,
    halo: Arc<HaloLayout>,
}

impl DistributedMesh {
    /// Builds this rank's part of a distributed mesh (collective over `comm`: every rank calls it,
    /// and every rank returns the same error if any rank's input is wrong).
    ///
    /// - `local`: the rank's vertices (any order, local 0-based indices), its cells (its owned
    ///   ones, and any ghost cells), their regions and the tagged faces on them, as for
    ///   [`Mesh::from_data`].
    /// - `global_ids`: the global id of each local vertex (the same id for the same vertex on
    ///   every rank that has it, with the same coordinates to the bit).
    /// - `ghost_cells`: true for a cell another rank owns (empty: every cell is owned). Each
    ///   cell is owned by exactly one rank.
    ///
    /// The library completes the ghost layer: every cell another rank owns around a vertex of
    /// this rank's owned cells is fetched from its owner (with its vertices, region and tagged
    /// faces), and a ghost cell the host gave is replaced by its owner's copy, so a partition
    /// given with or without ghost cells is solved bitwise the same. A vertex held by several
    /// ranks is owned by the lowest rank that has it in an owned cell. The library duplicates
    /// `comm` for its own messages.
    pub fn new<C: Communicator>(
        comm: &C,
        local: &MeshData,
        global_ids: &[u64],
        ghost_cells: &[bool],
    ) -> Result<DistributedMesh, DistError> {
        DistributedMesh::build(Arc::new(Comm::duplicate(comm)), local, global_ids, ghost_cells)
    }

    /// Builds this rank's part of a distributed mesh from its owned cells given by their faces,
    /// as a finite-volume code stores its partition (collective over `comm`): see
    /// [`FaceMeshData::to_part_data`] for the faces shared with other ranks' cells, and
    /// [`new`](Self::new) for the global ids and the ghost layer, which the library fetches.
    pub fn from_faces<C: Communicator>(
        comm: &C,
        faces: &FaceMeshData,
        global_ids: &[u64],
    ) -> Result<DistributedMesh, DistError> {
        let comm = Arc::new(Comm::duplicate(comm));
        let me = comm.rank();
        let data = faces.to_part_data().map_err(|e| DistError::new(me, DistErrorKind::LocalMesh, e.to_string()));
        let data = agree(&comm, data)?;
        DistributedMesh::build(comm, &data, global_ids, &[])
    }

    /// [`new`](Self::new) on the library's communicator.
    fn build(
        comm: Arc<Comm>,
        local: &MeshData,
        global_ids: &[u64],
        ghost_cells: &[bool],
    ) -> Result<DistributedMesh, DistError> {
        let me = comm.rank();
        let checked = agree(&comm, local_checks(me, local, global_ids, ghost_cells));
        let flipped = checked?;
        agree(&comm, same_orientation(&comm, flipped))?;
        let nv = local.num_vertices();
        let owned_cell: Vec<bool> = (0..local.num_cells()).map(|c| ghost_cells.get(c) != Some(&true)).collect();
        let mut in_owned_cell = vec![false; nv];
        for c in (0..local.num_cells()).filter(|&c| owned_cell[c]) {
            local.cell(c).iter().for_each(|&v| in_owned_cell[v as usize] = true);
        }
        let (owners, found) = ownership::owners(&comm, local.dim, global_ids, &local.coords, &in_owned_cell);
        agree(&comm, found.map_or(Ok(()), Err))?;
        let (part, clash) = ghosts::complete(&comm, local, global_ids, &owners, &owned_cell);
        agree(&comm, clash.map_or(Ok(()), Err))?;
        let host_index = layout_order(me, &part.gids, &part.owners);
        let (halo, found) = halo_lists(&comm, &host_index, &part.gids, &part.owners);
        agree(&comm, found.map_or(Ok(()), Err))?;
        let owned = part.owners.iter().filter(|&&o| o == me).count();
        let (first, global_vertices) = ownership::first_global_number(&comm, owned);
        let global_ids: Vec<u64> = host_index.iter().map(|&v| part.gids[v as usize]).collect();
        let owners: Vec<usize> = host_index.iter().map(|&v| part.owners[v as usize]).collect();
        let mut global_numbers: Vec<u64> = (0..host_index.len() as u64).map(|i| first + i).collect();
        halo.refresh(&mut global_numbers);
        // The completed part in layout order, validated again (the host's cells passed above;
        // the fetched ones passed on their owners).
        let layout = reordered(&part.data, &host_index);
        let mesh = Mesh::from_data(&layout).map_err(|e| local_error(me, &e, &layout, &global_ids));
        let mesh = agree(&comm, mesh);
        Ok(DistributedMesh {
            comm,
            mesh: mesh?,
            host_index,
            host_vertices: nv,
            owned_cells: part.owned_cell,
            global_ids,
            owners,
            global_numbers,
            global_vertices,
            halo: Arc::new(halo),
        })
    }

    /// A mesh made from this one's completed part with some vertices replaced by copies
    /// (`distributed::interfaces`): `part` (the cells in this part's order, `ghost` the cells
    /// this rank does not own), its vertices' global ids `gids` and the layout position of this
    /// mesh each comes from (`origin`). Its host vertices are this mesh's: a copy takes its
    /// original's host values. Returns the mesh and the layout position of this mesh each of its
    /// vertices comes from (`u32::MAX` for a vertex it fetched itself). Collective.
    pub(crate) fn with_vertices_split(
        &self,
        part: &MeshData,
        gids: &[u64],
        ghost: &[bool],
        origin: &[u32],
    ) -> Result<(DistributedMesh, Vec<u32>), DistError> {
        let mut split = DistributedMesh::build(self.comm.clone(), part, gids, ghost)?;
        let from: Vec<u32> =
            split.host_index.iter().map(|&i| origin.get(i as usize).copied().unwrap_or(u32::MAX)).collect();
        split.host_index = from.iter().map(|&p| self.host_index.get(p as usize).copied().unwrap_or(u32::MAX)).collect();
        split.host_vertices = self.host_vertices;
        Ok((split, from))
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.comm.rank()
    }

    /// The number of ranks.
    pub fn num_ranks(&self) -> usize {
        self.comm.size()
    }

    /// The space dimension.
    pub fn dim(&self) -> usize {
        self.mesh.dim()
    }

    /// The vertices the host gave this rank (owned and not): the length of the per-vertex
    /// arrays of the distributed calls.
    pub fn num_local_vertices(&self) -> usize {
        self.host_vertices
    }

    /// The vertices of this rank's part: the host's and those the library fetched with the
    /// ghost layer.
    pub fn num_part_vertices(&self) -> usize {
        self.host_index.len()
    }

    /// The vertices this rank owns.
    pub fn num_owned_vertices(&self) -> usize {
        use crate::multigrid::layout::Layout;
        self.halo.owned()
    }

    /// The vertices of the whole mesh.
    pub fn num_global_vertices(&self) -> u64 {
        self.global_vertices
    }

    /// The global id of each local vertex, in the host's order (as given).
    pub fn global_ids(&self) -> Vec<u64> {
        self.to_host_order(&self.global_ids, 1)
    }

    /// The owner rank of each local vertex, in the host's order.
    pub fn owner_ranks(&self) -> Vec<usize> {
        self.to_host_order(&self.owners, 1)
    }

    /// The global number of each local vertex, in the host's order: the owned vertices of rank 0
    /// first, then rank 1's, …, each rank's in global id order, numbered from 0.
    pub fn global_numbers(&self) -> Vec<u64> {
        self.to_host_order(&self.global_numbers, 1)
    }

    /// The neighbour ranks this rank exchanges halo values with.
    pub fn neighbour_ranks(&self) -> Vec<usize> {
        self.halo.neighbours()
    }

    /// The values this rank sends to its neighbours per halo exchange of one vector.
    pub fn halo_values_sent(&self) -> usize {
        self.halo.sent_per_exchange()
    }

    /// The global ids of the local vertices in layout order.
    pub(crate) fn layout_global_ids(&self) -> &[u64] {
        &self.global_ids
    }

    /// The local part in layout order.
    pub(crate) fn local_mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Whether each local cell is owned (not a ghost).
    pub(crate) fn owned_cells(&self) -> &[bool] {
        &self.owned_cells
    }

    /// The halo layout of the local vertices.
    pub(crate) fn halo(&self) -> &Arc<HaloLayout> {
        &self.halo
    }

    /// `values` (`per` per vertex, layout order) on the host's vertices, in the host's order (a
    /// vertex split at an interface has several copies, all prescribed alike: the last counts).
    pub(crate) fn to_host_order<T: Copy + Default>(&self, values: &[T], per: usize) -> Vec<T> {
        let mut out = vec![T::default(); self.host_vertices * per];
        for (i, &h) in self.host_index.iter().enumerate().filter(|(_, &h)| (h as usize) < self.host_vertices) {
            out[h as usize * per..(h as usize + 1) * per].copy_from_slice(&values[i * per..(i + 1) * per]);
        }
        out
    }

    /// `values` (`per` per host vertex, the host's order) in layout order; the fetched
    /// vertices, which this rank never owns, get `T::default()`.
    pub(crate) fn to_layout_order<T: Copy + Default>(&self, values: &[T], per: usize) -> Vec<T> {
        let mut out = vec![T::default(); self.host_index.len() * per];
        for (i, &h) in self.host_index.iter().enumerate().filter(|(_, &h)| (h as usize) < self.host_vertices) {
            out[i * per..(i + 1) * per].copy_from_slice(&values[h as usize * per..(h as usize + 1) * per]);
        }
        out
    }

    /// As [`to_layout_order`](Self::to_layout_order), with every halo vertex (the fetched ones
    /// included) given its owner's values (collective).
    pub(crate) fn to_layout_order_exchanged(&self, values: &[f64], per: usize) -> Vec<f64> {
        let mut out = self.to_layout_order(values, per);
        let n = self.host_index.len();
        let mut one = vec![0.0; n];
        for c in 0..per {
            (0..n).for_each(|v| one[v] = out[v * per + c]);
            self.halo.refresh(&mut one);
            (0..n).for_each(|v| out[v * per + c] = one[v]);
        }
        out
    }
}

/// Everything one rank can check alone: sizes, global ids given twice, and every serial mesh
/// check on its part (named by global ids). Returns whether the serial validation flipped the
/// part's orientation (a part given in the negative orientation).
fn local_checks(me: usize, local: &MeshData, gids: &[u64], ghost: &[bool]) -> Result<bool, DistError> {
    let input = |msg: String| Err(DistError::new(me, DistErrorKind::Input, msg));
    let nv = local.num_vertices();
    if gids.len() != nv {
        return input(format!("{} global ids given for {nv} vertices", gids.len()));
    }
    if !ghost.is_empty() && ghost.len() != local.num_cells() {
        return input(format!("{} ghost flags given for {} cells", ghost.len(), local.num_cells()));
    }
    let mut sorted: Vec<(u64, usize)> = gids.iter().copied().zip(0..).collect();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0].0 == w[1].0) {
        let msg = format!("global id {} is given to two local vertices, {} and {}", w[0].0, w[0].1, w[1].1);
        return Err(DistError::new(me, DistErrorKind::Inconsistent, msg));
    }
    if ghost.len() == local.num_cells() && ghost.iter().all(|&g| g) {
        return input("every cell is a ghost cell: a rank needs an owned cell".into());
    }
    let mesh = Mesh::from_data(local).map_err(|e| local_error(me, &e, local, gids))?;
    Ok((0..local.num_cells()).any(|c| mesh.cell(c) != local.cell(c)))
}

/// The serial validation's error on rank `me`, with the global ids of the vertex, of the
/// cell's corners or of the face's vertices it names (`local`'s cells are checked by then for
/// the cell variants named).
fn local_error(me: usize, e: &MeshError, local: &MeshData, gids: &[u64]) -> DistError {
    let vertex = |v: usize| gids.get(v).map_or(String::new(), |g| format!(" (global id {g})"));
    let cell = |c: usize| {
        let corners: Option<Vec<u64>> = local.cell(c).iter().map(|&v| gids.get(v as usize).copied()).collect();
        corners.map_or(String::new(), |g| format!(" (corners: global ids {g:?})"))
    };
    let face = |f: &[u32]| {
        let ids: Option<Vec<u64>> = f.iter().map(|&v| gids.get(v as usize).copied()).collect();
        ids.map_or(String::new(), |g| format!(" (face: global ids {g:?})"))
    };
    let item = match e {
        MeshError::NonFiniteCoordinate { vertex: v, .. } | MeshError::UnusedVertex { vertex: v } => vertex(*v),
        MeshError::RepeatedVertex { vertex: v, .. } => vertex(*v),
        MeshError::DegenerateCell { cell: c, .. }
        | MeshError::InvertedCorner { cell: c, .. }
        | MeshError::MeasureOutOfRange { cell: c, .. }
        | MeshError::InconsistentOrientation { cell: c, .. }
        | MeshError::RepeatedCell { first: c, .. } => cell(*c),
        MeshError::Overlap { face: f, .. }
        | MeshError::NonManifoldFace { face: f, .. }
        | MeshError::TaggedFaceNotAFace { vertices: f, .. }
        | MeshError::TaggedFaceTwice { vertices: f, .. } => face(f),
        _ => String::new(),
    };
    DistError::new(me, DistErrorKind::LocalMesh, format!("{e}{item}"))
}

/// Every rank's part must keep its given orientation or every rank's be flipped: parts in
/// opposite orientations make a tangled mesh together. Blames the lowest rank that differs
/// from rank 0.
fn same_orientation(comm: &Comm, flipped: bool) -> Result<(), DistError> {
    let all = gather(comm, &[flipped as u8]);
    match all.iter().position(|&f| f != all[0]) {
        None => Ok(()),
        Some(rank) => Err(DistError::new(
            rank,
            DistErrorKind::Inconsistent,
            format!("the cells of rank {rank} are oriented opposite to rank 0's: the parts fold over each other"),
        )),
    }
}

/// The layout order of the local vertices (as host indices): owned ones by global id, then the
/// others by (owner rank, global id).
fn layout_order(me: usize, gids: &[u64], owners: &[usize]) -> Vec<u32> {
    let mut order: Vec<u32> = (0..gids.len() as u32).collect();
    order.sort_unstable_by_key(|&v| {
        let o = owners[v as usize];
        (o != me, o, gids[v as usize])
    });
    order
}

/// The halo exchange lists of the layout `order` (collective): each rank asks each owner for its
/// halo vertices by global id; the owner finds them among its owned vertices.
pub(super) fn halo_lists(
    comm: &Arc<Comm>,
    order: &[u32],
    gids: &[u64],
    owners: &[usize],
) -> (HaloLayout, Option<DistError>) {
    let me = comm.rank();
    let owned = order.iter().take_while(|&&v| owners[v as usize] == me).count();
    let mut asks = vec![Vec::new(); comm.size()];
    let mut recvs: Vec<(usize, Range<usize>)> = Vec::new();
    for (i, &v) in order.iter().enumerate().skip(owned) {
        let o = owners[v as usize];
        asks[o].push(gids[v as usize]);
        match recvs.last_mut() {
            Some((r, range)) if *r == o => range.end = i + 1,
            _ => recvs.push((o, i..i + 1)),
        }
    }
    let asked = all_to_all(comm, &asks);
    let position: HashMap<u64, u32> = order[..owned].iter().zip(0..).map(|(&v, i)| (gids[v as usize], i)).collect();
    let mut error = None;
    let mut sends = Vec::new();
    for (rank, list) in asked.iter().enumerate().filter(|(_, l)| !l.is_empty()) {
        let idx: Vec<u32> = list
            .iter()
            .filter_map(|g| {
                let p = position.get(g).copied();
                if p.is_none() {
                    let msg = format!(
                        "rank {rank} takes rank {me} for the owner of global id {g}, which rank {me} does not own"
                    );
                    error.get_or_insert(DistError::new(rank, DistErrorKind::Inconsistent, msg));
                }
                p
            })
            .collect();
        sends.push((rank, idx));
    }
    (HaloLayout::new(comm.clone(), owned, order.len(), sends, recvs), error)
}

/// `local` with its vertices in the layout `order` (host indices by layout position).
fn reordered(local: &MeshData, order: &[u32]) -> MeshData {
    let dim = local.dim;
    let mut at = vec![0u32; order.len()];
    order.iter().enumerate().for_each(|(i, &v)| at[v as usize] = i as u32);
    let mut d = local.clone();
    d.coords = order.iter().flat_map(|&v| local.point(v as usize)[..dim].iter().copied()).collect();
    d.cell_vertices.iter_mut().for_each(|v| *v = at[*v as usize]);
    d.face_vertices.iter_mut().for_each(|v| *v = at[*v as usize]);
    // The polyhedra's faces: per polyhedron its face count, then per face its length and
    // vertices; only the vertices are renumbered.
    let s = &mut d.polyhedron_faces;
    let mut i = 0;
    while i < s.len() {
        let faces = s[i] as usize;
        i += 1;
        for _ in 0..faces {
            let len = s.get(i).map_or(0, |&n| n as usize);
            let end = (i + 1 + len).min(s.len());
            s[i + 1..end].iter_mut().for_each(|v| *v = at[*v as usize]);
            i = end;
        }
    }
    d
}
