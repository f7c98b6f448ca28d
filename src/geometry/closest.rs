//! Closest points on the simplices of a boundary (segments in 2D, triangles in 3D) and the
//! simplices a boundary face splits into: what a piecewise-linear wall is made of.

use super::{cross, dot3, sub};

/// A boundary face's simplices: a segment (2 corners, the third `u32::MAX`) is its own; a
/// polygon (a triangle or a quad) is cut into a fan from its first corner, so a quad's two
/// triangles share its first diagonal.
pub(crate) fn face_simplices(vs: &[u32]) -> impl Iterator<Item = [u32; 3]> + '_ {
    let segment = (vs.len() == 2).then(|| [vs[0], vs[1], u32::MAX]);
    let fan = (1..vs.len().saturating_sub(1)).map(move |k| [vs[0], vs[k], vs[k + 1]]);
    segment.into_iter().chain(fan)
}

/// Side `k` of a boundary simplex of a `dim`-dimensional mesh (`dim` sides in all), as a sorted
/// pair of vertices: corner k of a segment (second vertex `u32::MAX`), or the edge from corner k
/// to corner k + 1 of a triangle.
pub(crate) fn simplex_side(t: &[u32; 3], k: usize, dim: usize) -> (u32, u32) {
    if dim == 2 {
        (t[k], u32::MAX)
    } else {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        (a.min(b), a.max(b))
    }
}

/// The closest point to `p` of a boundary simplex `t` of a `dim`-dimensional mesh (its first
/// `dim` corners), extended past its sides that are open (bit k of `open`: see [`simplex_side`]).
pub(crate) fn closest_on_simplex(t: &[[f64; 3]; 3], open: u8, dim: usize, p: &[f64; 3]) -> [f64; 3] {
    if dim == 2 {
        closest_on_line(&t[0], &t[1], p, (open & 1 != 0, open & 2 != 0))
    } else {
        closest_on_triangle(t, open, p)
    }
}

fn lerp(a: &[f64; 3], b: &[f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|c| a[c] + t * (b[c] - a[c]))
}

pub(crate) fn closest_on_segment(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> [f64; 3] {
    closest_on_line(a, b, p, (false, false))
}

/// The closest point to p of segment ab, extended past a or b when that end is open.
fn closest_on_line(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3], open: (bool, bool)) -> [f64; 3] {
    let ab = sub(b, a);
    let l2 = dot3(&ab, &ab);
    if l2 == 0.0 {
        return *a;
    }
    let t = dot3(&sub(p, a), &ab) / l2;
    let lo = if open.0 { f64::NEG_INFINITY } else { 0.0 };
    let hi = if open.1 { f64::INFINITY } else { 1.0 };
    lerp(a, b, t.clamp(lo, hi))
}

/// The closest point of triangle t to p (Ericson, Real-Time Collision Detection, 5.1.5): its
/// projection on the plane when that is inside, or outside only across open edges (bit k of
/// `open`: edge k → k + 1); else the closest point of the nearest edge it is outside of.
pub(crate) fn closest_on_triangle(t: &[[f64; 3]; 3], open: u8, p: &[f64; 3]) -> [f64; 3] {
    let (a, b, c) = (&t[0], &t[1], &t[2]);
    let n = cross(&sub(b, a), &sub(c, a));
    let n2 = dot3(&n, &n);
    let mut outside = [true; 3];
    if n2 > 0.0 {
        let q = {
            let s = dot3(&sub(p, a), &n) / n2;
            [0, 1, 2].map(|k| p[k] - s * n[k])
        };
        for k in 0..3 {
            let (u, v) = (&t[k], &t[(k + 1) % 3]);
            outside[k] = dot3(&cross(&sub(v, u), &sub(&q, u)), &n) < 0.0;
        }
        if (0..3).all(|k| !outside[k] || open & (1 << k) != 0) {
            return q;
        }
    }
    let d2 = |q: &[f64; 3]| dot3(&sub(q, p), &sub(q, p));
    (0..3)
        .filter(|&k| outside[k] && open & (1 << k) == 0)
        .map(|k| closest_on_segment(&t[k], &t[(k + 1) % 3], p))
        .min_by(|x, y| d2(x).total_cmp(&d2(y)))
        .unwrap_or(*a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_points_on_a_triangle() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let t = [a, b, c];
        assert_eq!(closest_on_triangle(&t, 0, &[0.2, 0.3, 5.0]), [0.2, 0.3, 0.0]);
        assert_eq!(closest_on_triangle(&t, 0, &[-1.0, -1.0, 1.0]), [0.0, 0.0, 0.0]);
        let q = closest_on_triangle(&t, 0, &[1.0, 1.0, 0.0]);
        assert!((q[0] - 0.5).abs() < 1e-15 && (q[1] - 0.5).abs() < 1e-15);
        // Open across its hypotenuse: the plane goes on.
        assert_eq!(closest_on_triangle(&t, 2, &[1.0, 1.0, 0.5]), [1.0, 1.0, 0.0]);
    }

    #[test]
    fn faces_split_into_segments_and_fans() {
        assert_eq!(face_simplices(&[4, 7]).collect::<Vec<_>>(), [[4, 7, u32::MAX]]);
        assert_eq!(face_simplices(&[1, 2, 3]).collect::<Vec<_>>(), [[1, 2, 3]]);
        assert_eq!(face_simplices(&[1, 2, 3, 4]).collect::<Vec<_>>(), [[1, 2, 3], [1, 3, 4]]);
        assert_eq!(simplex_side(&[5, 2, 9], 1, 3), (2, 9));
        assert_eq!(simplex_side(&[5, 2, 9], 2, 3), (5, 9));
        assert_eq!(simplex_side(&[5, 2, u32::MAX], 1, 2), (2, u32::MAX));
    }
}
