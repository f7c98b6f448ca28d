//! A component is determined only if every connected part of the mesh has a prescribed unknown.

use super::{Dofs, SlipFrames, P};
use crate::sparse::{offset, CsrMatrix};
use crate::{Error, Result};

/// Names of the components in messages.
pub(crate) const COMPONENT: [&str; 3] = ["x", "y", "z"];

/// Each component needs a prescribed unknown in every connected part of the mesh, or its
/// displacement is undetermined (docs/DESIGN.md §3: an error, not a hang). With slip walls a
/// part is determined when the directions prescribed in it (the axes of its P components and the
/// normals of its slip unknowns) span every direction: a uniform translation along all its walls
/// would be free otherwise.
pub(crate) fn check_well_posed(k: &CsrMatrix, flags: &[Vec<u8>], dofs: &Dofs, slip: Option<&SlipFrames>) -> Result<()> {
    let n = dofs.n;
    let mut comp = vec![u32::MAX; n];
    // The smallest vertex of each part: messages name vertices in the caller's numbering,
    // independent of how the solver orders its unknowns.
    let mut parts: Vec<u32> = Vec::new();
    // The numbering's runs are the parts of the cells' graph, which is K's (every cell couples
    // all its corners): no search over K's rows.
    let starts = dofs.part_starts().unwrap_or(&[]);
    for (p, &a) in starts.iter().enumerate() {
        let b = starts.get(p + 1).map_or(n, |&b| b as usize);
        let id = offset(p);
        comp[a as usize..b].iter_mut().for_each(|c| *c = id);
        parts.push(dofs.dof_vertex[a as usize..b].iter().copied().min().unwrap_or(u32::MAX));
    }
    for s in 0..n {
        if comp[s] != u32::MAX {
            continue;
        }
        let id = parts.len() as u32;
        parts.push(dofs.dof_vertex[s]);
        let mut stack = vec![s];
        comp[s] = id;
        while let Some(i) = stack.pop() {
            parts[id as usize] = parts[id as usize].min(dofs.dof_vertex[i]);
            for &j in k.row(i).0 {
                if comp[j as usize] == u32::MAX {
                    comp[j as usize] = id;
                    stack.push(j as usize);
                }
            }
        }
    }
    if let Some(slip) = slip {
        return check_spans(&comp, &parts, flags, slip);
    }
    for (c, flags) in flags.iter().enumerate() {
        let mut has_p = vec![false; parts.len()];
        for i in 0..n {
            if flags[i] & P != 0 {
                has_p[comp[i] as usize] = true;
            }
        }
        let floating = (0..parts.len()).filter(|&p| !has_p[p]).min_by_key(|&p| parts[p]);
        if let Some(part) = floating {
            let v = parts[part];
            let detail = if parts.len() == 1 {
                String::new()
            } else {
                format!(" in the part of the mesh containing vertex {v}")
            };
            return Err(Error::IllPosed {
                component: COMPONENT[c],
                detail: format!("{detail}: set a FIXED or CLAMPED patch"),
            });
        }
    }
    Ok(())
}

/// The slip form of the check: per part, the prescribed directions must span the space.
fn check_spans(comp: &[u32], parts: &[u32], flags: &[Vec<u8>], slip: &SlipFrames) -> Result<()> {
    let dim = flags.len();
    // Per part, for each component, some unknown has it prescribed; and the slip normals.
    let mut has_p = vec![[false; 3]; parts.len()];
    for (c, f) in flags.iter().enumerate() {
        for (i, &fi) in f.iter().enumerate() {
            if fi & P != 0 {
                has_p[comp[i] as usize][c] = true;
            }
        }
    }
    let mut normals: Vec<Vec<[f64; 3]>> = vec![Vec::new(); parts.len()];
    for (k, &d) in slip.dofs.iter().enumerate() {
        normals[comp[d as usize] as usize].extend_from_slice(slip.directions(k));
    }
    let mut order: Vec<usize> = (0..parts.len()).collect();
    order.sort_by_key(|&p| parts[p]);
    for p in order {
        // A basis of the prescribed directions (Gram–Schmidt); what it misses is free to slide.
        let mut basis: Vec<[f64; 3]> = Vec::new();
        let axes = (0..dim).filter(|&c| has_p[p][c]).map(|c| {
            let mut e = [0.0; 3];
            e[c] = 1.0;
            e
        });
        for v in axes.chain(normals[p].iter().copied()) {
            add_direction(&mut basis, v, dim);
        }
        if basis.len() == dim {
            continue;
        }
        let mut missing = [0.0; 3];
        for c in 0..dim {
            let mut e = [0.0; 3];
            e[c] = 1.0;
            if add_direction(&mut basis, e, dim) {
                missing = *basis.last().expect("just added");
                break;
            }
        }
        let c = (0..dim).max_by(|&a, &b| missing[a].abs().total_cmp(&missing[b].abs())).unwrap_or(0);
        let dir: Vec<String> = missing[..dim].iter().map(|v| format!("{v:.3}")).collect();
        let part = if parts.len() > 1 { format!(" in the part of the mesh containing vertex {}", parts[p]) } else { String::new() };
        return Err(Error::IllPosed {
            component: COMPONENT[c],
            detail: format!(
                "{part}: the mesh can slide along ({}) on its SLIP walls, nothing prescribes that direction: set a \
                 FIXED or CLAMPED patch",
                dir.join(", ")
            ),
        });
    }
    Ok(())
}

/// Adds the part of `v` orthogonal to the orthonormal `basis`, when it is not negligible.
fn add_direction(basis: &mut Vec<[f64; 3]>, v: [f64; 3], dim: usize) -> bool {
    if basis.len() >= dim {
        return false;
    }
    let len0 = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let mut w = v;
    for _ in 0..2 {
        for b in basis.iter() {
            let a = b[0] * w[0] + b[1] * w[1] + b[2] * w[2];
            (0..3).for_each(|c| w[c] -= a * b[c]);
        }
    }
    let len = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    if len0 == 0.0 || len <= 1e-6 * len0 {
        return false;
    }
    basis.push(w.map(|x| x / len));
    true
}
