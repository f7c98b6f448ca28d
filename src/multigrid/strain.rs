//! The stop test under wall layers: the stretch of the first layer's edges by a correction. A
//! relative residual weighs every row of the finest level alike, and in the first cells of a
//! wall layer, many times thinner than the cells that make up the residual's norm, an error the
//! norm no longer sees can still be a sizeable fraction of a cell's thickness (docs/DESIGN.md
//! §5, "The tolerance and the thinnest cells"). An edge from a prescribed unknown (a wall) to a
//! free one measures that thickness: its stretch by a correction d, (dᵢ − dⱼ)·(xᵢ − xⱼ) / |xᵢ −
//! xⱼ|², is the relative change of the edge's length, and of the first cell's volume along it.
//! On a level with lines a solve is converged when, besides its criterion, its last correction
//! stretches no such edge by more than `LAYER_STRETCH`.

use super::level::Level;
use crate::bc::P;
use rayon::prelude::*;
use std::ops::Range;

/// The largest stretch the last correction of a converged solve may make on an edge from a wall:
/// the error left after it is a small fraction of it (the last iterations' rate), within a
/// percent of the first layer's volume with a wide margin.
pub(crate) const LAYER_STRETCH: f64 = 1e-2;

/// The edges of a finest level from its prescribed unknowns (the couplings of K), for a group of
/// components.
pub(crate) struct WallEdges<'a> {
    level: &'a Level,
    /// The positions of the level's unknowns (`dim` values each).
    points: Vec<f64>,
    /// The group's components.
    comps: Range<usize>,
}

impl<'a> WallEdges<'a> {
    /// The edges of `level` for the group `comps` when its stretches are tested: a level with a
    /// mesh and lines across wall layers, in 2D and 3D; None elsewhere (without lines no cell is
    /// thin enough for the tolerance to leave an error comparable to it).
    pub(crate) fn of_layers(level: &'a Level, comps: Range<usize>) -> Option<Self> {
        if level.lines.is_empty() || level.mesh.is_none() {
            return None;
        }
        Some(WallEdges { level, points: level.unknown_points().into_owned(), comps })
    }

    /// The largest stretch of an edge from a prescribed unknown to a free one by the correction
    /// `step · d`, `d` holding one block of n values per component of the group: the group's
    /// share of the edge's stretch (all of it when the group holds every component). `unit` is
    /// the solve's values per unit of the mesh's coordinates (see `solver::units`).
    pub(crate) fn largest(&self, step: f64, d: &[f64], unit: f64) -> f64 {
        let (k, lev) = (&self.level.op.k, self.level);
        let (n, dim, p) = (lev.n(), lev.dim(), &self.points);
        let at = |i: usize| &p[i * dim..(i + 1) * dim];
        let comps = self.comps.clone();
        let flags = &lev.flags[comps.clone()];
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
                        .filter(|&(b, _)| flags[b][j] & P != 0 && flags[b][i] & P == 0)
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
