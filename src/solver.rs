//! The solver a flow code holds for the life of its mesh: hierarchy built once, then each time
//! step a motion in and displacements out.

use crate::bc::{resolve_links, BoundaryConditions, Kind, P};
use crate::mesh::quality::{quality, Quality};
use crate::motion::Motion;
use crate::multigrid::cycle::{cycle, Workspace};
use crate::multigrid::hierarchy::{Hierarchy, HierarchyParams, Level};
use crate::multigrid::smoother::Start;
use crate::multigrid::solve::{solve, Report, SolveParams};
use crate::operator::Method;
use crate::sparse::max_abs;
use crate::{Error, Mesh, Result};
use glam::DVec2;

#[derive(Clone, Debug, Default)]
pub struct Options {
    pub method: Method,
    pub solve: SolveParams,
    /// Worker threads; 0 uses rayon's global pool.
    pub threads: usize,
    pub hierarchy: HierarchyParams,
}

/// Displacements of every vertex and how the solve went.
#[derive(Clone, Debug)]
pub struct Solution {
    pub displacement: Vec<DVec2>,
    pub report: Report,
}

pub struct Solver {
    opts: Options,
    bcs: BoundaryConditions,
    hierarchy: Hierarchy,
    pool: Option<rayon::ThreadPool>,
}

use crate::bc::COMPONENT;

impl Solver {
    pub fn new(mesh: &Mesh, bcs: &BoundaryConditions, opts: Options) -> Result<Solver> {
        check_solve_params(&opts.solve)?;
        bcs.check(mesh)?;
        let pairs = resolve_links(mesh, &bcs.links)?;
        let pool = match opts.threads {
            0 => None,
            n => Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| Error::InvalidArgument(format!("cannot start {n} threads: {e}")))?,
            ),
        };
        let build = || Hierarchy::build(mesh, pairs, bcs, opts.method, &opts.hierarchy);
        let hierarchy = match &pool {
            Some(p) => p.install(build)?,
            None => build()?,
        };
        Ok(Solver { opts, bcs: bcs.clone(), hierarchy, pool })
    }

    fn run<T: Send>(&self, f: impl FnOnce() -> T + Send) -> T {
        match &self.pool {
            Some(p) => p.install(f),
            None => f(),
        }
    }

    /// The reference mesh (the mesh at the start of the step).
    pub fn mesh(&self) -> &Mesh {
        &self.hierarchy.fine().mesh
    }

    pub fn options(&self) -> &Options {
        &self.opts
    }

    /// Changes how later solves iterate (mode, criterion, tolerance, Chebyshev settings) without
    /// rebuilding the hierarchy: the coarse meshes and operators do not depend on them.
    pub fn set_solve_params(&mut self, p: SolveParams) -> Result<()> {
        check_solve_params(&p)?;
        self.opts.solve = p;
        Ok(())
    }

    pub fn num_levels(&self) -> usize {
        self.hierarchy.levels.len()
    }

    /// A table of the multigrid levels.
    pub fn describe(&self) -> String {
        self.hierarchy.describe()
    }

    pub fn hierarchy(&self) -> &Hierarchy {
        &self.hierarchy
    }

    /// Prescribed values (zero off P) and the rigid-motion flux source of component `c`.
    fn prescribed(&self, motion: &Motion, vals: &[DVec2], c: usize) -> Result<(Vec<f64>, Option<Vec<f64>>)> {
        let lev = self.hierarchy.fine();
        let flags = &lev.flags[c];
        let mut dp = vec![0.0; lev.n()];
        for d in 0..lev.n() {
            if flags[d] & P == 0 {
                continue;
            }
            let vs = lev.dofs.vertices_of(d);
            let v0 = vals[vs[0] as usize][c];
            // Linked vertices are one unknown: they must be told the same thing.
            for &v in &vs[1..] {
                let vv = vals[v as usize][c];
                if (vv - v0).abs() > 1e-9 * (1.0 + v0.abs().max(vv.abs())) {
                    return Err(Error::InvalidArgument(format!(
                        "linked vertices {} and {v} are prescribed different {} displacements ({v0} and {vv})",
                        vs[0], COMPONENT[c]
                    )));
                }
            }
            dp[d] = v0;
        }
        Ok((dp, self.rigid_flux(motion, c)))
    }

    /// DESIGN §4: on a CLAMPED patch moving rigidly, S_b = (1/V_b) Σ_j K_bj (d_j − L_j); the
    /// K L part is returned here as a source, so the held spacing rotates with the body.
    fn rigid_flux(&self, motion: &Motion, c: usize) -> Option<Vec<f64>> {
        let lev = self.hierarchy.fine();
        if lev.op.method != Method::Biharmonic {
            return None;
        }
        let mut g: Option<Vec<f64>> = None;
        let x = lev.mesh.coords();
        for &(patch, m) in &motion.rigid {
            if self.bcs.kind(patch, c) != Kind::Clamped {
                continue;
            }
            let l: Vec<f64> = lev.dofs.dof_vertex.iter().map(|&v| m.displacement(x[v as usize])[c]).collect();
            let mut on_patch = vec![false; lev.mesh.num_vertices()];
            lev.mesh.patch_vertices(patch).iter().for_each(|&v| on_patch[v as usize] = true);
            let g = g.get_or_insert_with(|| vec![0.0; lev.n()]);
            // Every unknown of a patch vertex: a vertex split per region has one per side.
            for (d, g) in g.iter_mut().enumerate() {
                if lev.dofs.vertices_of(d).iter().any(|&v| on_patch[v as usize]) {
                    *g = lev.op.k.row_dot(d, &l);
                }
            }
        }
        g
    }

    /// The right-hand side of component `c` (its scratch S freed before the solve starts).
    fn rhs(lev: &Level, c: usize, dp: &[f64], g: Option<&[f64]>) -> Vec<f64> {
        let (mut b, mut s) = (vec![0.0; lev.n()], vec![0.0; lev.n()]);
        lev.op.rhs(&lev.flags[c], dp, g, &mut b, &mut s);
        b
    }

    fn scale(vals: &[DVec2]) -> f64 {
        vals.iter().fold(0.0f64, |m, d| m.max(d.x.abs()).max(d.y.abs()))
    }

    fn to_vertices(lev: &Level, d: &[Vec<f64>; 2]) -> Vec<DVec2> {
        lev.dofs.vertex_dof.iter().map(|&k| DVec2::new(d[0][k as usize], d[1][k as usize])).collect()
    }

    /// Solves for the displacement of every vertex, to the tolerance of the options.
    pub fn solve(&self, motion: &Motion) -> Result<Solution> {
        self.solve_from(motion, None)
    }

    /// As `solve`, starting from a guess (e.g. the previous time step's displacement).
    pub fn solve_from(&self, motion: &Motion, guess: Option<&[DVec2]>) -> Result<Solution> {
        let lev = self.hierarchy.fine();
        motion.check(&lev.mesh)?;
        if let Some(g) = guess {
            check_guess(g, lev.mesh.num_vertices())?;
        }
        let vals = motion.vertex_values(&lev.mesh);
        let scale = Self::scale(&vals);
        let mut d: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut reps = Vec::new();
        for c in 0..2 {
            let (dp, g) = self.prescribed(motion, &vals, c)?;
            let flags = &lev.flags[c];
            let b = Self::rhs(lev, c, &dp, g.as_deref());
            // Not kept through the solve (memory): the prescribed values are re-read from `vals`.
            drop((dp, g));
            let mut x: Vec<f64> = match guess {
                Some(gv) => (0..lev.n())
                    .map(|k| if flags[k] & P != 0 { 0.0 } else { gv[lev.dofs.dof_vertex[k] as usize][c] })
                    .collect(),
                None => vec![0.0; lev.n()],
            };
            let rep = self.run(|| solve(&self.hierarchy, c, &self.opts.solve, &b, &mut x, scale));
            if !rep.rel_residual.is_finite() || rep.rel_residual > 1.0 {
                return Err(Error::Diverged(format!(
                    "component {} residual {:e} after {} cycles",
                    COMPONENT[c], rep.rel_residual, rep.cycles
                )));
            }
            // The solve leaves P unknowns at zero; they take their prescribed values.
            for (k, x) in x.iter_mut().enumerate() {
                if flags[k] & P != 0 {
                    *x += vals[lev.dofs.vertices_of(k)[0] as usize][c];
                }
            }
            d[c] = x;
            reps.push(rep);
        }
        let ry = reps.pop().expect("two reports");
        let rx = reps.pop().expect("two reports");
        Ok(Solution { displacement: Self::to_vertices(lev, &d), report: Report::merge(rx, ry) })
    }

    /// One multigrid cycle of the solver's mode from `displacement` (read and overwritten): for
    /// codes that run a fixed number of cycles per time step.
    pub fn cycle(&self, motion: &Motion, displacement: &mut [DVec2]) -> Result<Report> {
        let lev = self.hierarchy.fine();
        motion.check(&lev.mesh)?;
        check_guess(displacement, lev.mesh.num_vertices())?;
        let vals = motion.vertex_values(&lev.mesh);
        let cp = self.opts.solve.cycle_params(self.opts.method);
        let mut d: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        let mut reps = Vec::new();
        for c in 0..2 {
            let t0 = std::time::Instant::now();
            let (dp, g) = self.prescribed(motion, &vals, c)?;
            let flags = &lev.flags[c];
            let n = lev.n();
            let b = Self::rhs(lev, c, &dp, g.as_deref());
            let (mut s, mut r) = (vec![0.0; n], vec![0.0; n]);
            let mut x: Vec<f64> = (0..n)
                .map(|k| if flags[k] & P != 0 { 0.0 } else { displacement[lev.dofs.dof_vertex[k] as usize][c] })
                .collect();
            let before = x.clone();
            self.run(|| {
                let mut ws = Workspace::new(&self.hierarchy);
                cycle(&self.hierarchy, c, &cp, &b, &mut x, Start::Guess, &mut ws);
            });
            lev.op.residual(flags, &b, &x, &mut r, &mut s);
            let bn = crate::sparse::dot(&b, &b).sqrt();
            let rel = if bn > 0.0 { crate::sparse::dot(&r, &r).sqrt() / bn } else { 0.0 };
            let change: Vec<f64> = x.iter().zip(&before).map(|(a, b)| a - b).collect();
            let mc = max_abs(&change);
            x.iter_mut().zip(&dp).for_each(|(x, p)| *x += p);
            d[c] = x;
            let secs = t0.elapsed().as_secs_f64();
            reps.push(Report {
                cycles: 1,
                max_correction: mc,
                rel_residual: rel,
                converged: false,
                seconds: secs,
                history: vec![(mc, rel)],
            });
        }
        let ry = reps.pop().expect("two reports");
        let rx = reps.pop().expect("two reports");
        let out = Self::to_vertices(lev, &d);
        displacement.copy_from_slice(&out);
        Ok(Report::merge(rx, ry))
    }

    /// Makes `coords` the new reference mesh: K and V re-evaluated on every level, the coarse
    /// topology kept (rebuilt only if a coarse cell would invert).
    pub fn set_reference(&mut self, coords: Vec<DVec2>) -> Result<()> {
        if coords.len() != self.mesh().num_vertices() || coords.iter().any(|p| !p.is_finite()) {
            return Err(Error::InvalidArgument(format!(
                "new reference needs {} finite positions, got {}",
                self.mesh().num_vertices(),
                coords.len()
            )));
        }
        let hierarchy = &mut self.hierarchy;
        let pool = &self.pool;
        let kept = match pool {
            Some(p) => p.install(|| hierarchy.move_to(coords.clone()))?,
            None => hierarchy.move_to(coords.clone())?,
        };
        if !kept {
            let mesh = self.hierarchy.fine().mesh.with_coords(coords);
            let pairs = self.hierarchy.fine().pairs.clone();
            let (bcs, method, hp) = (&self.bcs, self.opts.method, &self.opts.hierarchy);
            let build = || Hierarchy::build(&mesh, pairs, bcs, method, hp);
            self.hierarchy = match &self.pool {
                Some(p) => p.install(build)?,
                None => build()?,
            };
        }
        Ok(())
    }

    /// Moves the boundary to `motion` in `steps` equal steps, the reference re-evaluated after
    /// each (the paper's 10- and 15-interval runs). The solver's reference becomes the moved
    /// mesh. Returns one report per step.
    pub fn move_in_steps(&mut self, motion: &Motion, steps: usize) -> Result<Vec<Report>> {
        if steps == 0 {
            return Err(Error::InvalidArgument("step count must be at least 1".into()));
        }
        motion.check(self.mesh())?;
        let mut reports = Vec::with_capacity(steps);
        for i in 0..steps {
            let sol = self.solve(&motion.increment(i, steps))?;
            let moved: Vec<DVec2> = self.mesh().coords().iter().zip(&sol.displacement).map(|(x, d)| *x + *d).collect();
            self.set_reference(moved)?;
            reports.push(sol.report);
        }
        Ok(reports)
    }

    /// Quality of the reference mesh moved by `displacement`.
    pub fn quality(&self, displacement: &[DVec2]) -> Quality {
        let m = self.mesh();
        let moved: Vec<DVec2> = m.coords().iter().zip(displacement).map(|(x, d)| *x + *d).collect();
        quality(m, &moved)
    }
}

fn check_solve_params(p: &SolveParams) -> Result<()> {
    if !(p.tol > 0.0 && p.tol.is_finite())
        || p.max_cycles == 0
        || p.cheb_degree == Some(0)
        || p.cheb_coarse_degree == Some(0)
        || p.cheb_lower_ratio.is_some_and(|r| !(r > 1.0 && r.is_finite()))
    {
        return Err(Error::InvalidArgument(
            "tolerance must be positive and finite, max cycles and Chebyshev degree at least 1, lower ratio finite and above 1"
                .into(),
        ));
    }
    Ok(())
}

fn check_guess(g: &[DVec2], nv: usize) -> Result<()> {
    if g.len() != nv {
        return Err(Error::InvalidArgument(format!(
            "displacement has {} entries, the mesh has {nv} vertices",
            g.len()
        )));
    }
    if let Some(v) = g.iter().position(|d| !d.is_finite()) {
        return Err(Error::InvalidArgument(format!("initial displacement of vertex {v} is not finite")));
    }
    Ok(())
}
