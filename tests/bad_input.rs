//! Every named mesh error, ill-posed problems and bad arguments give their error; nothing panics.

mod common;
use common::*;
use meshmove::{
    BoundaryConditions, Error, IndexBase, InterfaceVariant, Kind, Link, Mesh, MeshError, Motion, Options, RigidMotion,
    Solver,
};

const SQ: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

fn mesh_err(
    coords: &[[f64; 2]],
    cells: &[[i64; 3]],
    base: IndexBase,
    tagged: &[([i64; 2], i32)],
    regions: Option<&[i32]>,
) -> MeshError {
    Mesh::triangles(coords, cells, base, tagged, regions).unwrap_err()
}

#[test]
fn each_mesh_error_is_named() {
    let z = IndexBase::Zero;
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 4], [0, 2, 3]], z, &[], None),
        MeshError::IndexOutOfRange { cell: 0, index: 4, .. }
    ));
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, -1], [0, 2, 3]], z, &[], None),
        MeshError::IndexOutOfRange { index: -1, .. }
    ));
    // 1-based input: index 0 is out of range, index 4 is fine.
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 2]], IndexBase::One, &[], None),
        MeshError::IndexOutOfRange { index: 0, base: 1, .. }
    ));
    assert!(Mesh::triangles(&SQ, &[[1i64, 2, 3], [1, 3, 4]], IndexBase::One, &[], None).is_ok());
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 1], [0, 2, 3]], z, &[], None),
        MeshError::RepeatedVertex { cell: 0, vertex: 1 }
    ));
    let collinear = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
    assert!(matches!(
        mesh_err(&collinear, &[[0, 1, 2], [0, 1, 3]], z, &[], None),
        MeshError::DegenerateCell { cell: 0, .. }
    ));
    let nan = [[0.0, 0.0], [1.0, f64::NAN], [1.0, 1.0], [0.0, 1.0]];
    assert!(matches!(
        mesh_err(&nan, &[[0, 1, 2], [0, 2, 3]], z, &[], None),
        MeshError::NonFiniteCoordinate { vertex: 1, .. }
    ));
    let inf = [[0.0, 0.0], [1.0, 0.0], [f64::INFINITY, 1.0], [0.0, 1.0]];
    assert!(matches!(
        mesh_err(&inf, &[[0, 1, 2], [0, 2, 3]], z, &[], None),
        MeshError::NonFiniteCoordinate { vertex: 2, .. }
    ));
    // Three cells on edge (0, 2).
    let fan = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, -1.0]];
    assert!(matches!(
        mesh_err(&fan, &[[0, 1, 2], [0, 2, 3], [0, 4, 2]], z, &[], None),
        MeshError::NonManifoldFace { face, cells: 3 } if face == [0, 2]
    ));
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 2], [0, 2, 3]], z, &[([1, 3], 5)], None),
        MeshError::TaggedFaceNotAFace { face: 0, .. }
    ));
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 2], [0, 2, 3]], z, &[([0, 1], 5), ([1, 0], 6)], None),
        MeshError::TaggedFaceTwice { .. }
    ));
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 2], [0, 2, 3]], z, &[([0, 9], 5)], None),
        MeshError::TaggedIndexOutOfRange { index: 9, .. }
    ));
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 2], [0, 2, 3]], z, &[], Some(&[1])),
        MeshError::RegionCount { regions: 1, cells: 2 }
    ));
    assert!(matches!(mesh_err(&SQ, &[[0, 1, 2]], z, &[], None), MeshError::UnusedVertex { vertex: 3 }));
    assert!(matches!(mesh_err(&[], &[], z, &[], None), MeshError::Empty));
    assert!(matches!(mesh_err(&SQ, &[], z, &[], None), MeshError::Empty));
}

#[test]
fn a_mesh_given_clockwise_is_normalised_but_mixed_orientation_is_refused() {
    let m = Mesh::triangles(&SQ, &[[0i64, 2, 1], [0, 3, 2]], IndexBase::Zero, &[], None).unwrap();
    let areas = meshmove::mesh::signed_measures(&m, m.coords());
    assert_eq!(areas, vec![0.5, 0.5]);
    assert_eq!(m.patch_edges().len(), 4);
    let z = IndexBase::Zero;
    assert!(matches!(
        mesh_err(&SQ, &[[0, 1, 2], [0, 3, 2]], z, &[], None),
        MeshError::InconsistentOrientation { cell: 1, negative: 1, positive: 1 }
    ));
}

/// A fan of four cells around a centre vertex that lies outside the square: each cell on its
/// own is a fine triangle, together they fold. Flipping cells one by one accepted it.
#[test]
fn a_tangled_fan_is_refused() {
    let xy = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.5, 0.5]];
    let fan = [[0i64, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]];
    let e = Mesh::triangles(&xy, &fan, IndexBase::Zero, &[], None).unwrap_err();
    assert!(matches!(e, MeshError::InconsistentOrientation { cell: 1, negative: 1, positive: 3 }), "{e}");
}

#[test]
fn overlapping_and_repeated_cells_are_refused() {
    let xy = [[0.0, 0.0], [1.0, 0.0], [0.5, 1.0], [0.5, 0.5]];
    let e = Mesh::triangles(&xy, &[[0i64, 1, 2], [0, 1, 3]], IndexBase::Zero, &[], None).unwrap_err();
    assert!(matches!(e, MeshError::Overlap { first: 0, second: 1, ref face } if face == &[0, 1]), "{e}");
    let e = Mesh::triangles(&SQ, &[[0i64, 1, 2], [0, 2, 3], [1, 2, 0]], IndexBase::Zero, &[], None).unwrap_err();
    assert!(matches!(e, MeshError::RepeatedCell { first: 0, second: 2 }), "{e}");
}

#[test]
fn interior_tagged_edge_is_an_interface() {
    let m = Mesh::triangles(&SQ, &[[0i64, 1, 2], [0, 2, 3]], IndexBase::Zero, &[([0, 2], 7)], Some(&[0, 1])).unwrap();
    assert!(m.patch_edges().iter().any(|e| e.patch == 7 && e.interior));
}

#[test]
fn ill_posed_component_is_an_error_not_a_hang() {
    let mesh = Grid::new(6, 6).mesh();
    let mut bcs = BoundaryConditions::new();
    bcs.default_kind = [Kind::Free, Kind::Fixed, Kind::Fixed];
    let e = Solver::new(&mesh, &bcs, Options::default()).err().unwrap();
    assert!(matches!(e, Error::IllPosed { component: "x", .. }), "{e}");
    // Two disjoint squares: the second has only a FREE patch, so it floats.
    let mut coords = SQ.to_vec();
    coords.extend(SQ.iter().map(|p| [p[0] + 2.0, p[1]]));
    let cells = [[0i64, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    let tagged = [([4i64, 5], 9), ([5, 6], 9), ([6, 7], 9), ([7, 4], 9)];
    let two = Mesh::triangles(&coords, &cells, IndexBase::Zero, &tagged, None).unwrap();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(9, Kind::Free);
    let e = Solver::new(&two, &bcs, Options::default()).err().unwrap();
    assert!(matches!(&e, Error::IllPosed { detail, .. } if detail.contains("vertex 4")), "{e}");
}

#[test]
fn bad_boundary_conditions_are_named() {
    let mesh = Grid::new(6, 6).mesh();
    let mut bcs = BoundaryConditions::new();
    bcs.set_kinds(42, Kind::Fixed);
    assert!(matches!(Solver::new(&mesh, &bcs, Options::default()), Err(Error::Bc(m)) if m.contains("patch 42")));
    // Components are x, y, z (a z kind is accepted and ignored on a 2D mesh): 3 does not exist.
    assert!(BoundaryConditions::new().set_kind(1, 3, Kind::Free).is_err());
    assert!(BoundaryConditions::new().set_kind(1, 2, Kind::Free).is_ok());
    // A periodic link whose partner is missing (wrong offset).
    let mut bcs = BoundaryConditions::new();
    bcs.add_link(Link::ByOffset { a: LEFT, b: RIGHT, offset: [0.9, 0.0, 0.0], tol: 1e-9 });
    assert!(matches!(Solver::new(&mesh, &bcs, Options::default()), Err(Error::Bc(m)) if m.contains("no partner")));
    let mut bcs = BoundaryConditions::new();
    bcs.add_link(Link::Pairs(vec![[0, 10_000]]));
    assert!(matches!(Solver::new(&mesh, &bcs, Options::default()), Err(Error::Bc(_))));
    // Variant A on a patch that is not interior, and with a free component.
    let mut bcs = BoundaryConditions::new();
    bcs.set_interface(TOP, InterfaceVariant::Separate);
    assert!(matches!(Solver::new(&mesh, &bcs, Options::default()), Err(Error::Bc(_))));
    let two = Grid::new(6, 6).two_regions();
    let mut bcs = BoundaryConditions::new();
    bcs.set_interface(INTERFACE, InterfaceVariant::Separate).set_kind(INTERFACE, 1, Kind::Free).unwrap();
    assert!(matches!(Solver::new(&two, &bcs, Options::default()), Err(Error::Bc(m)) if m.contains("FREE")));
}

#[test]
fn bad_motions_and_options_are_named() {
    let mesh = Grid::new(6, 6).mesh();
    let s = Solver::new(&mesh, &BoundaryConditions::new(), Options::default()).unwrap();
    // A displacement of 3 values (1.5 vertices) for a mesh of 49 vertices.
    let short = Motion::from_displacement(vec![0.0; 3]);
    assert!(matches!(s.solve(&short), Err(Error::InvalidArgument(m)) if m.contains("3 values")));
    let mut m = Motion::zero(&mesh);
    m.displacement[2 * 5] = f64::NAN;
    assert!(matches!(s.solve(&m), Err(Error::InvalidArgument(m)) if m.contains("vertex 5")));
    let m = Motion::zero(&mesh).with_rigid(99, RigidMotion::translation([1.0, 0.0, 0.0]));
    assert!(matches!(s.solve(&m), Err(Error::InvalidArgument(m)) if m.contains("patch 99")));
    let mut s2 = Solver::new(&mesh, &BoundaryConditions::new(), Options::default()).unwrap();
    assert!(s2.move_in_steps(&Motion::zero(&mesh), 0).is_err());
    assert!(s2.set_reference(vec![0.0; 2 * 2]).is_err());
    let mut o = Options::default();
    o.solve.tol = -1.0;
    assert!(matches!(Solver::new(&mesh, &BoundaryConditions::new(), o), Err(Error::InvalidArgument(_))));
}

/// A periodic offset with a z component on a 2D mesh is refused when the solver resolves the
/// link, naming the link (a 3-vector with z = 0 is fine).
#[test]
fn z_offset_on_a_2d_mesh_is_refused() {
    let mesh = common::Grid::new(4, 4).mesh();
    let mut ok = BoundaryConditions::new();
    ok.set_kinds(common::BOTTOM, Kind::Fixed).set_kinds(common::TOP, Kind::Fixed);
    for p in [common::LEFT, common::RIGHT] {
        ok.set_kind(p, 1, Kind::Free).unwrap();
    }
    let mut bad = ok.clone();
    ok.add_link(Link::ByOffset { a: common::LEFT, b: common::RIGHT, offset: [1.0, 0.0, 0.0], tol: 1e-9 });
    assert!(Solver::new(&mesh, &ok, Options::default()).is_ok());
    bad.add_link(Link::ByOffset { a: common::LEFT, b: common::RIGHT, offset: [1.0, 0.0, 0.5], tol: 1e-9 });
    let e = Solver::new(&mesh, &bad, Options::default()).err().expect("refused");
    assert!(e.to_string().contains("has a z component, and the mesh is 2D"), "{e}");
}
