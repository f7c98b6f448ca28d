//! The interpolation's rows per level: how many rows each transfer interpolates, their mean
//! donors, how far they extrapolate (their Σ|w| binned: 1 is a convex combination, above 2 the
//! fit found no bounded row) and Σ wⱼ |xⱼ − x|² over the nearest donor's squared distance (a
//! quadratic's error relative to the row's own spacing), with the rows of largest Σ|w| (or,
//! given a point, the rows nearest it) and their weights at their donors' distances:
//! `cargo run --release -p meshmove-cases --example interpolation_probe -- spheroid 8 [X,Y,Z]`
//! (kinds and sizes as in `galerkin_probe`; `sphere VERTICES` the bench's graded sphere).
use meshmove::{BoundaryConditions, Kind, Options, Solver};
use meshmove_cases::ogrid::{self, CellKind};
use meshmove_cases::viscous::*;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let kind = args[0].as_str();
    let size = args[1].as_str();
    let at: Vec<f64> = args.get(2).map_or(vec![0.0; 3], |s| s.split(',').map(|x| x.parse().unwrap()).collect());
    let (mesh, bcs) = if kind == "sphere" {
        let mesh = ogrid::sphere_with_vertices(size.parse().unwrap(), CellKind::Simplex).unwrap();
        let mut bcs = BoundaryConditions::new();
        bcs.set_kinds(ogrid::OG_WALL, Kind::Fixed).set_kinds(ogrid::OG_BODY, Kind::Clamped);
        (mesh, bcs)
    } else {
        let v = by_name(kind, size).expect("a mesh");
        let b = boundary_conditions(&v);
        (v.mesh, b)
    };
    let solver = Solver::new(&mesh, &bcs, Options { threads: 1, ..Default::default() }).expect("solver");
    let h = solver.hierarchy();
    print!("{}", solver.describe());
    for l in 0..h.levels.len() - 1 {
        let Some(p) = h.levels[l].prolong() else { continue };
        let fp = h.levels[l].unknown_points();
        let cp = h.levels[l + 1].unknown_points();
        let mut hist = [0usize; 6];
        let (mut single, mut maxs, mut ent) = (0, 0.0f64, 0usize);
        let mut qerr = 0.0f64;
        let mut qn = 0usize;
        let mut worst: Vec<(f64, usize)> = Vec::new();
        for i in 0..p.nrows {
            let (c, w) = p.row(i);
            let s: f64 = w.iter().map(|w| w.abs()).sum();
            let x = &fp[3 * i..3 * i + 3];
            if c.len() == 1 {
                let y = &cp[3 * c[0] as usize..3 * c[0] as usize + 3];
                if x != y {
                    single += 1;
                }
                continue;
            }
            ent += c.len();
            maxs = maxs.max(s);
            let b = if s <= 1.0 + 1e-9 {
                0
            } else if s <= 1.2 {
                1
            } else if s <= 1.5 {
                2
            } else if s <= 2.0 {
                3
            } else if s <= 3.0 {
                4
            } else {
                5
            };
            hist[b] += 1;
            // |y − x|² interpolated at x (zero there) over the nearest donor's squared distance.
            let mut est = 0.0;
            let mut hmin = f64::INFINITY;
            for (&cc, &ww) in c.iter().zip(w) {
                let y = &cp[3 * cc as usize..3 * cc as usize + 3];
                let d2: f64 = (0..3).map(|k| (y[k] - x[k]).powi(2)).sum();
                est += ww * d2;
                hmin = hmin.min(d2);
            }
            qerr += est / hmin;
            qn += 1;
            let dd: f64 = (0..3).map(|k| (x[k] - at[k]).powi(2)).sum();
            worst.push((if args.len() > 2 { dd } else { -s }, i));
        }
        println!("level {l}->{}: rows {} interpolated {} (mean donors {:.2}), single non-kept {single}, sum|w| <=1 {} <=1.2 {} <=1.5 {} <=2 {} <=3 {} >3 {}, max {:.2}, mean quad/h^2 {:.2}",
            l + 1, p.nrows, qn, ent as f64 / qn.max(1) as f64, hist[0], hist[1], hist[2], hist[3], hist[4], hist[5], maxs, qerr / qn.max(1) as f64);
        worst.sort_by(|a, b| a.0.total_cmp(&b.0));
        for &(dd, i) in worst.iter().take(3) {
            let (c, w) = p.row(i);
            let x = &fp[3 * i..3 * i + 3];
            let offs: Vec<String> = c
                .iter()
                .zip(w)
                .map(|(&cc, &ww)| {
                    let y = &cp[3 * cc as usize..3 * cc as usize + 3];
                    let d: f64 = (0..3).map(|k| (y[k] - x[k]).powi(2)).sum::<f64>().sqrt();
                    format!("{ww:.3}@{d:.3}")
                })
                .collect();
            println!("   row {i} at {:.3?} (key {:.3}): {}", x, dd, offs.join(" "));
        }
    }
}
