//! Resolving links into vertex pairs.

use super::Link;
use crate::{Error, Mesh, Result};

/// All linked vertex pairs of the mesh, with a clear error when a vertex finds no partner.
pub fn resolve_links(mesh: &Mesh, links: &[Link]) -> Result<Vec<[u32; 2]>> {
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

fn by_offset(mesh: &Mesh, a: i32, b: i32, offset: glam::DVec2, tol: f64) -> Result<Vec<[u32; 2]>> {
    if !(tol >= 0.0 && tol.is_finite() && offset.is_finite()) {
        return Err(Error::Bc(format!("link {a} -> {b}: offset and tolerance must be finite, tolerance ≥ 0")));
    }
    let (va, vb) = (mesh.patch_vertices(a), mesh.patch_vertices(b));
    if va.is_empty() || vb.is_empty() {
        return Err(Error::Bc(format!("link {a} -> {b}: patch {} has no vertex", if va.is_empty() { a } else { b })));
    }
    let x = mesh.coords();
    // Patches are boundary curves (O(√N) vertices), so a sorted sweep on x is plenty.
    let mut sorted_b: Vec<u32> = vb.clone();
    sorted_b.sort_by(|&p, &q| x[p as usize].x.total_cmp(&x[q as usize].x).then(p.cmp(&q)));
    let mut taken = vec![false; sorted_b.len()];
    let mut out = Vec::with_capacity(va.len());
    for &v in &va {
        let target = x[v as usize] + offset;
        let lo = sorted_b.partition_point(|&w| x[w as usize].x < target.x - tol);
        let found = sorted_b[lo..]
            .iter()
            .enumerate()
            .take_while(|(_, &w)| x[w as usize].x <= target.x + tol)
            .filter(|(_, &w)| x[w as usize].distance(target) <= tol)
            .min_by(|(_, &p), (_, &q)| x[p as usize].distance(target).total_cmp(&x[q as usize].distance(target)));
        match found {
            Some((k, &w)) if !taken[lo + k] => {
                taken[lo + k] = true;
                out.push([v, w]);
            }
            Some((_, &w)) => {
                return Err(Error::Bc(format!(
                    "link {a} -> {b}: vertex {w} of patch {b} is the partner of two vertices"
                )))
            }
            None => {
                return Err(Error::Bc(format!(
                    "link {a} -> {b}: vertex {v} at ({}, {}) has no partner on patch {b} at ({}, {}) within {tol}",
                    x[v as usize].x, x[v as usize].y, target.x, target.y
                )))
            }
        }
    }
    if let Some(k) = taken.iter().position(|t| !t) {
        let w = sorted_b[k];
        return Err(Error::Bc(format!("link {a} -> {b}: vertex {w} of patch {b} has no partner on patch {a}")));
    }
    Ok(out)
}
