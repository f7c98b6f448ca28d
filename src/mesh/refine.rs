//! Uniform refinement: each triangle into four at its edge midpoints.

use super::{edge_key, Mesh, PatchEdge};
use std::collections::HashMap;

pub(super) fn uniform(m: &Mesh) -> Mesh {
    let mut coords = m.coords().to_vec();
    let mut mid: HashMap<u64, u32> = HashMap::with_capacity(3 * m.num_cells() / 2 + m.num_vertices());
    let mut midpoint = |a: u32, b: u32, coords: &mut Vec<glam::DVec2>| -> u32 {
        *mid.entry(edge_key(a, b)).or_insert_with(|| {
            coords.push(0.5 * (coords[a as usize] + coords[b as usize]));
            (coords.len() - 1) as u32
        })
    };
    let mut cells = Vec::with_capacity(4 * m.num_cells());
    let mut regions = Vec::with_capacity(4 * m.num_cells());
    for (t, &r) in m.cells().iter().zip(m.regions()) {
        let [a, b, c] = *t;
        let ab = midpoint(a, b, &mut coords);
        let bc = midpoint(b, c, &mut coords);
        let ca = midpoint(c, a, &mut coords);
        cells.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        regions.extend([r; 4]);
    }
    let mut patch_edges = Vec::with_capacity(2 * m.patch_edges().len());
    for e in m.patch_edges() {
        let [a, b] = e.vertices;
        let c = midpoint(a, b, &mut coords);
        patch_edges.push(PatchEdge { vertices: [a, c], ..*e });
        patch_edges.push(PatchEdge { vertices: [c, b], ..*e });
    }
    Mesh::from_parts(coords, cells, regions, patch_edges)
}

#[cfg(test)]
mod tests {
    use crate::mesh::{quality::signed_areas, IndexBase, Mesh};

    #[test]
    fn refinement_quadruples_and_keeps_area_and_patches() {
        let m = Mesh::new(
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
        let area: f64 = signed_areas(&r, r.coords()).iter().sum();
        assert!((area - 1.0).abs() < 1e-14);
        assert_eq!(r.patch_vertices(7).len(), 5);
        assert_eq!(r.patch_edges().len(), 16);
        assert_eq!(r.regions().iter().filter(|&&x| x == 2).count(), 16);
    }
}
