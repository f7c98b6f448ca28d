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
    let (ma, mb) = (&a.mesh, &b.mesh);
    if ma.num_vertices() != mb.num_vertices() || ma.dim != mb.dim {
        return Err(format!(
            "{} has {} points in {}D, {} has {} in {}D",
            args.a.display(),
            ma.num_vertices(),
            ma.dim,
            args.b.display(),
            mb.num_vertices(),
            mb.dim
        ));
    }
    let (mut worst, mut at) = (0.0f64, 0usize);
    for (i, (p, q)) in ma.coords.chunks_exact(ma.dim).zip(mb.coords.chunks_exact(mb.dim)).enumerate() {
        // The largest difference of the point's coordinates; NaN if any is.
        let nan_max = |m: f64, d: f64| if m.is_nan() || d.is_nan() { f64::NAN } else { m.max(d) };
        let d = p.iter().zip(q).map(|(x, y)| (x - y).abs()).fold(0.0, nan_max);
        if d > worst || d.is_nan() {
            worst = d;
            at = i;
        }
    }
    if (&ma.cell_types, &ma.cell_vertices) != (&mb.cell_types, &mb.cell_vertices) {
        println!("note: the cell lists differ");
    }
    if worst <= args.tol {
        println!("agree: max coordinate difference {worst:e} <= {:e} ({} points)", args.tol, ma.num_vertices());
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!("differ: max coordinate difference {worst:e} at point {at} > tolerance {:e}", args.tol);
        Ok(ExitCode::FAILURE)
    }
}
