//! Sizes and quality of the O-grid meshes (cases/src/ogrid.rs):
//! `cargo run --release -p meshmove-cases --example ogrid_probe`; with `worst`, the spheroid's worst cells.
use meshmove_cases::ogrid::*;
use std::time::Instant;

fn show(name: &str, p: &OgridParams) {
    let t = Instant::now();
    let pl = plan(p).unwrap();
    let m = ogrid(p).unwrap_or_else(|e| panic!("{name}: {e}"));
    let s = measure(&m, OG_BODY);
    let n: Vec<usize> = (0..p.dim).map(|d| pl.n(d)).collect();
    println!(
        "{name}: {:?} n {:?} layers {} half {:?}: {} vertices (plan {}), {} cells, min angle {:.2}, max edge ratio {:.2}, body edge {:.4}, wall edge {:.4}, max edge {:.3}, measure {:.6}, {:.2}s",
        p.kind, n, pl.layers, &pl.half[..p.dim], m.num_vertices(), pl.num_vertices(p.kind), m.num_cells(),
        s.min_angle_deg, s.max_edge_ratio, s.body_edge, s.wall_normal_edge, s.max_edge, s.total_measure, t.elapsed().as_secs_f64()
    );
}

fn main() {
    if std::env::args().nth(1).as_deref() == Some("worst") {
        for kind in [CellKind::Tensor, CellKind::Simplex] {
            let m =
                ogrid(&OgridParams::spheroid([0.0; 3], [0.6, 0.15, 0.15], [[-3.0, 3.0]; 3], 0.03, 0.3).with_kind(kind))
                    .unwrap();
            println!("{kind:?}");
            worst(&m, 12);
        }
        return;
    }
    let ch = [[0.0, 6.0], [-1.5, 1.5], [-1.5, 1.5]];
    for kind in [CellKind::Tensor, CellKind::Simplex] {
        show("sphere_channel", &OgridParams::sphere([2.0, 0.0, 0.0], 0.5, ch, 0.05, 0.15).with_kind(kind));
        show("sphere_channel quick", &OgridParams::sphere([2.0, 0.0, 0.0], 0.5, ch, 0.1, 0.3).with_kind(kind));
        show(
            "spheroid",
            &OgridParams::spheroid([0.0; 3], [0.6, 0.15, 0.15], [[-3.0, 3.0]; 3], 0.03, 0.3).with_kind(kind),
        );
        show("cylinder", &OgridParams::cylinder([0.0; 2], 0.5, [[-20.0, 20.0]; 2], 0.05, 2.5).with_kind(kind));
    }
    let exact = 54.0 - 4.0 / 3.0 * std::f64::consts::PI * 0.125;
    println!("sphere_channel exact volume {exact:.6}");
}

/// The `k` cells of smallest angle: centroid and angle.
fn worst(m: &meshmove::Mesh, k: usize) {
    let q: Vec<f64> = (0..m.num_cells()).map(|c| cell_min_angle(m, c)).collect();
    let mut idx: Vec<usize> = (0..m.num_cells()).collect();
    idx.sort_by(|&a, &b| q[a].total_cmp(&q[b]));
    for &c in idx.iter().take(k) {
        let v = m.cell(c);
        let cen: Vec<f64> =
            (0..3).map(|a| v.iter().map(|&x| m.point(x as usize)[a]).sum::<f64>() / v.len() as f64).collect();
        println!("  cell {c}: angle {:.2} at ({:.3}, {:.3}, {:.3})", q[c], cen[0], cen[1], cen[2]);
    }
}
