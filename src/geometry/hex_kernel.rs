//! The trilinear hexahedron's stiffness and lumped mass (2×2×2 Gauss) laid out for vector lanes:
//! the eight points' Jacobians side by side, each point's eight transformed gradients side by
//! side, and the 28 corner pairs as the pairs (i, i + d mod 8) of cyclic distance d = 1…4, so
//! every step is the same operation on neighbouring lanes. Each value sees the operations of the
//! point-by-point formulation in the same order (the Jacobian summed over the corners in order,
//! each pair's entry over the points in order, no fused multiply-add), so K and V are bitwise
//! that formulation's. It runs compiled for AVX2's four lanes, chosen at run time on x86-64
//! processors that have them (the same operations, the same roundings); elsewhere the
//! point-by-point formulation (`tensor::hex_stiffness_and_mass_by_points`) runs, which SSE2's two
//! lanes run as fast.

/// The trilinear shape functions at the Gauss points, in the layouts the kernel's lanes read.
struct Tables {
    /// Per corner k and reference direction b, the gradient's component at the eight points.
    by_corner: [[[f64; 8]; 3]; 8],
    /// Per point q and reference direction b, the gradient's component at the eight corners.
    by_point: [[[f64; 8]; 3]; 8],
    /// Per point q, each corner's shape function value.
    value: [[f64; 8]; 8],
}

/// The kernel's `Tables`, worked out once.
fn tables() -> &'static Tables {
    static TABLES: std::sync::OnceLock<Tables> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let g = 1.0 / 3f64.sqrt();
        let mut t = Tables { by_corner: [[[0.0; 8]; 3]; 8], by_point: [[[0.0; 8]; 3]; 8], value: [[0.0; 8]; 8] };
        for q in 0..8 {
            let xi = [if q & 1 == 0 { -g } else { g }, if q & 2 == 0 { -g } else { g }, if q & 4 == 0 { -g } else { g }];
            for (k, r) in super::tensor::HEX_REF.iter().enumerate() {
                let f = [1.0 + r[0] * xi[0], 1.0 + r[1] * xi[1], 1.0 + r[2] * xi[2]];
                t.value[q][k] = 0.125 * f[0] * f[1] * f[2];
                let grad = [0.125 * r[0] * f[1] * f[2], 0.125 * r[1] * f[0] * f[2], 0.125 * r[2] * f[0] * f[1]];
                for (b, &x) in grad.iter().enumerate() {
                    t.by_corner[k][b][q] = x;
                    t.by_point[q][b][k] = x;
                }
            }
        }
        t
    })
}

/// Eight lanes of a vector's three components.
type Lanes3 = [[f64; 8]; 3];

/// a × b lane by lane (plain loops: closures would not be inlined into the AVX2 copy).
#[inline(always)]
fn cross(a: &Lanes3, b: &Lanes3) -> Lanes3 {
    let mut c = [[0.0; 8]; 3];
    for (r, cr) in c.iter_mut().enumerate() {
        let (s, t) = ((r + 1) % 3, (r + 2) % 3);
        for q in 0..8 {
            cr[q] = a[s][q] * b[t][q] - a[t][q] * b[s][q];
        }
    }
    c
}

/// Which compiled copy of the element kernels a pass over the cells runs: the processor is asked
/// once per pass (`Lanes::detect`), not once per cell, and the pass runs inside `Lanes::run`, so
/// the hexahedron's kernel is inlined into the loop compiled for the lanes it has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Lanes {
    /// AVX2's four lanes (x86-64 processors that have them).
    Avx2,
    /// The baseline's instructions.
    Baseline,
}

impl Lanes {
    /// The lanes this processor has.
    pub(crate) fn detect() -> Lanes {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            return Lanes::Avx2;
        }
        Lanes::Baseline
    }

    /// Runs `f` compiled for these lanes (`f`'s values are the same on either: no fused
    /// multiply-add is enabled).
    #[inline(always)]
    pub(crate) fn run<R>(self, f: impl FnOnce() -> R) -> R {
        match self {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Avx2` comes from `detect`, which found AVX2 on this processor.
            Lanes::Avx2 => unsafe { in_avx2(f) },
            _ => f(),
        }
    }
}

/// `f` compiled for AVX2 (without FMA: the same roundings as the baseline's).
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn in_avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// K_ij = ∫∇φ_i·∇φ_j for the 28 corner pairs in `CellType::Hexahedron.couplings()` order and
/// the lumped mass ∫φ_i of the eight corners. At each point, with the cofactors C of the
/// Jacobian (det·J⁻ᵀ), K_ij gains (C∇_ref φ_i)·(C∇_ref φ_j) / det and the mass φ_i det. With
/// `Lanes::Avx2`, called inside `Lanes::run`, the lanes' layout runs on AVX2; with
/// `Lanes::Baseline` the point-by-point formulation, which SSE2's two lanes run as fast as the
/// lanes' layout (its shuffles and spills cost what its vectors save). Bitwise the same values
/// either way.
#[inline(always)]
pub(super) fn stiffness_and_mass(p: &[[f64; 3]], k: &mut [f64], m: &mut [f64], with: Lanes) {
    match with {
        Lanes::Avx2 => lanes(p, k, m),
        Lanes::Baseline => super::tensor::hex_stiffness_and_mass_by_points(p, k, m),
    }
}

/// The kernel itself (see the module's comment), inlined into the caller's loop.
#[inline(always)]
fn lanes(p: &[[f64; 3]], k: &mut [f64], m: &mut [f64]) {
    let t = tables();
    let p = &p[..8];
    // The Jacobian J_ab = Σ_k x_k,a ∂φ_k/∂ξ_b at the eight points, corners summed in order.
    let mut j = [[[0.0f64; 8]; 3]; 3];
    for (pk, gk) in p.iter().zip(&t.by_corner) {
        for a in 0..3 {
            for b in 0..3 {
                for q in 0..8 {
                    j[a][b][q] += pk[a] * gk[b][q];
                }
            }
        }
    }
    let (mut j0, mut j1, mut j2) = ([[0.0; 8]; 3], [[0.0; 8]; 3], [[0.0; 8]; 3]);
    for a in 0..3 {
        (j0[a], j1[a], j2[a]) = (j[a][0], j[a][1], j[a][2]);
    }
    let c = [cross(&j1, &j2), cross(&j2, &j0), cross(&j0, &j1)];
    let (mut det, mut w) = ([0.0f64; 8], [0.0f64; 8]);
    for q in 0..8 {
        det[q] = j0[0][q] * c[0][0][q] + j0[1][q] * c[0][1][q] + j0[2][q] * c[0][2][q];
        w[q] = 1.0 / det[q];
    }
    // s_k = C ∇_ref φ_k at each point, the eight corners side by side, twice over so that the
    // corners d further on are a contiguous slice. All eight points' are formed before any pair
    // reads them: a window d further on spans two of the stores, which the processor cannot
    // forward to the load while they are still in flight.
    let mut s = [[[0.0f64; 16]; 3]; 8];
    for (q, sq) in s.iter_mut().enumerate() {
        let g = &t.by_point[q];
        for a in 0..3 {
            let (c0, c1, c2) = (c[0][a][q], c[1][a][q], c[2][a][q]);
            for kk in 0..8 {
                sq[a][kk] = c0 * g[0][kk] + c1 * g[1][kk] + c2 * g[2][kk];
                sq[a][kk + 8] = sq[a][kk];
            }
        }
    }
    // Per cyclic distance d = 1, 2, 3 the pairs (i, i + d mod 8), and for d = 4 the pairs
    // (i, i + 4) of the first four lanes (the other four are the same pairs).
    let mut pairs = [[0.0f64; 8]; 3];
    let mut opposite = [0.0f64; 4];
    let mut mass = [0.0f64; 8];
    for (q, s) in s.iter().enumerate() {
        for (d, row) in pairs.iter_mut().enumerate() {
            for i in 0..8 {
                let r = i + d + 1;
                row[i] += (s[0][i] * s[0][r] + s[1][i] * s[1][r] + s[2][i] * s[2][r]) * w[q];
            }
        }
        for (i, o) in opposite.iter_mut().enumerate() {
            let r = i + 4;
            *o += (s[0][i] * s[0][r] + s[1][i] * s[1][r] + s[2][i] * s[2][r]) * w[q];
        }
        for (mc, n) in mass.iter_mut().zip(&t.value[q]) {
            *mc += n * det[q];
        }
    }
    for (kk, &[i, j]) in k[..28].iter_mut().zip(super::CellType::Hexahedron.couplings()) {
        let (i, j) = (i as usize, j as usize);
        // The pair's lane: from the lower corner where j − i ≤ 4, else from j round to i.
        *kk = match j - i {
            4 => opposite[i],
            d if d < 4 => pairs[d - 1][i],
            d => pairs[8 - d - 1][j],
        };
    }
    m[..8].copy_from_slice(&mass);
}

#[cfg(test)]
mod tests {
    use super::super::tensor::hex_stiffness_and_mass_by_points;
    use super::Lanes;

    /// Distorted hexahedra (corners of the unit cube moved by up to 0.2 or 0.75 of its side,
    /// some cells inverted): the lanes' K and V are bitwise the point-by-point formulation's,
    /// compiled for the baseline and (where the processor has it, inside `Lanes::run`) for AVX2,
    /// and so is the kernel with either choice of lanes.
    #[test]
    fn the_lanes_are_the_point_by_point_kernel_bitwise() {
        let cube = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]];
        let mut seed = 987654321u64;
        let mut jitter = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut nonzero = 0;
        for cell in 0..2000 {
            let size = if cell % 2 == 0 { 0.4 } else { 1.5 };
            let p: [[f64; 3]; 8] = cube.map(|c| c.map(|x| 1e3 * (x + size * jitter())));
            let (mut k0, mut m0) = ([0.0; 28], [0.0; 8]);
            hex_stiffness_and_mass_by_points(&p, &mut k0, &mut m0);
            let bits = |k: &[f64; 28], m: &[f64; 8]| k.iter().chain(m).map(|x| x.to_bits()).collect::<Vec<_>>();
            let (mut k1, mut m1) = ([0.0; 28], [0.0; 8]);
            super::lanes(&p, &mut k1, &mut m1);
            assert_eq!(bits(&k1, &m1), bits(&k0, &m0), "cell {cell}");
            for with in [Lanes::Baseline, Lanes::Avx2, Lanes::detect()] {
                let (mut k2, mut m2) = ([0.0; 28], [0.0; 8]);
                super::stiffness_and_mass(&p, &mut k2, &mut m2, with);
                assert_eq!(bits(&k2, &m2), bits(&k0, &m0), "cell {cell}, {with:?}");
            }
            let (mut k3, mut m3) = ([0.0; 28], [0.0; 8]);
            let with = Lanes::detect();
            with.run(|| super::stiffness_and_mass(&p, &mut k3, &mut m3, with));
            assert_eq!(bits(&k3, &m3), bits(&k0, &m0), "cell {cell}, {with:?} run");
            nonzero += k0.iter().filter(|x| **x != 0.0).count();
        }
        assert!(nonzero > 2000 * 20);
    }
}
