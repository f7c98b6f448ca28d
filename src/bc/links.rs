//! Resolving links into vertex pairs.

use super::Link;
use crate::{Error, Mesh, Result};

/// All linked vertex pairs of the mesh, with a clear error when a vertex finds no partner.
pub(crate) fn resolve_links(mesh: &Mesh, links: &[Link]) -> Result<Vec<[u32; 2]>> {
    let mut pairs = Vec::new();
    let nv = mesh.num_vertices() as u32;
    for link in links {
        match link {
            Link::Pairs(p) => {
                if let Some(bad) = p.iter().flatten().find(|&&v| v >= nv) {
                    return Err(Error::Bc(format!("link pair names vertex {bad}, the mesh has {nv}")));
                }
                pairs.extend(p.iter().copied());
            }
            &Link::ByOffset { a, b, offset, tol } => pairs.extend(by_offset(mesh, a, b, offset, tol)?),
        }
    }
    Ok(pairs)
}

fn by_offset(mesh: &Mesh, a: i32, b: i32, offset: [f64; 3], tol: f64) -> Result<Vec<[u32; 2]>> {
    check_offset(mesh.dim(), a, b, offset, tol)?;
    let (va, vb) = (mesh.patch_vertices(a), mesh.patch_vertices(b));
    let dim = mesh.dim();
    let x = |v: u32| -> [f64; 3] {
        let mut p = [0.0; 3];
        p[..dim].copy_from_slice(mesh.point(v as usize));
        p
    };
    match_by_offset(dim, [a, b], offset, tol, &va, &vb, x, |v| format!("vertex {v}")).map_err(|(_, msg)| Error::Bc(msg))
}

/// The offset and tolerance of the link `a` → `b` are usable on a mesh of dimension `dim`.
pub(crate) fn check_offset(dim: usize, a: i32, b: i32, offset: [f64; 3], tol: f64) -> Result<()> {
    if !(tol >= 0.0 && tol.is_finite() && offset.iter().all(|x| x.is_finite())) {
        return Err(Error::Bc(format!("link {a} -> {b}: offset and tolerance must be finite, tolerance ≥ 0")));
    }
    if dim == 2 && offset[2] != 0.0 {
        return Err(Error::Bc(format!(
            "link {a} -> {b}: the offset {offset:?} has a z component, and the mesh is 2D"
        )));
    }
    Ok(())
}

/// Pairs each vertex of `va` (patch `a`) with the vertex of `vb` (patch `b`) at its position
/// (`x`) plus `offset` within `tol`, every vertex of both used once. Else the vertex at fault
/// and a message naming vertices by `name`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn match_by_offset(
    dim: usize,
    [a, b]: [i32; 2],
    offset: [f64; 3],
    tol: f64,
    va: &[u32],
    vb: &[u32],
    x: impl Fn(u32) -> [f64; 3],
    name: impl Fn(u32) -> String,
) -> std::result::Result<Vec<[u32; 2]>, (u32, String)> {
    if va.is_empty() || vb.is_empty() {
        let (p, v) = if va.is_empty() { (a, vb.first()) } else { (b, va.first()) };
        return Err((v.copied().unwrap_or(0), format!("link {a} -> {b}: patch {p} has no vertex")));
    }
    let dist = |p: &[f64; 3], q: &[f64; 3]| crate::geometry::dist2(p, q).sqrt();
    // Patches are boundary curves (O(√N) vertices), so a sorted sweep on x is plenty.
    let mut sorted_b: Vec<u32> = vb.to_vec();
    sorted_b.sort_by(|&p, &q| x(p)[0].total_cmp(&x(q)[0]).then(p.cmp(&q)));
    let mut taken = vec![false; sorted_b.len()];
    let mut out = Vec::with_capacity(va.len());
    for &v in va {
        let xv = x(v);
        let target = [0, 1, 2].map(|i| if i < dim { xv[i] + offset[i] } else { 0.0 });
        let lo = sorted_b.partition_point(|&w| x(w)[0] < target[0] - tol);
        let found = sorted_b[lo..]
            .iter()
            .enumerate()
            .take_while(|(_, &w)| x(w)[0] <= target[0] + tol)
            .filter(|(_, &w)| dist(&x(w), &target) <= tol)
            .min_by(|(_, &p), (_, &q)| dist(&x(p), &target).total_cmp(&dist(&x(q), &target)));
        match found {
            Some((k, &w)) if !taken[lo + k] => {
                taken[lo + k] = true;
                out.push([v, w]);
            }
            Some((_, &w)) => {
                return Err((w, format!("link {a} -> {b}: {} of patch {b} is the partner of two vertices", name(w))))
            }
            None => {
                return Err((
                    v,
                    format!(
                        "link {a} -> {b}: {} at {:?} has no partner on patch {b} at {:?} within {tol}",
                        name(v),
                        &xv[..dim],
                        &target[..dim]
                    ),
                ))
            }
        }
    }
    if let Some(k) = taken.iter().position(|t| !t) {
        let w = sorted_b[k];
        return Err((w, format!("link {a} -> {b}: {} of patch {b} has no partner on patch {a}", name(w))));
    }
    Ok(out)
}
