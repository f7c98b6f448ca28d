//! Split interfaces (variant A, docs/DESIGN.md §4) across ranks: the vertices of a split
//! interface get one unknown per region in one process (`bc::Dofs`); across ranks each such
//! vertex becomes one vertex per region around it, a copy with a global id of its own, and the
//! rank's part is rebuilt with the cells of each region on their region's copies. The solver
//! then works on the split mesh as on any other: each copy has its own row, owner and halo
//! entries, and the system is the serial one with its split unknowns.
//!
//! Every rank decides alike which vertices are split and what their copies are called: the
//! vertices of the split patches' interior faces, and the (vertex, region) pairs of the owned
//! cells at them, are gathered from every rank (interface sized, once per solver). The copies,
//! sorted by (global id, region), are numbered after the largest global id of the mesh, so the
//! copies' ids depend on the mesh alone. A copy's owner is decided as any vertex's (the lowest
//! rank with it in an owned cell); where periodic links tie copies, the class takes the owner
//! of the original vertex.
//!
//! A copy's flags are its original vertex's, made by that vertex's owner from every patch face
//! at it on both sides (as one process gives every unknown of a split vertex the flags of the
//! vertex), and each copy takes the host's values of its original vertex.

use super::agreement::agree;
use super::dist_mesh::DistributedMesh;
use super::error::{DistError, DistErrorKind};
use super::reduce::gather_varcount;
use super::ties::Linked;
use crate::multigrid::layout::Layout;
use crate::{BoundaryConditions, CellType, MeshData};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// A distributed mesh with its split interfaces' vertices split per region.
pub(crate) struct Split {
    /// The split mesh; its host vertices are the unsplit mesh's.
    pub(crate) mesh: DistributedMesh,
    /// The unsplit mesh's layout position of each vertex of the split mesh's layout
    /// (`u32::MAX` for vertices the split mesh fetched itself).
    origin: Vec<u32>,
    /// The global id of every copy over all ranks, by (original global id, region).
    copies: BTreeMap<(u64, i32), u64>,
}

/// The mesh `dm` with the vertices of `bcs`'s split interfaces split per region, or None
/// without split interfaces (collective; the error is every rank's).
pub(crate) fn split(dm: &DistributedMesh, bcs: &BoundaryConditions) -> Result<Option<Split>, DistError> {
    let patches = bcs.split_patches();
    if patches.is_empty() {
        return Ok(None);
    }
    let me = dm.rank();
    let comm = dm.halo().comm();
    let local = dm.local_mesh();
    let gids = dm.layout_global_ids();
    let dim = local.dim();
    let prescribed =
        bcs.check_split_prescribed(dim).map_err(|e| DistError::new(me, DistErrorKind::Input, e.to_string()));
    agree(comm, prescribed)?;
    // The split vertices: those of the split patches' interior faces (a face between two
    // cells is interior on the part of every rank owning one of them), with each patch's count.
    let mut mine: Vec<u64> = Vec::new();
    let mut faces_of = vec![0.0; patches.len()];
    for e in local.patch_faces().filter(|e| e.interior) {
        if let Some(k) = patches.iter().position(|&p| p == e.patch) {
            faces_of[k] += 1.0;
            mine.extend(e.vertices.iter().map(|&v| gids[v as usize]));
        }
    }
    let faces_of = super::reduce::sum_in_rank_order(comm, &faces_of);
    if let Some(k) = faces_of.iter().position(|&n| n == 0.0) {
        let msg = format!("interface patch {} has no interior face between two cells on any rank", patches[k]);
        return Err(DistError::new(0, DistErrorKind::Input, msg));
    }
    let split_ids: BTreeSet<u64> = gather_varcount(comm, &mine).into_iter().flatten().collect();
    let is_split: Vec<bool> = gids.iter().map(|g| split_ids.contains(g)).collect();
    // The copies: (global id, region) of the owned cells' corners at split vertices.
    let owned_cells = dm.owned_cells();
    let mut pairs: Vec<u64> = Vec::new();
    for c in (0..local.num_cells()).filter(|&c| owned_cells[c]) {
        let r = local.regions()[c];
        for &v in local.cell(c).iter().filter(|&&v| is_split[v as usize]) {
            pairs.extend([gids[v as usize], region_key(r)]);
        }
    }
    let all: BTreeSet<(u64, i32)> = gather_varcount(comm, &pairs)
        .iter()
        .flat_map(|l| l.chunks_exact(2).map(|p| (p[0], region_of_key(p[1]))))
        .collect();
    let largest = gather_varcount(comm, &[gids.iter().copied().max().unwrap_or(0)]).into_iter().flatten().max();
    let first = largest.and_then(|m| m.checked_add(1)).filter(|f| f.checked_add(all.len() as u64).is_some());
    let first = agree(
        comm,
        first.ok_or_else(|| {
            let msg = "the global ids leave no room for the split interface's copies (ids up to u64::MAX)";
            DistError::new(0, DistErrorKind::Input, msg)
        }),
    )?;
    let copies: BTreeMap<(u64, i32), u64> = all.into_iter().zip(first..).collect();
    let (data, split_gids, origin_of_data) = split_part(dm, &is_split, &copies);
    let ghost: Vec<bool> = owned_cells.iter().map(|o| !o).collect();
    let (mesh, origin) = dm.with_vertices_split(&data, &split_gids, &ghost, &origin_of_data)?;
    Ok(Some(Split { mesh, origin, copies }))
}

/// A region as an unsigned key that sorts as the region does.
fn region_key(r: i32) -> u64 {
    (i64::from(r) - i64::from(i32::MIN)) as u64
}

fn region_of_key(k: u64) -> i32 {
    (k as i64 + i64::from(i32::MIN)) as i32
}

/// The rank's part of `dm` with each split vertex replaced, in the cells of each region, by
/// that region's copy: the mesh (unsplit vertices first in layout order, then the copies by
/// (position, region)), the global ids of its vertices and the layout position each comes from.
/// The tagged faces at split vertices are given once per side, each on its cell's copies.
fn split_part(
    dm: &DistributedMesh,
    is_split: &[bool],
    copies: &BTreeMap<(u64, i32), u64>,
) -> (MeshData, Vec<u64>, Vec<u32>) {
    let local = dm.local_mesh();
    let gids = dm.layout_global_ids();
    let regions = local.regions();
    let nv = local.num_vertices();
    let mut index = vec![u32::MAX; nv];
    let mut origin: Vec<u32> = Vec::with_capacity(nv);
    for v in (0..nv).filter(|&v| !is_split[v]) {
        index[v] = origin.len() as u32;
        origin.push(v as u32);
    }
    // The copies the part uses, by (position, region).
    let mut used: BTreeMap<(u32, i32), u32> = BTreeMap::new();
    for (c, &r) in regions.iter().enumerate() {
        for &v in local.cell(c).iter().filter(|&&v| is_split[v as usize]) {
            used.insert((v, r), 0);
        }
    }
    for (key, at) in used.iter_mut() {
        *at = origin.len() as u32;
        origin.push(key.0);
    }
    let at = |v: u32, r: i32| if is_split[v as usize] { used[&(v, r)] } else { index[v as usize] };
    let mut split_gids: Vec<u64> = origin.iter().map(|&v| gids[v as usize]).collect();
    for (&(v, r), &i) in &used {
        // Every copy a part uses is some rank's owned cell's, so it was gathered.
        split_gids[i as usize] = copies.get(&(gids[v as usize], r)).copied().unwrap_or(u64::MAX);
    }
    let mut d = MeshData::new(local.dim());
    d.coords = origin.iter().flat_map(|&v| local.point(v as usize).to_vec()).collect();
    for (c, &r) in regions.iter().enumerate() {
        let t: Vec<u32> = local.cell(c).iter().map(|&v| at(v, r)).collect();
        d.push_cell(local.cell_type(c), &t, r);
    }
    // The polyhedra's faces, each on its cell's copies.
    for c in (0..local.num_cells()).filter(|&c| local.cell_type(c) == CellType::Polyhedron) {
        d.polyhedron_faces.push(local.polyhedron_faces(c).len() as u32);
        for f in local.polyhedron_faces(c) {
            d.polyhedron_faces.push(f.len() as u32);
            d.polyhedron_faces.extend(f.iter().map(|&v| at(v, regions[c])));
        }
    }
    // The tagged faces, once per region of the cells holding them.
    let mut cells_at: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for c in 0..local.num_cells() {
        local.cell(c).iter().for_each(|&v| cells_at[v as usize].push(c as u32));
    }
    let mut seen: HashMap<(Vec<u32>, i32), ()> = HashMap::new();
    for e in local.patch_faces() {
        let holders = cells_at[e.vertices[0] as usize]
            .iter()
            .filter(|&&c| e.vertices.iter().all(|v| local.cell(c as usize).contains(v)));
        for &c in holders {
            let t: Vec<u32> = e.vertices.iter().map(|&v| at(v, regions[c as usize])).collect();
            let mut key = t.clone();
            key.sort_unstable();
            if seen.insert((key, e.patch), ()).is_none() {
                d.push_face(&t, e.patch);
            }
        }
    }
    (d, split_gids, origin)
}

impl Split {
    /// The flags of every component of `base` (per vertex of the unsplit mesh `dm`, layout
    /// order) on the split mesh: each copy its original vertex's owner's (collective).
    pub(crate) fn flags(&self, dm: &DistributedMesh, base: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
        let (halo, owned) = (self.mesh.halo(), self.mesh.halo().owned());
        base.into_iter()
            .map(|mut f| {
                dm.halo().refresh(&mut f);
                let mut out: Vec<u8> =
                    (0..self.origin.len()).map(|j| if j < owned { f[self.origin[j] as usize] } else { 0 }).collect();
                halo.refresh(&mut out);
                out
            })
            .collect()
    }

    /// The links' pairs of the unsplit mesh on the split one: a pair of split vertices
    /// becomes one pair per region both have a copy in, each copy's class owned by its
    /// original's owner. Error: a linked vertex split and its partner not.
    pub(crate) fn linked(&self, me: usize, linked: Linked) -> Result<Linked, DistError> {
        let Linked { pairs, mut owner_of } = linked;
        let copies_of = |g: u64| self.copies.range((g, i32::MIN)..=(g, i32::MAX)).map(|(&(_, r), &id)| (r, id));
        let mut out = Vec::with_capacity(pairs.len());
        for [a, b] in pairs {
            let (ca, cb): (BTreeMap<i32, u64>, BTreeMap<i32, u64>) = (copies_of(a).collect(), copies_of(b).collect());
            if ca.is_empty() && cb.is_empty() {
                out.push([a, b]);
                continue;
            }
            if ca.is_empty() || cb.is_empty() {
                let (s, u) = if ca.is_empty() { (b, a) } else { (a, b) };
                let msg = format!(
                    "global id {s} is on a split interface and linked to global id {u}, which is not: link the \
                     interface's ends to each other"
                );
                return Err(DistError::new(me, DistErrorKind::Input, msg));
            }
            for (r, &x) in &ca {
                if let Some(&y) = cb.get(r) {
                    out.push([x, y]);
                }
            }
        }
        for (&(g, _), &id) in &self.copies {
            if let Some(&o) = owner_of.get(&g) {
                owner_of.insert(id, o);
            }
        }
        Ok(Linked { pairs: out, owner_of })
    }
}
