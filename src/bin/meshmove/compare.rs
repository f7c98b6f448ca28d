//! `meshmove compare A.vtu B.vtu --tol T`.

use meshmove::io::read_vtu;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(clap::Args)]
pub struct Args {
    a: PathBuf,
    b: PathBuf,
    /// Largest allowed difference of any coordinate.
    #[arg(long, default_value_t = 1e-12)]
    tol: f64,
}

pub fn run(args: Args) -> Result<ExitCode, String> {
    if args.tol.is_nan() || args.tol < 0.0 {
        return Err(format!("--tol must be a non-negative number, got {}", args.tol));
    }
    let a = read_vtu(&args.a).map_err(|e| format!("{}: {e}", args.a.display()))?;
    let b = read_vtu(&args.b).map_err(|e| format!("{}: {e}", args.b.display()))?;
    if a.points.len() != b.points.len() {
        return Err(format!(
            "{} has {} points, {} has {}",
            args.a.display(),
            a.points.len(),
            args.b.display(),
            b.points.len()
        ));
    }
    let (mut worst, mut at) = (0.0f64, 0usize);
    for (i, (p, q)) in a.points.iter().zip(&b.points).enumerate() {
        let d = (p[0] - q[0]).abs().max((p[1] - q[1]).abs());
        if d > worst || d.is_nan() {
            worst = d;
            at = i;
        }
    }
    if a.cells != b.cells {
        println!("note: the cell lists differ");
    }
    if worst <= args.tol {
        println!("agree: max coordinate difference {worst:e} <= {:e} ({} points)", args.tol, a.points.len());
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!("differ: max coordinate difference {worst:e} at point {at} > tolerance {:e}", args.tol);
        Ok(ExitCode::FAILURE)
    }
}
