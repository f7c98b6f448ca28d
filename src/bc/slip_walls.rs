//! The shapes of SLIP walls, to put slipped vertices back on them after a solve (docs/DESIGN.md
//! §4, "Curved walls"): the solve moves a slip vertex in its wall's tangent plane, which leaves a
//! curved wall by a second-order distance; the vertex is then moved to the closest point of the
//! wall. The wall is the patch's original faces (piecewise linear, found through a bounding-box tree)
//! or an analytic shape the caller gives as a closest-point function, both where the wall was in
//! the mesh the solver was made with; a wall that moves rigidly carries its shape along.

use super::wall_tree::WallTree;
use super::BoundaryConditions;
use crate::geometry::closest::{closest_on_simplex, face_simplices, simplex_side};
use crate::geometry::{cross, dot3, padded, sub};
use crate::motion::RigidMotion;
use crate::Mesh;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// An analytic wall: a function from a point (`dim` coordinates) to the closest point of the wall
/// (the first `dim` values are read). It is called from the solver's threads, one call at a time.
#[derive(Clone)]
pub struct SlipSurface(Arc<ClosestPoint>);

/// A closest-point function: a point (`dim` coordinates) to the closest point of a wall, or
/// None when it failed.
type ClosestPoint = dyn Fn(&[f64]) -> Option<[f64; 3]> + Send + Sync;

/// A fan triangle (or a 2D segment) of a wall face: its mesh vertices and their positions.
type FacePiece = ([u32; 3], [[f64; 3]; 3]);

impl SlipSurface {
    /// A wall given by its closest-point function.
    pub fn new(closest: impl Fn(&[f64]) -> [f64; 3] + Send + Sync + 'static) -> SlipSurface {
        SlipSurface(Arc::new(move |x: &[f64]| Some(closest(x))))
    }

    /// A wall given by a closest-point function that may fail (None): a solve that meets a
    /// failure fails with `Error::CallbackFailed` and changes nothing.
    pub fn fallible(closest: impl Fn(&[f64]) -> Option<[f64; 3]> + Send + Sync + 'static) -> SlipSurface {
        SlipSurface(Arc::new(closest))
    }

    /// The closest point of the wall to `x` (`x` itself where the function fails).
    pub fn closest(&self, x: &[f64]) -> [f64; 3] {
        self.try_closest(x).unwrap_or_else(|| {
            let mut same = [0.0; 3];
            same[..x.len()].copy_from_slice(x);
            same
        })
    }

    /// The closest point of the wall to `x`, or None when the function failed.
    pub fn try_closest(&self, x: &[f64]) -> Option<[f64; 3]> {
        (self.0)(x)
    }

    /// A sphere (in 2D a circle) of `radius` about `center` (the first `dim` values are read).
    /// The centre itself, which has no closest point, maps to the point in the first axis'
    /// direction.
    pub fn sphere(center: [f64; 3], radius: f64) -> SlipSurface {
        SlipSurface::new(move |x| {
            let mut d = [0.0; 3];
            (0..x.len()).for_each(|c| d[c] = x[c] - center[c]);
            let len = dot3(&d, &d).sqrt();
            let u = if len > 0.0 { d.map(|v| v / len) } else { [1.0, 0.0, 0.0] };
            let mut q = [0.0; 3];
            (0..x.len()).for_each(|c| q[c] = center[c] + radius * u[c]);
            q
        })
    }

    /// An infinite circular cylinder (3D) of `radius` about the line through `center` along
    /// `axis` (any non-zero length). A point on the axis maps to the point in the direction
    /// of a fixed vector normal to the axis.
    pub fn cylinder(center: [f64; 3], axis: [f64; 3], radius: f64) -> SlipSurface {
        let len = dot3(&axis, &axis).sqrt();
        let a = axis.map(|v| v / len);
        // A fixed normal to the axis, for the points on it.
        let pick = if a[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
        let n0 = cross(&a, &pick);
        let n0 = n0.map(|v| v / dot3(&n0, &n0).sqrt());
        SlipSurface::new(move |x| {
            let mut d = [0.0; 3];
            (0..x.len()).for_each(|c| d[c] = x[c] - center[c]);
            let along = dot3(&d, &a);
            let r = [0, 1, 2].map(|c| d[c] - along * a[c]);
            let len = dot3(&r, &r).sqrt();
            let u = if len > 0.0 { r.map(|v| v / len) } else { n0 };
            [0, 1, 2].map(|c| center[c] + along * a[c] + radius * u[c])
        })
    }

    /// A plane (in 2D a line) through `point` with the normal `normal` (any non-zero length).
    pub fn plane(point: [f64; 3], normal: [f64; 3]) -> SlipSurface {
        let len = dot3(&normal, &normal).sqrt();
        let n = normal.map(|v| v / len);
        SlipSurface::new(move |x| {
            let mut d = [0.0; 3];
            (0..x.len()).for_each(|c| d[c] = x[c] - point[c]);
            let off = dot3(&d, &n);
            let mut q = [0.0; 3];
            (0..x.len()).for_each(|c| q[c] = x[c] - off * n[c]);
            q
        })
    }
}

impl std::fmt::Debug for SlipSurface {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SlipSurface(closure)")
    }
}

/// Two surfaces are equal when they are the same closure.
impl PartialEq for SlipSurface {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// A simplex of a piecewise-linear wall: `dim` corners of 3 coordinates, and which of its sides
/// are open (bit k: in 2D corner k, in 3D the edge from corner k to k + 1): where the union of
/// the SLIP walls ends (a periodic end, an inlet), the wall is extended along its last face, so a
/// vertex that slides past the end keeps its position instead of being pulled back to the end.
type Simplex = ([[f64; 3]; 3], u8);

/// A piecewise-linear wall: its faces as simplices (segments in 2D, triangles in 3D: a quad is
/// cut along its first diagonal) and a bounding-box tree of them (`wall_tree`).
#[derive(Clone, Debug)]
struct PlWall {
    dim: usize,
    simplices: Vec<Simplex>,
    tree: WallTree,
}

impl PlWall {
    fn new(dim: usize, simplices: Vec<Simplex>) -> PlWall {
        let edge = |s: &[[f64; 3]; 3], a: usize, b: usize| dot3(&sub(&s[b], &s[a]), &sub(&s[b], &s[a])).sqrt();
        let mean = simplices.iter().map(|(s, _)| edge(s, 0, 1)).sum::<f64>() / simplices.len().max(1) as f64;
        let boxes: Vec<([f64; 3], [f64; 3])> = simplices
            .iter()
            .map(|(s, open)| {
                let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
                for c in 0..dim {
                    lo[c] = s[..dim].iter().map(|p| p[c]).fold(f64::INFINITY, f64::min);
                    hi[c] = s[..dim].iter().map(|p| p[c]).fold(f64::NEG_INFINITY, f64::max);
                }
                // An open side's extension is found within a face's size of it (the larger of
                // this face's longest side and the wall's mean side): its box reaches that far.
                if *open != 0 {
                    let longest = (0..dim).flat_map(|a| (a + 1..dim).map(move |b| (a, b))).map(|(a, b)| edge(s, a, b));
                    let reach = longest.fold(mean, f64::max);
                    (0..dim).for_each(|c| (lo[c], hi[c]) = (lo[c] - reach, hi[c] + reach));
                }
                (lo, hi)
            })
            .collect();
        PlWall { dim, tree: WallTree::new(&boxes), simplices }
    }

    /// The closest point of the wall to `p`: the tree's nearest simplex.
    fn closest(&self, p: &[f64; 3]) -> [f64; 3] {
        self.tree.closest(p, |s| self.closest_on(s, p))
    }

    fn closest_on(&self, s: usize, p: &[f64; 3]) -> [f64; 3] {
        let (t, open) = &self.simplices[s];
        closest_on_simplex(t, *open, self.dim, p)
    }
}

/// The shape of one SLIP patch.
#[derive(Clone, Debug)]
enum Shape {
    Faces(PlWall),
    Analytic(SlipSurface),
}

/// The shapes of every SLIP patch of a mesh, taken when the solver is made (the original walls).
#[derive(Clone, Debug)]
pub struct SlipWalls {
    dim: usize,
    shapes: BTreeMap<i32, Shape>,
    /// The SLIP patches of each vertex that has any, sorted by vertex.
    vertex_patches: Vec<(u32, i32)>,
    /// The walls moved rigidly since their shapes were taken: the motion that took each there.
    placed: Placements,
    /// Set when a fallible analytic wall's function failed (see [`SlipWalls::take_failure`]).
    failed: Arc<AtomicBool>,
}

/// Where walls are: for each wall moved rigidly, the motion from where its shape was taken.
pub type Placements = BTreeMap<i32, RigidMotion>;

impl SlipWalls {
    /// The walls of `mesh`'s SLIP patches under `bcs`; None when there is none.
    pub fn new(mesh: &Mesh, bcs: &BoundaryConditions) -> Option<SlipWalls> {
        let dim = mesh.dim();
        let mut faces: BTreeMap<i32, Vec<FacePiece>> = BTreeMap::new();
        let mut vertex_patches = Vec::new();
        let pt = |v: u32| padded(mesh.point(v as usize));
        for f in mesh.patch_faces() {
            if !bcs.is_slip(f.patch) {
                continue;
            }
            vertex_patches.extend(f.vertices.iter().map(|&v| (v, f.patch)));
            let list = faces.entry(f.patch).or_default();
            list.extend(face_simplices(f.vertices).map(|t| (t, t.map(|v| if v == u32::MAX { [0.0; 3] } else { pt(v) }))));
        }
        if faces.is_empty() {
            return None;
        }
        // Sides used once in the union of the SLIP walls are open: corners in 2D, edges in 3D.
        let side = |t: &[u32; 3], k: usize| simplex_side(t, k, dim);
        let mut sides: Vec<(u32, u32)> =
            faces.values().flatten().flat_map(|(t, _)| (0..dim).map(move |k| side(t, k))).collect();
        sides.sort_unstable();
        let used_once = |s: (u32, u32)| {
            let lo = sides.partition_point(|&e| e < s);
            sides[lo..].iter().take_while(|&&e| e == s).count() == 1
        };
        vertex_patches.sort_unstable();
        vertex_patches.dedup();
        let shapes = faces
            .into_iter()
            .map(|(p, s)| {
                let shape = match bcs.slip_surface(p) {
                    Some(a) => Shape::Analytic(a.clone()),
                    None => {
                        let simplices = s
                            .iter()
                            .map(|(t, x)| (*x, (0..dim).filter(|&k| used_once(side(t, k))).fold(0u8, |m, k| m | 1 << k)))
                            .collect();
                        Shape::Faces(PlWall::new(dim, simplices))
                    }
                };
                (p, shape)
            })
            .collect();
        Some(SlipWalls { dim, shapes, vertex_patches, placed: Placements::new(), failed: Arc::default() })
    }

    /// Where the walls are now.
    pub fn placements(&self) -> &Placements {
        &self.placed
    }

    /// Puts the walls back where `placed` says (undoing a call that moved them).
    pub fn set_placements(&mut self, placed: Placements) {
        self.placed = placed;
    }

    /// Where the walls are after the rigid motions `rigid` of patches (the SLIP ones among them
    /// move their walls).
    pub fn placed_by(&self, rigid: &[(i32, RigidMotion)]) -> Placements {
        let mut at = self.placed.clone();
        for (p, m) in rigid.iter().filter(|(p, _)| self.shapes.contains_key(p)) {
            let next = match at.get(p) {
                Some(before) => before.then(m, self.dim),
                None => *m,
            };
            at.insert(*p, next);
        }
        at
    }

    /// Moves the walls by the rigid motions `rigid` of patches (an accepted step).
    pub fn move_walls(&mut self, rigid: &[(i32, RigidMotion)]) {
        self.placed = self.placed_by(rigid);
    }

    /// The SLIP patches vertex `v` lies on.
    pub fn patches_of(&self, v: u32) -> impl Iterator<Item = i32> + '_ {
        let lo = self.vertex_patches.partition_point(|e| e.0 < v);
        self.vertex_patches[lo..].iter().take_while(move |e| e.0 == v).map(|e| e.1)
    }

    /// The closest point of patch `patch`'s wall, placed as `at` says, to `x` (`dim`
    /// coordinates): the point is taken back to where the wall's shape was taken, the closest
    /// point found there and carried forward.
    pub fn closest(&self, at: &Placements, patch: i32, x: &[f64]) -> [f64; 3] {
        let dim = self.dim;
        let Some(m) = at.get(&patch) else {
            return self.closest_in_place(patch, x);
        };
        let back = m.inverse().apply(&x[..dim]);
        m.apply(&self.closest_in_place(patch, &back[..dim])[..dim])
    }

    /// True when a wall's closest-point function failed since the last call (which it resets).
    pub fn take_failure(&self) -> bool {
        self.failed.swap(false, Ordering::Relaxed)
    }

    /// The closest point of patch `patch`'s wall where its shape was taken.
    fn closest_in_place(&self, patch: i32, x: &[f64]) -> [f64; 3] {
        let dim = self.dim;
        let mut p = [0.0; 3];
        p[..dim].copy_from_slice(&x[..dim]);
        match &self.shapes[&patch] {
            Shape::Faces(w) => w.closest(&p),
            Shape::Analytic(s) => {
                // A failed function leaves the point where it is; the solve asks
                // `take_failure` when it is done and fails as a whole.
                let mut q = s.try_closest(&p[..dim]).unwrap_or_else(|| {
                    self.failed.store(true, Ordering::Relaxed);
                    p
                });
                q[dim..].iter_mut().for_each(|v| *v = 0.0);
                q
            }
        }
    }

    /// The distance of `x` from the walls of `patches`: from the farther wall on an `edge`
    /// (`project`), else from their union.
    pub fn distance(&self, at: &Placements, patches: &[i32], edge: bool, x: &[f64]) -> f64 {
        if !edge {
            return dist(&self.closest_of(at, patches, x), x, self.dim);
        }
        patches.iter().map(|&p| dist(&self.closest(at, p, x), x, self.dim)).fold(0.0, f64::max)
    }

    /// The closest point to `x` of the union of the walls of `patches`.
    pub fn closest_of(&self, at: &Placements, patches: &[i32], x: &[f64]) -> [f64; 3] {
        let d = |q: &[f64; 3]| dist(q, x, self.dim);
        patches.iter().map(|&p| self.closest(at, p, x)).min_by(|a, b| d(a).total_cmp(&d(b))).expect("a patch")
    }

    /// Moves `x` onto the walls of `patches`. `edge`: x lies where the walls meet at an angle
    /// (a 3D edge between two walls): alternating projections onto each wall, which converge
    /// linearly, at least as cos² of the angle between them (`FEATURE_ANGLE_DEG` or more);
    /// otherwise the closest point of their union (one smooth wall made of several patches).
    pub fn project(&self, at: &Placements, patches: &[i32], edge: bool, x: &mut [f64]) {
        let dim = self.dim;
        if !edge {
            let q = self.closest_of(at, patches, x);
            x[..dim].copy_from_slice(&q[..dim]);
            return;
        }
        let rounds = 200;
        for _ in 0..rounds {
            let mut moved = 0.0f64;
            for &p in patches {
                let q = self.closest(at, p, x);
                moved = moved.max(dist(&q, x, dim));
                x[..dim].copy_from_slice(&q[..dim]);
            }
            let scale = x[..dim].iter().fold(1.0f64, |m, v| m.max(v.abs()));
            if moved <= 1e-15 * scale {
                break;
            }
        }
    }
}

fn dist(a: &[f64; 3], x: &[f64], dim: usize) -> f64 {
    (0..dim).map(|c| (a[c] - x[c]) * (a[c] - x[c])).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::closest::closest_on_segment;

    #[test]
    fn analytic_shapes_give_their_closest_points() {
        let close = |s: &SlipSurface, x: &[f64], want: [f64; 3]| {
            let q = s.closest(x);
            assert!((0..3).all(|c| (q[c] - want[c]).abs() < 1e-15), "{x:?}: {q:?}, want {want:?}");
        };
        let circle = SlipSurface::sphere([1.0, 2.0, 0.0], 2.0);
        close(&circle, &[4.0, 6.0], [1.0 + 1.2, 2.0 + 1.6, 0.0]);
        close(&circle, &[1.0, 2.0], [3.0, 2.0, 0.0]);
        let cyl = SlipSurface::cylinder([0.0, 0.0, 1.0], [0.0, 0.0, 5.0], 3.0);
        close(&cyl, &[0.0, 2.0, 7.0], [0.0, 3.0, 7.0]);
        let plane = SlipSurface::plane([0.0, 1.0, 0.0], [0.0, 2.0, 0.0]);
        close(&plane, &[0.5, 3.0, -1.0], [0.5, 1.0, -1.0]);
        let line = SlipSurface::plane([0.0, 0.0, 0.0], [1.0, 1.0, 0.0]);
        close(&line, &[1.0, 0.0], [0.5, -0.5, 0.0]);
    }

    #[test]
    fn tree_search_finds_the_nearest_segment_of_a_polygon() {
        let n = 200;
        let pt = |k: usize| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            [3.0 * t.cos(), 3.0 * t.sin(), 0.0]
        };
        let segs: Vec<[[f64; 3]; 3]> = (0..n).map(|k| [pt(k), pt(k + 1), [0.0; 3]]).collect();
        let w = PlWall::new(2, segs.iter().map(|s| (*s, 0)).collect());
        for p in [[3.1, 0.05, 0.0], [-2.0, 0.3, 0.0], [0.0, -7.0, 0.0], [0.3, 0.1, 0.0]] {
            let got = w.closest(&p);
            let want = segs
                .iter()
                .map(|s| closest_on_segment(&s[0], &s[1], &p))
                .min_by(|x, y| dot3(&sub(x, &p), &sub(x, &p)).total_cmp(&dot3(&sub(y, &p), &sub(y, &p))))
                .unwrap();
            assert!(dist(&got, &want, 2) < 1e-14, "{p:?}: {got:?} vs {want:?}");
        }
    }
}
