//! Checks on raw caller input, each returning the named error of docs/DESIGN.md §2.

use super::{IndexBase, MeshError};
use glam::DVec2;

pub(super) fn coordinates(coords: &[[f64; 2]]) -> Result<Vec<DVec2>, MeshError> {
    if coords.is_empty() {
        return Err(MeshError::Empty);
    }
    if coords.len() >= u32::MAX as usize {
        return Err(MeshError::TooLarge { vertices: coords.len(), max: u32::MAX as usize - 1 });
    }
    coords
        .iter()
        .enumerate()
        .map(|(i, &[x, y])| {
            if x.is_finite() && y.is_finite() {
                Ok(DVec2::new(x, y))
            } else {
                Err(MeshError::NonFiniteCoordinate { vertex: i, x, y })
            }
        })
        .collect()
}

/// Converts one caller index to a 0-based vertex, or None when out of range.
pub(super) fn index<I: Copy + TryInto<i64>>(i: I, base: IndexBase, n: usize) -> Result<u32, i64> {
    let raw: i64 = i.try_into().unwrap_or(i64::MIN);
    let v = raw.checked_sub(base as i64).unwrap_or(-1);
    if v < 0 || v >= n as i64 {
        Err(raw)
    } else {
        Ok(v as u32)
    }
}

pub(super) fn cells<I: Copy + TryInto<i64>>(
    tris: &[[I; 3]],
    base: IndexBase,
    n: usize,
) -> Result<Vec<[u32; 3]>, MeshError> {
    if tris.is_empty() {
        return Err(MeshError::Empty);
    }
    let b = base as i64;
    tris.iter()
        .enumerate()
        .map(|(c, t)| {
            let mut out = [0u32; 3];
            for k in 0..3 {
                out[k] = index(t[k], base, n).map_err(|index| MeshError::IndexOutOfRange {
                    cell: c,
                    index,
                    base: b,
                    end: n as i64 + b,
                })?;
            }
            if out[0] == out[1] || out[0] == out[2] {
                return Err(MeshError::RepeatedVertex { cell: c, vertex: out[0] as usize });
            }
            if out[1] == out[2] {
                return Err(MeshError::RepeatedVertex { cell: c, vertex: out[1] as usize });
            }
            Ok(out)
        })
        .collect()
}

/// Every vertex must belong to a cell: a lone vertex has no equation to move it.
pub(super) fn all_used(cells: &[[u32; 3]], n: usize) -> Result<(), MeshError> {
    let mut used = vec![false; n];
    cells.iter().flatten().for_each(|&v| used[v as usize] = true);
    match used.iter().position(|u| !u) {
        Some(vertex) => Err(MeshError::UnusedVertex { vertex }),
        None => Ok(()),
    }
}

/// Twice the signed area of triangle (a, b, c).
pub fn twice_signed_area(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - a)
}

/// Orients the mesh counter-clockwise as a whole: a mesh given entirely clockwise is flipped, a
/// zero-area cell is an error, and so is a cell whose orientation disagrees with the rest's
/// (flipping cells one by one would accept a tangled mesh). The reported cell is the first one
/// of the smaller group (the first clockwise one on a tie).
pub(super) fn orient(coords: &[DVec2], cells: &mut [[u32; 3]]) -> Result<(), MeshError> {
    let mut clockwise = Vec::new();
    for (c, t) in cells.iter().enumerate() {
        let [a, b, d] = t.map(|v| coords[v as usize]);
        let area2 = twice_signed_area(a, b, d);
        // Relative test: the area against the squared longest edge, so the check is scale-free.
        let scale = (b - a).length_squared().max((d - a).length_squared()).max((d - b).length_squared());
        if area2.abs() <= 1e-14 * scale || !area2.is_finite() {
            return Err(MeshError::DegenerateCell { cell: c, area: 0.5 * area2 });
        }
        clockwise.push(area2 < 0.0);
    }
    let cw = clockwise.iter().filter(|&&x| x).count();
    let ccw = cells.len() - cw;
    if cw > 0 && ccw > 0 {
        let minority_cw = cw <= ccw;
        let cell = clockwise.iter().position(|&x| x == minority_cw).expect("both orientations present");
        return Err(MeshError::InconsistentOrientation { cell, clockwise: cw, counter_clockwise: ccw });
    }
    if cw > 0 {
        cells.iter_mut().for_each(|t| t.swap(1, 2));
    }
    Ok(())
}

/// Two cells with the same vertex set are an error (the second one names the pair).
pub(super) fn distinct(cells: &[[u32; 3]]) -> Result<(), MeshError> {
    let mut keys: Vec<([u32; 3], u32)> = cells
        .iter()
        .enumerate()
        .map(|(c, t)| {
            let mut k = *t;
            k.sort_unstable();
            (k, c as u32)
        })
        .collect();
    keys.sort_unstable();
    match keys.windows(2).find(|w| w[0].0 == w[1].0) {
        Some(w) => Err(MeshError::RepeatedCell { first: w[0].1 as usize, second: w[1].1 as usize }),
        None => Ok(()),
    }
}

pub(super) fn tagged_edges<I: Copy + TryInto<i64>>(
    tagged: &[([I; 2], i32)],
    base: IndexBase,
    n: usize,
) -> Result<Vec<([u32; 2], i32)>, MeshError> {
    let b = base as i64;
    tagged
        .iter()
        .enumerate()
        .map(|(e, &([p, q], patch))| {
            let conv = |i| {
                index(i, base, n).map_err(|index| MeshError::TaggedIndexOutOfRange {
                    edge: e,
                    index,
                    base: b,
                    end: n as i64 + b,
                })
            };
            Ok(([conv(p)?, conv(q)?], patch))
        })
        .collect()
}
