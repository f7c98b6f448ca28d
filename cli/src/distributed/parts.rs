//! Each rank's part of a mesh partitioned by cells, as `DistributedMesh::new` takes it: the cells
//! the rank owns and one layer of ghost cells (every other cell with a vertex in an owned cell),
//! their vertices with global ids (the vertex's index in the whole mesh, so local vertices are in
//! global order), and the tagged faces of those cells. Rank 0, which read the mesh, cuts the
//! parts and sends each rank its own (`send`, `receive`).

use super::wire;
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::{CellType, MeshData};

/// One rank's part.
pub struct Part {
    /// The part's vertices (in global order), cells (the whole mesh's order) and tagged faces.
    pub data: MeshData,
    /// The global id of each local vertex: its index in the whole mesh, ascending.
    pub gids: Vec<u64>,
    /// Whether each local cell is another rank's.
    pub ghost: Vec<bool>,
}

impl Part {
    /// A part of no vertex and no cell.
    pub fn empty() -> Part {
        Part { data: MeshData::default(), gids: Vec::new(), ghost: Vec::new() }
    }
}

/// The parts of `data` whose cells `owner` gives to ranks 0..`ranks`.
pub fn cut(data: &MeshData, owner: &[usize], ranks: usize) -> Result<Vec<Part>, String> {
    let spans = polyhedron_spans(data)?;
    let face_cells = face_cells(data);
    (0..ranks).map(|r| Ok(cut_one(data, owner, r, &spans, &face_cells))).collect()
}

/// Rank `rank`'s part.
fn cut_one(
    data: &MeshData,
    owner: &[usize],
    rank: usize,
    spans: &[Option<std::ops::Range<usize>>],
    face_cells: &[Vec<u32>],
) -> Part {
    let nv = data.num_vertices();
    let mut touches = vec![false; nv];
    (0..data.num_cells())
        .filter(|&c| owner[c] == rank)
        .for_each(|c| data.cell(c).iter().for_each(|&v| touches[v as usize] = true));
    let in_part: Vec<bool> =
        (0..data.num_cells()).map(|c| owner[c] == rank || data.cell(c).iter().any(|&v| touches[v as usize])).collect();
    let mut local_of = vec![u32::MAX; nv];
    (0..data.num_cells())
        .filter(|&c| in_part[c])
        .for_each(|c| data.cell(c).iter().for_each(|&v| local_of[v as usize] = 0));
    let mut out = MeshData::new(data.dim);
    let mut gids = Vec::new();
    for (v, l) in local_of.iter_mut().enumerate() {
        if *l == 0 {
            *l = out.push_vertex(data.point(v));
            gids.push(v as u64);
        }
    }
    let local = |vs: &[u32]| -> Vec<u32> { vs.iter().map(|&v| local_of[v as usize]).collect() };
    let mut ghost = Vec::new();
    for c in (0..data.num_cells()).filter(|&c| in_part[c]) {
        copy_cell(&mut out, data, c, spans[c].as_ref(), &local);
        ghost.push(owner[c] != rank);
    }
    for (f, cells) in face_cells.iter().enumerate() {
        if cells.iter().any(|&c| in_part[c as usize]) {
            out.push_face(&local(data.face(f)), data.face_patch[f]);
        }
    }
    Part { data: out, gids, ghost }
}

/// Appends cell `c` of `data` to `out`, its vertices renumbered by `local` (`span`: where its
/// face list lies in `data.polyhedron_faces`, for a polyhedron).
pub fn copy_cell(
    out: &mut MeshData,
    data: &MeshData,
    c: usize,
    span: Option<&std::ops::Range<usize>>,
    local: &impl Fn(&[u32]) -> Vec<u32>,
) {
    if let Some(span) = span {
        // The polyhedron's faces, renumbered: a count, then each face's size and vertices.
        let faces = &data.polyhedron_faces[span.clone()];
        out.polyhedron_faces.push(faces[0]);
        let mut k = 1;
        while k < faces.len() {
            let n = faces[k] as usize;
            out.polyhedron_faces.push(faces[k]);
            out.polyhedron_faces.extend(local(&faces[k + 1..k + 1 + n]));
            k += 1 + n;
        }
    }
    out.push_cell(data.cell_types[c], &local(data.cell(c)), data.regions.get(c).copied().unwrap_or(0));
}

/// Where each polyhedron's list lies in `data.polyhedron_faces` (None for the other cells).
pub fn polyhedron_spans(data: &MeshData) -> Result<Vec<Option<std::ops::Range<usize>>>, String> {
    let s = &data.polyhedron_faces;
    let mut at = 0;
    let mut spans = Vec::with_capacity(data.num_cells());
    let whole = || "the polyhedra's face lists end early".to_string();
    for &ty in &data.cell_types {
        if ty != CellType::Polyhedron {
            spans.push(None);
            continue;
        }
        let start = at;
        let faces = *s.get(at).ok_or_else(whole)? as usize;
        at += 1;
        for _ in 0..faces {
            at += 1 + *s.get(at).ok_or_else(whole)? as usize;
        }
        if at > s.len() {
            return Err(whole());
        }
        spans.push(Some(start..at));
    }
    Ok(spans)
}

/// The cells each tagged face is a side of (one for a boundary face, two for an interior one), in
/// ascending order.
pub fn face_cells(data: &MeshData) -> Vec<Vec<u32>> {
    let nv = data.num_vertices();
    let mut start = vec![0u32; nv + 1];
    data.cell_vertices.iter().for_each(|&v| start[v as usize + 1] += 1);
    (0..nv).for_each(|v| start[v + 1] += start[v]);
    let mut next = start.clone();
    let mut cells = vec![0u32; data.cell_vertices.len()];
    for c in 0..data.num_cells() {
        for &v in data.cell(c) {
            cells[next[v as usize] as usize] = c as u32;
            next[v as usize] += 1;
        }
    }
    (0..data.num_faces())
        .map(|f| {
            let face = data.face(f);
            let Some(&first) = face.first() else { return Vec::new() };
            let around = &cells[start[first as usize] as usize..start[first as usize + 1] as usize];
            around.iter().copied().filter(|&c| face.iter().all(|v| data.cell(c as usize).contains(v))).collect()
        })
        .collect()
}

/// On rank 0 (`parts`: every rank's): sends each other rank its part and returns rank 0's; on
/// the others, the part rank 0 sent. A part that does not arrive whole becomes an empty one,
/// which the distributed mesh then refuses on every rank (no rank is left waiting). Collective.
pub fn distribute(world: &SimpleCommunicator, parts: Option<Vec<Part>>) -> Part {
    let Some(mut parts) = parts else { return receive(world).unwrap_or_else(|_| Part::empty()) };
    for (r, p) in parts.iter().enumerate().skip(1) {
        send(world, r, p);
    }
    parts.truncate(1);
    parts.pop().unwrap_or_else(Part::empty)
}

/// Sends `part` to rank `to` (rank 0; `to` calls [`receive`]).
fn send(world: &SimpleCommunicator, to: usize, part: &Part) {
    let d = &part.data;
    let types: Vec<u8> = d.cell_types.iter().map(|t| t.vtk_id()).collect();
    let ghost: Vec<u8> = part.ghost.iter().map(|&g| u8::from(g)).collect();
    wire::send(world, to, &[d.dim as u64]);
    wire::send(world, to, &d.coords);
    wire::send(world, to, &types);
    wire::send(world, to, &d.cell_offsets);
    wire::send(world, to, &d.cell_vertices);
    wire::send(world, to, &d.regions);
    wire::send(world, to, &d.face_offsets);
    wire::send(world, to, &d.face_vertices);
    wire::send(world, to, &d.face_patch);
    wire::send(world, to, &d.polyhedron_faces);
    wire::send(world, to, &part.gids);
    wire::send(world, to, &ghost);
}

/// This rank's part, from rank 0 ([`send`]).
fn receive(world: &SimpleCommunicator) -> Result<Part, String> {
    let dim = wire::receive::<u64>(world).first().copied().unwrap_or(0) as usize;
    let coords = wire::receive(world);
    let types: Vec<u8> = wire::receive(world);
    let cell_types = types
        .iter()
        .map(|&t| CellType::from_vtk(t.into()).ok_or_else(|| format!("rank 0 sent cell type {t}")))
        .collect::<Result<Vec<_>, _>>()?;
    let data = MeshData {
        dim,
        coords,
        cell_types,
        cell_offsets: wire::receive(world),
        cell_vertices: wire::receive(world),
        regions: wire::receive(world),
        face_offsets: wire::receive(world),
        face_vertices: wire::receive(world),
        face_patch: wire::receive(world),
        polyhedron_faces: wire::receive(world),
    };
    let gids = wire::receive(world);
    let ghost = wire::receive::<u8>(world).into_iter().map(|g| g != 0).collect();
    Ok(Part { data, gids, ghost })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit squares of triangles side by side (x in 0..2), the left side tagged 1.
    fn strip() -> MeshData {
        let mut d = MeshData::new(2);
        for j in 0..2 {
            for i in 0..3 {
                d.push_vertex(&[i as f64, j as f64]);
            }
        }
        for i in 0..2u32 {
            d.push_cell(CellType::Triangle, &[i, i + 1, i + 4], 0);
            d.push_cell(CellType::Triangle, &[i, i + 4, i + 3], 0);
        }
        d.push_face(&[3, 0], 1);
        d
    }

    #[test]
    fn a_part_holds_its_cells_the_ghost_layer_and_their_faces() {
        let d = strip();
        // Cells 0 and 1 (x in 0..1) on rank 0, cells 2 and 3 on rank 1.
        let parts = cut(&d, &[0, 0, 1, 1], 2).unwrap();
        // Every cell touches vertex 1 or 4, which both parts' owned cells hold: each part has all.
        assert_eq!(parts[0].ghost, vec![false, false, true, true]);
        assert_eq!(parts[1].ghost, vec![true, true, false, false]);
        assert_eq!(parts[1].gids, vec![0, 1, 2, 3, 4, 5]);
        // The tagged face on x = 0 is a side of cell 1, which both parts hold.
        assert_eq!(parts[1].data.face(0), &[3, 0]);
        meshmove::Mesh::from_data(&parts[1].data).unwrap();
    }

    #[test]
    fn a_far_part_leaves_out_cells_and_faces_it_does_not_touch() {
        let mut d = strip();
        // A third square (x in 2..3) makes the left square's cells far from rank 1's.
        d.push_vertex(&[3.0, 0.0]);
        d.push_vertex(&[3.0, 1.0]);
        d.push_cell(CellType::Triangle, &[2, 6, 7], 0);
        d.push_cell(CellType::Triangle, &[2, 7, 5], 0);
        let parts = cut(&d, &[0, 0, 0, 0, 1, 1], 2).unwrap();
        assert_eq!(parts[1].gids, vec![1, 2, 4, 5, 6, 7]);
        assert_eq!(parts[1].ghost, vec![true, true, false, false]);
        assert_eq!(parts[1].data.num_faces(), 0);
        assert_eq!(parts[1].data.cell(0), &[0, 1, 3]);
    }
}
