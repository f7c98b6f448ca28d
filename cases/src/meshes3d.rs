//! 3D meshes as [`MeshData`]: structured boxes of hexahedra, of tetrahedra and of prisms
//! (wedges), and the extrusion of a 2D mesh in z (triangles to wedges, quads to hexahedra).
//!
//! They are plain arrays, as a host code would hand them over; `Mesh::from_data` validates them.
//! The box patches follow the 2D free surface's numbering ([`FS_BOTTOM`](super::meshes::FS_BOTTOM)
//! 1, right 2, top 3, left 4) with the two y sides added (5, 6).

use super::meshes::lerp_step;
use meshmove::geometry::CellType;
use meshmove::mesh::MeshData;
use std::collections::HashMap;

/// Box meshes: the bottom, z = z0.
pub const BOX_BOTTOM: i32 = 1;
/// Box meshes: the side x = x1.
pub const BOX_RIGHT: i32 = 2;
/// Box meshes: the top, z = z1 (the free surface).
pub const BOX_TOP: i32 = 3;
/// Box meshes: the side x = x0.
pub const BOX_LEFT: i32 = 4;
/// Box meshes: the side y = y0.
pub const BOX_FRONT: i32 = 5;
/// Box meshes: the side y = y1.
pub const BOX_BACK: i32 = 6;

/// The cells a structured box is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxCells {
    /// One trilinear hexahedron per grid cube.
    Hexes,
    /// Six tetrahedra per grid cube around its diagonal from corner (0,0,0) to (1,1,1) (Kuhn's
    /// or Freudenthal's split): the same in every cube, so neighbouring faces match.
    Tets,
    /// Two wedges per grid cube: the xy-grid's squares split along their diagonal from (0,0) to
    /// (1,1) (as [`structured_rectangle`](super::meshes::structured_rectangle)), extruded in z;
    /// the top and bottom are triangles.
    Prisms,
}

impl BoxCells {
    /// The three kinds, in the order the cases list them.
    pub const ALL: [BoxCells; 3] = [BoxCells::Tets, BoxCells::Hexes, BoxCells::Prisms];

    /// Lower-case name: `tets`, `hexes` or `prisms`.
    pub fn name(self) -> &'static str {
        match self {
            BoxCells::Hexes => "hexes",
            BoxCells::Tets => "tets",
            BoxCells::Prisms => "prisms",
        }
    }
}

/// The box [x0, x1] × [y0, y1] × [z0, z1] (`bounds` = [x0, x1, y0, y1, z0, z1]) on an
/// `n[0]` × `n[1]` × `n[2]` grid: vertex (i, j, k) at index (k (n1 + 1) + j)(n0 + 1) + i, cells
/// as `cells` says, cube by cube (x fastest). Every boundary face is tagged with its side's patch
/// ([`BOX_BOTTOM`], [`BOX_RIGHT`], [`BOX_TOP`], [`BOX_LEFT`], [`BOX_FRONT`], [`BOX_BACK`]).
pub fn structured_box(cells: BoxCells, n: [usize; 3], bounds: [f64; 6]) -> MeshData {
    assert!(n.iter().all(|&k| k >= 1), "structured_box: at least one cell per direction");
    let [nx, ny, nz] = n;
    let id = |i: usize, j: usize, k: usize| ((k * (ny + 1) + j) * (nx + 1) + i) as u32;
    let mut d = MeshData::new(3);
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                d.push_vertex(&[
                    lerp_step(bounds[0], bounds[1], i, nx),
                    lerp_step(bounds[2], bounds[3], j, ny),
                    lerp_step(bounds[4], bounds[5], k, nz),
                ]);
            }
        }
    }
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                // The cube's corners in VTK hexahedron order: the bottom counter-clockwise
                // seen from above, then the top.
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                match cells {
                    BoxCells::Hexes => d.push_cell(CellType::Hexahedron, &c, 0),
                    BoxCells::Tets => {
                        // The six monotone paths from corner 0 to corner 6, one tetrahedron each.
                        for [a, b] in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
                            d.push_cell(CellType::Tetra, &[c[0], c[a], c[b], c[6]], 0);
                        }
                    }
                    BoxCells::Prisms => {
                        // VTK's wedge lists its bottom triangle clockwise seen from above.
                        d.push_cell(CellType::Wedge, &[c[0], c[2], c[1], c[4], c[6], c[5]], 0);
                        d.push_cell(CellType::Wedge, &[c[0], c[3], c[2], c[4], c[7], c[6]], 0);
                    }
                }
            }
        }
    }
    let [x0, x1, y0, y1, z0, z1] = bounds;
    tag_boundary(&mut d, |p| {
        let on = |axis: usize, value: f64| p.iter().all(|q| q[axis] == value);
        [
            (2, z0, BOX_BOTTOM),
            (0, x1, BOX_RIGHT),
            (2, z1, BOX_TOP),
            (0, x0, BOX_LEFT),
            (1, y0, BOX_FRONT),
            (1, y1, BOX_BACK),
        ]
        .into_iter()
        .find(|&(axis, value, _)| on(axis, value))
        .map_or(0, |t| t.2)
    });
    d
}

/// Replaces `d`'s tagged faces by its boundary faces (faces of one cell only, oriented out of
/// it), each tagged `patch(corners)`; faces given patch 0 stay untagged.
fn tag_boundary(d: &mut MeshData, patch: impl Fn(&[&[f64]]) -> i32) {
    let mut count: HashMap<Vec<u32>, (usize, Vec<u32>)> = HashMap::new();
    let mut order = Vec::new();
    for c in 0..d.num_cells() {
        let cell = d.cell(c);
        for f in d.cell_types[c].faces() {
            let v: Vec<u32> = f.iter().map(|&k| cell[k as usize]).collect();
            let mut key = v.clone();
            key.sort_unstable();
            let e = count.entry(key.clone()).or_insert_with(|| {
                order.push(key);
                (0, v)
            });
            e.0 += 1;
        }
    }
    d.face_offsets = vec![0];
    d.face_vertices.clear();
    d.face_patch.clear();
    for key in order {
        let (n, v) = &count[&key];
        if *n == 1 {
            let p: Vec<&[f64]> = v.iter().map(|&k| d.point(k as usize)).collect();
            let id = patch(&p);
            if id != 0 {
                d.push_face(v, id);
            }
        }
    }
}

/// The 2D mesh `flat` extruded in z over [z0, z1] (`z`) in `layers` equal layers: vertex v of
/// layer k (k = 0 at z0) is k nv + v; cell c of layer k is k nc + c, a wedge from a triangle and a
/// hexahedron from a quad, in `flat`'s region. Each tagged face of `flat` becomes one quad face
/// per layer on the same patch; the bottom (z = z0) and top (z = z1) faces are tagged
/// `z_patches` = [bottom, top]. `flat`'s cells may be in either orientation (all alike).
pub fn extrude(flat: &MeshData, layers: usize, z: [f64; 2], z_patches: [i32; 2]) -> MeshData {
    assert_eq!(flat.dim, 2, "extrude: a 2D mesh");
    assert!(layers >= 1 && z[1] > z[0], "extrude: at least one layer and z0 < z1");
    let nv = flat.num_vertices() as u32;
    // A cell listed clockwise is reversed, so that every prism sees its base counter-clockwise
    // from above (the mesh is then oriented as a whole, as its validation requires).
    let ccw = |c: usize| {
        let v = flat.cell(c);
        let p = |k: usize| flat.point(v[k] as usize);
        let area: f64 = (1..v.len() - 1)
            .map(|k| (p(k)[0] - p(0)[0]) * (p(k + 1)[1] - p(0)[1]) - (p(k)[1] - p(0)[1]) * (p(k + 1)[0] - p(0)[0]))
            .sum();
        let mut v = v.to_vec();
        if area < 0.0 {
            v.reverse();
        }
        v
    };
    let base: Vec<Vec<u32>> = (0..flat.num_cells()).map(ccw).collect();
    let mut d = MeshData::new(3);
    for k in 0..=layers {
        let zk = lerp_step(z[0], z[1], k, layers);
        for v in 0..flat.num_vertices() {
            let p = flat.point(v);
            d.push_vertex(&[p[0], p[1], zk]);
        }
    }
    let region = |c: usize| flat.regions.get(c).copied().unwrap_or(0);
    for k in 0..layers as u32 {
        let (lo, hi) = (k * nv, (k + 1) * nv);
        for (c, v) in base.iter().enumerate() {
            match flat.cell_types[c] {
                // VTK's wedge: the bottom triangle clockwise seen from above, then the top.
                CellType::Triangle => d.push_cell(
                    CellType::Wedge,
                    &[v[0] + lo, v[2] + lo, v[1] + lo, v[0] + hi, v[2] + hi, v[1] + hi],
                    region(c),
                ),
                CellType::Quad => {
                    let c8: Vec<u32> = v.iter().map(|&x| x + lo).chain(v.iter().map(|&x| x + hi)).collect();
                    d.push_cell(CellType::Hexahedron, &c8, region(c))
                }
                t => panic!("extrude: cell {c} is a {t}, not a 2D cell"),
            }
        }
        for f in 0..flat.num_faces() {
            let [a, b] = [flat.face(f)[0], flat.face(f)[1]];
            d.push_face(&[a + lo, b + lo, b + hi, a + hi], flat.face_patch[f]);
        }
    }
    let top = layers as u32 * nv;
    for v in &base {
        let bottom: Vec<u32> = v.iter().rev().copied().collect();
        d.push_face(&bottom, z_patches[0]);
        let upper: Vec<u32> = v.iter().map(|&x| x + top).collect();
        d.push_face(&upper, z_patches[1]);
    }
    d
}
