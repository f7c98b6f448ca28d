//! The first distributed solve: the Laplacian mover (∇²d = 0) with every boundary vertex's
//! displacement prescribed, on a rank's owned rows assembled from its owned and ghost cells,
//! solved by conjugate gradients preconditioned by a V-cycle of the distributed multigrid
//! (`distributed::mg`), or with one level by the Chebyshev–Jacobi smoother alone.

use super::agreement::agree;
use super::dist_mesh::DistributedMesh;
use super::error::{DistError, DistErrorKind};
use super::halo::HaloLayout;
use super::level_layout::Distribution;
use super::mg::{Multigrid, OwnedRows};
use super::pcg::{pcg, OneLevel, Preconditioner};
use crate::bc::{P, Z};
use crate::multigrid::group::GroupOp;
use crate::multigrid::layout::Layout;
use crate::multigrid::local_level::local_level;
use crate::multigrid::smoother::Smoother;
use crate::operator::Method;
use crate::sparse::CsrMatrix;

/// How a distributed solve iterates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistSolveParams {
    /// Relative residual ‖b − A x‖₂ / ‖b‖₂ to reach, per component.
    pub tol: f64,
    /// Most iterations per component.
    pub max_iterations: usize,
    /// Degree of the fourth-kind Chebyshev–Jacobi smoother.
    pub degree: usize,
    /// Most levels of the multigrid preconditioner; 1 preconditions by the smoother alone.
    pub max_levels: usize,
}

impl Default for DistSolveParams {
    fn default() -> Self {
        DistSolveParams { tol: 1e-8, max_iterations: 5000, degree: 4, max_levels: 20 }
    }
}

/// The displacement of a distributed solve and how it went (the same report on every rank).
#[derive(Clone, Debug, PartialEq)]
pub struct DistSolution {
    /// Displacement of every local vertex (owned and not), `dim` values each, in the host's
    /// order: the owners' values on every rank that holds a vertex.
    pub displacement: Vec<f64>,
    /// Conjugate gradient iterations of each component.
    pub iterations: Vec<usize>,
    /// The largest final relative residual over the components.
    pub rel_residual: f64,
    /// Unknowns of each level of the multigrid over all ranks, finest first (the finest level's
    /// are the vertices not prescribed); empty with one level.
    pub level_rows: Vec<u64>,
    /// Values all ranks send per halo exchange of one vector, on each level.
    pub level_halo_values: Vec<u64>,
    /// The coarsest level is gathered and factored on every rank (else it is smoothed).
    pub coarsest_gathered: bool,
}

impl DistributedMesh {
    /// Moves the interior by the Laplacian (∇²d = 0) so that every boundary vertex (a vertex on
    /// a face with one cell, on any patch) takes its value of `boundary` (`dim` values per local
    /// vertex in the host's order; only the boundary vertices' values are read, and each owner's
    /// are the ones used). Collective; every rank returns the same error when any fails.
    pub fn solve_laplacian(&self, boundary: &[f64], params: &DistSolveParams) -> Result<DistSolution, DistError> {
        let (me, dim, nv) = (self.rank(), self.dim(), self.num_local_vertices());
        let owned = self.num_owned_vertices();
        let prescribed = self.boundary_vertices();
        let checked = check_boundary(me, boundary, dim, &prescribed, self.host_index(), self.layout_global_ids());
        agree(self.halo().comm(), checked.and_then(|_| check_params(me, params)))?;
        let halo = self.halo();
        let mut flags = vec![0u8; nv];
        flags.iter_mut().enumerate().for_each(|(v, f)| {
            if v >= owned || prescribed[v] {
                *f = P | Z;
            }
        });
        let level = local_level(
            self.local_mesh().clone(),
            Method::Laplacian,
            vec![flags; dim],
            Distribution::Halo(halo.clone()),
        );
        let sm = Smoother::Fourth { degree: params.degree };
        let mut multigrid = match params.max_levels {
            1 => None,
            levels => {
                let fine = OwnedRows {
                    a: free_rows(&level.op.k, &level.flags[0], halo),
                    gids: self.layout_global_ids().to_vec(),
                    halo: halo.clone(),
                };
                Some(Multigrid::build(fine, levels, sm)?)
            }
        };
        let mut total = vec![0.0; nv * dim];
        let mut iterations = Vec::with_capacity(dim);
        let mut worst = 0.0f64;
        let mut failure = None;
        for c in 0..dim {
            // Prescribed values on owned boundary vertices, zero elsewhere; the halo takes its
            // owners' values.
            let mut dp: Vec<f64> =
                (0..nv)
                    .map(|v| {
                        if v < owned && prescribed[v] {
                            boundary[self.host_index()[v] as usize * dim + c]
                        } else {
                            0.0
                        }
                    })
                    .collect();
            halo.refresh(&mut dp);
            let op = GroupOp::new(&level, c..c + 1, false);
            let (mut b, mut s) = (vec![0.0; nv], vec![0.0; nv]);
            level.op.rhs(&level.flags[c], &dp, None, &mut b, &mut s);
            let mut x = vec![0.0; nv];
            let mut one_level = OneLevel::new(op, sm);
            let pre: &mut dyn Preconditioner = match &mut multigrid {
                Some(mg) => mg,
                None => &mut one_level,
            };
            let out = pcg(&op, halo, pre, &b, &mut x, params.tol, params.max_iterations);
            if !out.converged && failure.is_none() {
                let why = match out.breakdown {
                    Some(k) => format!("conjugate gradients broke down at iteration {k}"),
                    None => format!("relative residual {:e} after {} iterations", out.rel_residual, out.iterations),
                };
                failure = Some(format!("component {c} did not reach {:e}: {why}", params.tol));
            }
            iterations.push(out.iterations);
            worst = worst.max(out.rel_residual);
            x.iter_mut().zip(&dp).for_each(|(x, p)| *x += p);
            halo.refresh(&mut x);
            (0..nv).for_each(|v| total[v * dim + c] = x[v]);
        }
        // The PCG scalars are global, so every rank reaches the same verdict; rank 0 speaks.
        let verdict = match failure {
            Some(msg) if me == 0 => Err(DistError::new(0, DistErrorKind::Solve, msg)),
            _ => Ok(()),
        };
        agree(halo.comm(), verdict)?;
        let sizes = multigrid.as_ref().map(|mg| mg.sizes()).unwrap_or_default();
        Ok(DistSolution {
            displacement: self.to_host_order(&total, dim),
            iterations,
            rel_residual: worst,
            level_rows: sizes.iter().map(|s| s.rows).collect(),
            level_halo_values: sizes.iter().map(|s| s.halo_values).collect(),
            coarsest_gathered: multigrid.as_ref().is_some_and(|mg| mg.gathers()),
        })
    }

    /// Whether each local vertex (layout order) lies on a boundary face of the local part. For an
    /// owned vertex this is the global boundary: every cell around it is held, so a face at it
    /// with one local cell has one cell in the whole mesh.
    fn boundary_vertices(&self) -> Vec<bool> {
        let mesh = self.local_mesh();
        let mut on = vec![false; mesh.num_vertices()];
        for f in mesh.patch_faces().filter(|f| !f.interior) {
            f.vertices.iter().for_each(|&v| on[v as usize] = true);
        }
        on
    }
}

/// The rows of `k` (a level's local matrix) the solve has: the owned rows without P in `flags`,
/// over the columns without P, a halo column's P being its owner's (collective).
fn free_rows(k: &CsrMatrix, flags: &[u8], halo: &HaloLayout) -> CsrMatrix {
    let owned = halo.owned();
    let mut out: Vec<u8> = flags.iter().enumerate().map(|(v, f)| u8::from(v >= owned || f & P != 0)).collect();
    halo.refresh(&mut out);
    let mut t = Vec::new();
    for i in (0..owned).filter(|&i| out[i] == 0) {
        let (cols, vals) = k.row(i);
        t.extend(cols.iter().zip(vals).filter(|(&j, _)| out[j as usize] == 0).map(|(&j, &v)| (i as u32, j, v)));
    }
    CsrMatrix::from_triplets(k.nrows, k.ncols, t)
}

/// `boundary` has `dim` values per local vertex, finite on the boundary vertices (`host` and
/// `gids` of each vertex in layout order).
fn check_boundary(
    me: usize,
    boundary: &[f64],
    dim: usize,
    prescribed: &[bool],
    host: &[u32],
    gids: &[u64],
) -> Result<(), DistError> {
    let nv = host.len();
    if boundary.len() != nv * dim {
        let msg = format!("{} boundary values given for {nv} vertices of dimension {dim}", boundary.len());
        return Err(DistError::new(me, DistErrorKind::Input, msg));
    }
    let bad = (0..nv).filter(|&v| prescribed[v]).find(|&v| {
        let h = host[v] as usize;
        boundary[h * dim..(h + 1) * dim].iter().any(|x| !x.is_finite())
    });
    match bad {
        Some(v) => {
            let msg = format!("local vertex {} (global id {}) has a non-finite boundary value", host[v], gids[v]);
            Err(DistError::new(me, DistErrorKind::Input, msg))
        }
        None => Ok(()),
    }
}

/// The parameters are usable.
fn check_params(me: usize, p: &DistSolveParams) -> Result<(), DistError> {
    if p.tol.is_finite() && p.tol > 0.0 && p.degree >= 1 && p.degree <= 64 {
        Ok(())
    } else {
        Err(DistError::new(me, DistErrorKind::Input, format!("unusable solve parameters {p:?}")))
    }
}
