//! Uniform refinement: each triangle into four at its edge midpoints, each quad into four at
//! its edge midpoints and centre.

use super::{edge_key, Csr, Mesh};
use crate::geometry::CellType;
use std::collections::HashMap;

pub(super) fn uniform(m: &Mesh) -> Mesh {
    debug_assert_eq!(m.dim(), 2, "Mesh::refined checks the dimension");
    let mut coords = m.coords().to_vec();
    let mut mid: HashMap<u64, u32> = HashMap::with_capacity(3 * m.num_cells() / 2 + m.num_vertices());
    let mut midpoint = |a: u32, b: u32, coords: &mut Vec<f64>| -> u32 {
        *mid.entry(edge_key(a, b)).or_insert_with(|| {
            let (a, b) = (a as usize, b as usize);
            let p = [0.5 * (coords[2 * a] + coords[2 * b]), 0.5 * (coords[2 * a + 1] + coords[2 * b + 1])];
            coords.extend(p);
            (coords.len() / 2 - 1) as u32
        })
    };
    let mut cells = Csr::new();
    let mut types = Vec::with_capacity(4 * m.num_cells());
    let mut regions = Vec::with_capacity(4 * m.num_cells());
    for c in 0..m.num_cells() {
        let t = m.cell(c);
        let ty = m.cell_type(c);
        match ty {
            CellType::Triangle => {
                let [a, b, c] = [t[0], t[1], t[2]];
                let ab = midpoint(a, b, &mut coords);
                let bc = midpoint(b, c, &mut coords);
                let ca = midpoint(c, a, &mut coords);
                for q in [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]] {
                    cells.push(&q);
                }
            }
            CellType::Quad => {
                let e: Vec<u32> = (0..4).map(|k| midpoint(t[k], t[(k + 1) % 4], &mut coords)).collect();
                let centre = (0..2).map(|i| 0.25 * t.iter().map(|&v| coords[2 * v as usize + i]).sum::<f64>());
                coords.extend(centre.collect::<Vec<_>>());
                let o = (coords.len() / 2 - 1) as u32;
                for k in 0..4 {
                    cells.push(&[t[k], e[k], o, e[(k + 3) % 4]]);
                }
            }
            _ => unreachable!("2D cells only"),
        }
        types.extend([ty; 4]);
        regions.extend([m.regions()[c]; 4]);
    }
    let (mut faces, mut patch, mut interior) = (Csr::new(), Vec::new(), Vec::new());
    for f in m.patch_faces() {
        let [a, b] = [f.vertices[0], f.vertices[1]];
        let c = midpoint(a, b, &mut coords);
        faces.push(&[a, c]);
        faces.push(&[c, b]);
        patch.extend([f.patch; 2]);
        interior.extend([f.interior; 2]);
    }
    Mesh::from_parts(2, coords, types, cells, regions, faces, patch, interior)
}

#[cfg(test)]
mod tests {
    use crate::geometry::CellType;
    use crate::mesh::{quality::signed_measures, IndexBase, Mesh, MeshData, MeshError};

    #[test]
    fn a_3d_mesh_is_not_refined() {
        let mut d = MeshData::new(3);
        for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
            d.push_vertex(&p);
        }
        d.push_cell(CellType::Tetra, &[0, 1, 2, 3], 0);
        let m = Mesh::from_data(&d).unwrap();
        assert!(matches!(m.refined(), Err(MeshError::RefinementDimension { dim: 3 })));
    }

    #[test]
    fn refinement_quadruples_and_keeps_area_and_patches() {
        let m = Mesh::triangles(
            &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            &[[0u32, 1, 2], [0, 2, 3]],
            IndexBase::Zero,
            &[([0, 1], 7)],
            Some(&[1, 2]),
        )
        .unwrap();
        let r = m.refine_uniform().refine_uniform();
        assert_eq!(r.num_cells(), 32);
        assert_eq!(r.num_vertices(), 25);
        let area: f64 = signed_measures(&r, r.coords()).iter().sum();
        assert!((area - 1.0).abs() < 1e-14);
        assert_eq!(r.patch_vertices(7).len(), 5);
        assert_eq!(r.num_patch_faces(), 16);
        assert_eq!(r.regions().iter().filter(|&&x| x == 2).count(), 16);
    }
}
