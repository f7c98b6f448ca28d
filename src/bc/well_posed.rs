//! A component is determined only if every connected part of the mesh has a prescribed unknown.

use super::{Dofs, P};
use crate::sparse::CsrMatrix;
use crate::{Error, Result};

/// Names of the components in messages.
pub(crate) const COMPONENT: [&str; 3] = ["x", "y", "z"];

/// Each component needs a prescribed unknown in every connected part of the mesh, or its
/// displacement is undetermined (docs/DESIGN.md §3: an error, not a hang).
pub(crate) fn check_well_posed(k: &CsrMatrix, flags: &[Vec<u8>], dofs: &Dofs) -> Result<()> {
    let n = dofs.n;
    let mut comp = vec![u32::MAX; n];
    // The smallest vertex of each part: messages name vertices in the caller's numbering,
    // independent of how the solver orders its unknowns.
    let mut parts: Vec<u32> = Vec::new();
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
