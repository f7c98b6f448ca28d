//! The solver numbers its unknowns itself (reverse Cuthill–McKee, for cache locality): the
//! caller's vertex numbering must not change the answer. The same meshes with their vertices
//! shuffled give the same displacement at every vertex, to well below the solve tolerance.

use meshmove::{IndexBase, Mesh, Method, Motion, Options, Solver};
use meshmove_cases::setups::{case, free_surface_case, CaseSetup, Scale};

/// The case with its vertices renumbered by a fixed pseudo-random permutation; returns the
/// shuffled set-up and `new_of` (old vertex → new vertex).
fn shuffled(s: &CaseSetup) -> (Mesh, Motion, Vec<usize>) {
    let n = s.mesh.num_vertices();
    let mut order: Vec<usize> = (0..n).collect();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for i in (1..n).rev() {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        order.swap(i, (state >> 33) as usize % (i + 1));
    }
    let mut new_of = vec![0; n];
    for (new, &old) in order.iter().enumerate() {
        new_of[old] = new;
    }
    let m = &s.mesh;
    let xy = m.coords_xy();
    let coords: Vec<[f64; 2]> = order.iter().map(|&o| xy[o]).collect();
    let cells: Vec<[u32; 3]> = m.tris().iter().map(|t| t.map(|v| new_of[v as usize] as u32)).collect();
    let tagged: Vec<([u32; 2], i32)> =
        m.patch_edges().iter().map(|e| (e.vertices.map(|v| new_of[v as usize] as u32), e.patch)).collect();
    let mesh = Mesh::triangles(&coords, &cells, IndexBase::Zero, &tagged, Some(m.regions())).unwrap();
    let mut motion = s.motion.clone();
    let d = &s.motion.displacement;
    motion.displacement = order.iter().flat_map(|&o| [d[2 * o], d[2 * o + 1]]).collect();
    (mesh, motion, new_of)
}

fn check(s: &CaseSetup) {
    let (mesh, motion, new_of) = shuffled(s);
    for method in [Method::Biharmonic, Method::Laplacian] {
        let mut opts = Options { method, ..Default::default() };
        opts.solve.tol = 1e-12;
        let a = Solver::new(&s.mesh, &s.bcs, opts.clone()).unwrap().solve(&s.motion).unwrap();
        let b = Solver::new(&mesh, &s.bcs, opts).unwrap().solve(&motion).unwrap();
        let scale = s.motion.displacement.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        let (da, db, new_of) = (&a.displacement, &b.displacement, &new_of);
        let worst = (0..s.mesh.num_vertices())
            .flat_map(|v| (0..2).map(move |c| (da[2 * v + c] - db[2 * new_of[v] + c]).abs()))
            .fold(0.0, f64::max);
        assert!(worst <= 1e-9 * scale, "{} {method:?}: shuffled numbering differs by {worst:e}", s.name);
        assert!(a.report.converged && b.report.converged && a.report.cycles >= 3);
    }
}

#[test]
fn free_surface_answer_does_not_depend_on_vertex_numbering() {
    check(&free_surface_case("free_surface", 1.0 / 16.0, 0.25, 1));
}

#[test]
fn split_interface_answer_does_not_depend_on_vertex_numbering() {
    check(&case("deforming_interface_A", Scale::Quick).unwrap());
}
