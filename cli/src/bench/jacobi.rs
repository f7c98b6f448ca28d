//! The legacy alternative: the spring system by plain l1-Jacobi sweeps, no multigrid, run to the
//! tolerance or to a cap (a time, or a sweep count). From the asymptotic rate of the last sweeps it also estimates the
//! sweeps (and seconds) it would need to reach the tolerance.

use meshmove::multigrid::hierarchy::Level;
use meshmove::sparse::dot;

pub struct Jacobi {
    pub sweeps: usize,
    pub seconds: f64,
    pub rel_residual: f64,
    /// Estimated seconds to reach the tolerance (equal to `seconds` when it got there).
    pub est_seconds: f64,
}

/// Where the sweeps stop short of the tolerance.
#[derive(Clone, Copy, Debug)]
pub enum Cap {
    /// After this many seconds.
    Seconds(f64),
    /// After this many sweeps (rounded up to a multiple of the check interval).
    Sweeps(usize),
}

/// Residual norm checked every this many sweeps.
const CHECK: usize = 50;

pub fn solve(lev: &Level, c: usize, b: &[f64], x: &mut [f64], tol: f64, cap: Cap) -> Jacobi {
    let t0 = std::time::Instant::now();
    let (flags, inv_d) = (&lev.flags()[c], &lev.inv_d()[c]);
    let n = lev.n();
    let (mut r, mut s, mut xn) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let bn = dot(b, b).sqrt();
    let mut xv = vec![0.0; n];
    let mut hist: Vec<(usize, f64)> = Vec::new();
    let mut sweeps = 0;
    let mut rel;
    loop {
        if sweeps % CHECK == 0 {
            lev.op().residual(flags, b, &xv, &mut r, &mut s);
            rel = dot(&r, &r).sqrt() / bn;
            hist.push((sweeps, rel));
            let capped = match cap {
                Cap::Seconds(s) => t0.elapsed().as_secs_f64() >= s,
                Cap::Sweeps(n) => sweeps >= n,
            };
            if rel <= tol || capped {
                break;
            }
        }
        // One pass per sweep, the residual fused in, as a tuned legacy mover would do it.
        let xr = &xv;
        lev.op().update_with_residual(flags, b, xr, &mut s, &mut xn, |i, r, _| xr[i] + inv_d[i] * r);
        std::mem::swap(&mut xv, &mut xn);
        sweeps += 1;
    }
    x.copy_from_slice(&xv);
    let seconds = t0.elapsed().as_secs_f64();
    let est_seconds = super::extrapolate::seconds_to_tol(&hist, seconds, tol);
    Jacobi { sweeps, seconds, rel_residual: rel, est_seconds }
}
