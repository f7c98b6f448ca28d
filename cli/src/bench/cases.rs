//! The bench's cases: a mesh, what holds its boundary, how it moves, and which component
//! carries the solve. The 2D free surface (periodic sides, top moved by 0.25 cos 2πx), its 3D
//! analogue on the unit cube (top moved by 0.1 cos 2πx cos 2πy in z, sides sliding), and the
//! graded meshes the goals also name.

use meshmove::{BoundaryConditions, Kind, Link, Mesh, Motion, RigidMotion};
use meshmove_cases::boxes::{structured_box, BoxCells, BOX_BOTTOM, BOX_SIDES, BOX_TOP};
use meshmove_cases::meshes::{free_surface, FS_BOTTOM, FS_LEFT, FS_RIGHT, FS_TOP};
use meshmove_cases::ogrid::{self, CellKind};
use std::f64::consts::TAU;

/// Amplitude of the 2D free surface's motion.
pub const A_2D: f64 = 0.25;
/// Amplitude of the 3D box's motion.
pub const A_3D: f64 = 0.1;

/// One bench case on one mesh.
pub struct Case {
    /// The csv's `case` column.
    pub name: &'static str,
    pub mesh: Mesh,
    pub bcs: BoundaryConditions,
    pub motion: Motion,
    /// The component the motion moves: the only one with a non-zero right-hand side, the one
    /// the work unit, the direct solve and the Jacobi mover are measured on.
    pub comp: usize,
}

/// Base spacing of the 2D free surface: about 16.8 thousand vertices; each uniform
/// refinement ×4.
pub const BASE_H: f64 = 1.0 / 120.0;

/// The free-surface case on `mesh` (a [`free_surface`] mesh, refined or not): bottom fixed, top
/// clamped and moved by A cos(2πx) in y, the sides periodic (x clamped, y free).
pub fn free_surface_2d(mesh: Mesh) -> Case {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(FS_BOTTOM, Kind::Fixed).set_kinds(FS_TOP, Kind::Clamped);
    for p in [FS_LEFT, FS_RIGHT] {
        bcs.set_kind(p, 0, Kind::Clamped).expect("component 0").set_kind(p, 1, Kind::Free).expect("component 1");
    }
    bcs.add_link(Link::ByOffset { a: FS_LEFT, b: FS_RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(FS_TOP) {
        let x = mesh.point(v as usize)[0];
        motion.displacement[2 * v as usize + 1] = A_2D * (TAU * x).cos();
    }
    Case { name: "free-surface-2d", mesh, bcs, motion, comp: 1 }
}

/// The smallest 2D mesh.
pub fn free_surface_base() -> Mesh {
    free_surface(BASE_H)
}

/// Cells per side of the smallest 3D box: 32³ = 32768 vertices; each size doubles it (×8
/// vertices).
pub const BASE_N_3D: usize = 31;

/// The cells per side of every 3D box size: from `base`, doubling, while the box has at most
/// `max_vertices` vertices.
pub fn box_sizes(base: usize, max_vertices: usize) -> Vec<usize> {
    std::iter::successors(Some(base), |n| Some(2 * n)).take_while(|n| (n + 1).pow(3) <= max_vertices).collect()
}

/// Boundary conditions of the 3D box: bottom fixed, top clamped, the four sides sliding (the
/// normal component fixed, the others free).
pub fn box_bcs() -> BoundaryConditions {
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(BOX_BOTTOM, Kind::Fixed).set_kinds(BOX_TOP, Kind::Clamped);
    for (p, normal) in BOX_SIDES {
        for c in 0..3 {
            let kind = if c == normal { Kind::Fixed } else { Kind::Free };
            bcs.set_kind(p, c, kind).expect("3 components");
        }
    }
    bcs
}

/// The top's displacement in z at (x, y).
pub fn box_top_dz(x: f64, y: f64) -> f64 {
    A_3D * (TAU * x).cos() * (TAU * y).cos()
}

/// The 3D free-surface analogue on the unit cube of `n`³ cells: [`box_bcs`], the top moved by
/// A cos(2πx) cos(2πy) in z.
pub fn free_surface_box(n: usize, cells: BoxCells) -> Case {
    let mesh = structured_box(n, cells);
    let mut motion = Motion::zero(&mesh);
    for v in mesh.patch_vertices(BOX_TOP) {
        let p = mesh.point(v as usize);
        motion.displacement[3 * v as usize + 2] = box_top_dz(p[0], p[1]);
    }
    let name = match cells {
        BoxCells::Hexes => "box-hex-3d",
        BoxCells::Tets => "box-tet-3d",
        BoxCells::Prisms => "box-prism-3d",
    };
    Case { name, mesh, bcs: box_bcs(), motion, comp: 2 }
}

/// The graded cases: a cylinder (2D, triangles) and a sphere (3D, tetrahedra) of diameter 1 in
/// an O-grid whose wall cells are 1/50 of the far-field cells (`cases::ogrid`), the box's walls
/// fixed, the body clamped and translated by 0.1 in x, at about 30 thousand vertices and ×4
/// (2D) or ×8 (3D) up to the bench's limits; run like the uniform cases, in the csv under their
/// own `case` names. Each is a maker, so one mesh at a time is in memory.
pub fn graded_cases(max_vertices_2d: usize, max_vertices_3d: usize) -> Vec<Box<dyn FnOnce() -> Case>> {
    let mut out: Vec<Box<dyn FnOnce() -> Case>> = Vec::new();
    for n in graded_sizes(max_vertices_2d, 4) {
        out.push(Box::new(move || graded(ogrid::cylinder_with_vertices(n, CellKind::Simplex), "graded-cylinder-2d")));
    }
    for n in graded_sphere_sizes(max_vertices_3d) {
        out.push(Box::new(move || graded_sphere(n)));
    }
    out
}

/// The graded meshes' target vertex counts: about 30 thousand, times `factor` while at most `max`.
fn graded_sizes(max: usize, factor: usize) -> impl Iterator<Item = usize> {
    std::iter::successors(Some(30_000), move |n| Some(n * factor)).take_while(move |&n| n <= max)
}

/// The graded sphere's target vertex counts up to `max`.
pub fn graded_sphere_sizes(max: usize) -> impl Iterator<Item = usize> {
    graded_sizes(max, 8)
}

/// The 3D graded case (tetrahedra) at about `vertices` vertices.
pub fn graded_sphere(vertices: usize) -> Case {
    graded(ogrid::sphere_with_vertices(vertices, CellKind::Simplex), "graded-sphere-3d")
}

/// A graded O-grid case: walls fixed, the body clamped and translated by 0.1 in x.
fn graded(mesh: Result<Mesh, String>, name: &'static str) -> Case {
    let mesh = mesh.expect("the O-grid generator meets its vertex target");
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(ogrid::OG_WALL, Kind::Fixed).set_kinds(ogrid::OG_BODY, Kind::Clamped);
    let r = RigidMotion { translation: [0.1, 0.0, 0.0], rotation: [0.0; 3], center: [0.0; 3] };
    let motion = Motion::zero(&mesh).with_rigid(ogrid::OG_BODY, r);
    Case { name, mesh, bcs, motion, comp: 0 }
}
