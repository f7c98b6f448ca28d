//! Boundary faces: their area vector.

/// The area vector of a boundary face of `corners` corners in `dim` dimensions, corner k at
/// `point(k)` (z = 0 in 2D), in the face's orientation: in 2D the segment's right-hand normal
/// times its length; in 3D Newell's vector, the polygon's normal times its area (exact for
/// planar polygons, a least-squares plane's for warped quads).
pub(crate) fn face_area_vector(dim: usize, corners: usize, point: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
    let p = |k: usize| point(k % corners);
    if dim == 2 {
        let (a, b) = (p(0), p(1));
        return [b[1] - a[1], a[0] - b[0], 0.0];
    }
    let mut n = [0.0; 3];
    for k in 0..corners {
        let (a, b) = (p(k), p(k + 1));
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n.map(|x| 0.5 * x)
}
