//! The stop test under wall layers: the stretch of the finest level's edges by a correction. A
//! relative residual weighs every row of the finest level alike, and where a wall layer's cells
//! are many times thinner than the cells that make up the residual's norm, or where rows are tiny
//! against the wall's (the isotropic cells at the lines' outer ends), an error the norm no longer
//! sees can still be a sizeable fraction of a cell's size (docs/DESIGN.md §5, "The tolerance and
//! the thinnest cells"). An edge's stretch by a correction d, (dᵢ − dⱼ)·(xᵢ − xⱼ) / |xᵢ − xⱼ|²,
//! is the relative change of its length, and of the cells' volume along it; an edge from a wall
//! measures the first cell's thickness. On a level with lines a solve is converged when, besides
//! its criterion, its last correction stretches no edge (a coupling of K) by more than
//! `EDGE_STRETCH`.

use super::level::Level;
use rayon::prelude::*;
use std::ops::Range;

/// The largest stretch the last correction of a converged solve may make on an edge. The error
/// left after it is the rest of a series falling at the last iterations' rate: a fraction of it
/// where a correction's stretch falls fast from one iteration to the next, about as much again
/// where it falls slowly (the largest meshes), so no cell's volume is left more than about a
/// tenth of a percent from the converged solution's, the first layer's nor that of a cell where
/// the rows are tiny against the wall's (docs/DESIGN.md §5, "The tolerance and the thinnest
/// cells").
pub(crate) const EDGE_STRETCH: f64 = 2e-3;

/// The edges of a finest level (the couplings of K), for a group of components.
pub(crate) struct LevelEdges<'a> {
    level: &'a Level,
    /// The positions of the level's unknowns (`dim` values each).
    points: Vec<f64>,
    /// The group's components.
    comps: Range<usize>,
}

impl<'a> LevelEdges<'a> {
    /// The edges of `level` for the group `comps` when its stretches are tested: a level with a
    /// mesh and lines across wall layers, in 2D and 3D; None elsewhere (without lines no cell is
    /// thin enough for the tolerance to leave an error comparable to it).
    pub(crate) fn of_layers(level: &'a Level, comps: Range<usize>) -> Option<Self> {
        if level.lines.is_empty() || level.mesh.is_none() {
            return None;
        }
        Some(LevelEdges { level, points: level.unknown_points().into_owned(), comps })
    }

    /// The largest stretch of an edge by the correction `step · d`, `d` holding one block of n
    /// values per component of the group (zero at prescribed unknowns): the group's share of the
    /// edge's stretch (all of it when the group holds every component). `unit` is the solve's
    /// values per unit of the mesh's coordinates (see `solver::units`).
    pub(crate) fn largest(&self, step: f64, d: &[f64], unit: f64) -> f64 {
        let (k, lev) = (&self.level.op.k, self.level);
        let (n, dim, p) = (lev.n(), lev.dim(), &self.points);
        let at = |i: usize| &p[i * dim..(i + 1) * dim];
        let comps = self.comps.clone();
        let most = (0..n)
            .into_par_iter()
            .with_min_len(1024)
            .map(|i| {
                let mut most = 0.0f64;
                for &j in &k.cols[k.row_ptr[i] as usize..k.row_ptr[i + 1] as usize] {
                    let j = j as usize;
                    let len2: f64 = at(i).iter().zip(at(j)).map(|(a, b)| (a - b) * (a - b)).sum();
                    if len2 <= 0.0 {
                        continue;
                    }
                    let stretch: f64 = comps
                        .clone()
                        .enumerate()
                        .map(|(b, c)| (d[b * n + i] - d[b * n + j]) * (at(i)[c] - at(j)[c]))
                        .sum();
                    most = most.max(stretch.abs() / len2);
                }
                most
            })
            .reduce(|| 0.0, f64::max);
        step.abs() * most / unit
    }
}
