//! The trilinear hexahedron's stiffness and lumped mass (2×2×2 Gauss) in the modal basis of the
//! trilinear space: the monomials 1, ξ, η, ξη, ζ, ξζ, ηζ, ξηζ (mode m holds the variables of m's
//! bits: bit 0 ξ, bit 1 η, bit 2 ζ). A corner's shape function is φ_k = Σ_m H[m][k] m / 8, where
//! H[m][k] = m at corner k (±1), and the Gauss points sit at the same signs scaled by g = 1/√3,
//! so every change between corners, points and modes is one ±1 Walsh–Hadamard transform of
//! eight values (three butterfly stages over four pairs):
//! - the positions' modes A_m = Σ_k H[m][k] x_k give the Jacobian's column b at each point as
//!   the four modes that hold b, each scaled by its other variables' values there;
//! - at each point, with the cofactors C (det·J⁻ᵀ, columns c_b), M = CᵀC / det is symmetric,
//!   and the modes' stiffness Km_mn = Σ_q ∇m(q)ᵀ M_q ∇n(q) needs only M's six entries'
//!   moments over the points (their transforms), as every ∂_b m is a monomial and a square is
//!   1/3 at the points: 84 products in all;
//! - K = Hᵀ Km H / 64 by the transposed transform down Km's columns, a transpose and the
//!   transform down again (whole rows on the lanes), and the mass ∫φ_k = Σ_q φ_k(q) det_q by the forward transform of det and the transposed one back.
//!
//! About a third of the operations of the point-by-point formulation
//! (`tensor::hex_stiffness_and_mass_by_points`, the tests' reference, which forms the 24
//! transformed gradients at each point and their 28 dot products). The values differ from that
//! formulation's in the last bits only; they are the same on every processor: plain additions
//! and products in a fixed order, no fused multiply-add, compiled for AVX2's lanes where the
//! processor has them (chosen at run time, the same operations and roundings) and for the
//! baseline elsewhere.

/// Corner `k` of `tensor::HEX_REF` at binary index `BINARY[k]` (bit 0 set where ξ = 1, bit 1
/// where η = 1, bit 2 where ζ = 1); the map is its own inverse.
const BINARY: [usize; 8] = [0, 1, 3, 2, 4, 5, 7, 6];

/// The sign table of the points and the modes' scales, worked out once.
struct Tables {
    /// sign[r][q]: the monomial r at point q over g^|r| (±1).
    sign: [[f64; 8]; 8],
    /// g^|m| / 8 per mode m: a position mode's weight in the Jacobian, and the mass's scale.
    scale: [f64; 8],
    /// g^|m| / 64 per monomial m: the value of M's moment Σ_q M_q m(q) over its transform,
    /// with K's 1/64.
    moment: [f64; 8],
}

/// The kernel's `Tables`.
fn tables() -> &'static Tables {
    static TABLES: std::sync::OnceLock<Tables> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        let g = 1.0 / 3f64.sqrt();
        let pow_g = |bits: u32| (0..bits).fold(1.0, |x, _| x * g);
        let mut t = Tables { sign: [[0.0; 8]; 8], scale: [0.0; 8], moment: [0.0; 8] };
        for r in 0..8usize {
            t.scale[r] = pow_g(r.count_ones()) / 8.0;
            t.moment[r] = pow_g(r.count_ones()) / 64.0;
            for q in 0..8usize {
                // (−1) for every variable of r whose sign is negative at q.
                t.sign[r][q] = if (r & !q).count_ones() % 2 == 0 { 1.0 } else { -1.0 };
            }
        }
        t
    })
}

/// One butterfly stage of the ±1 transforms across the lanes, on the pairs (i, i + h):
/// forward (lo + hi, hi − lo), transposed (lo − hi, lo + hi). Written lane by lane (each lane
/// adds or subtracts its partner), so it runs as shuffles and whole-vector adds, never as
/// single lanes stored and read back as vectors.
#[inline(always)]
fn butterfly(v: &mut [f64; 8], h: usize, forward: bool) {
    let mut out = [0.0f64; 8];
    for (i, o) in out.iter_mut().enumerate() {
        let partner = v[i ^ h];
        *o = if (i & h == 0) == forward { v[i] + partner } else { v[i] - partner };
    }
    *v = out;
}

/// The ±1 transform v[m] ← Σ_k H[m][k] v[k] (binary order), in place.
#[inline(always)]
fn forward(v: &mut [f64; 8]) {
    for h in [1, 2, 4] {
        butterfly(v, h, true);
    }
}

/// The transposed transform v[k] ← Σ_m H[m][k] v[m] (binary order), in place.
#[inline(always)]
fn transposed(v: &mut [f64; 8]) {
    for h in [1, 2, 4] {
        butterfly(v, h, false);
    }
}

/// The transposed transform applied to eight rows at once: row k ← Σ_m H[m][k] row m.
#[inline(always)]
fn transposed_rows(v: &mut [[f64; 8]; 8]) {
    for h in [1, 2, 4] {
        for i in (0..8).filter(|i| i & h == 0) {
            let (upper, lower) = v.split_at_mut(i | h);
            for (lo, hi) in upper[i].iter_mut().zip(lower[0].iter_mut()) {
                (*lo, *hi) = (*lo - *hi, *lo + *hi);
            }
        }
    }
}

/// A shared variable's square at the Gauss points.
const THIRD: f64 = 1.0 / 3.0;
/// Two shared variables' squares at the Gauss points.
const NINTH: f64 = 1.0 / 9.0;

/// The modes' stiffness Km_mn = Σ_q ∇m(q)ᵀ M_q ∇n(q) (over 64) from M's moments `mo[entry][e]`
/// (entries 00, 11, 22, 01, 02, 12; e the monomial, with g^|e| / 64): for b in m and c in n,
/// ∂_b m ∂_c n is the monomial (m \ b) xor (n \ c) times 1/3 per variable the two share, so
/// each entry is a short sum of moments, written out term by term (84 in all). Symmetric; mode
/// 0's row and column are zero.
#[inline(always)]
fn modes_stiffness(mo: &[[f64; 8]; 6]) -> [[f64; 8]; 8] {
    let mut km = [[0.0f64; 8]; 8];
    km[1][1] = mo[0][0];
    km[1][2] = mo[3][0];
    km[1][3] = mo[0][2] + mo[3][1];
    km[1][4] = mo[4][0];
    km[1][5] = mo[0][4] + mo[4][1];
    km[1][6] = mo[3][4] + mo[4][2];
    km[1][7] = mo[0][6] + mo[3][5] + mo[4][3];
    km[2][2] = mo[1][0];
    km[2][3] = mo[3][2] + mo[1][1];
    km[2][4] = mo[5][0];
    km[2][5] = mo[3][4] + mo[5][1];
    km[2][6] = mo[1][4] + mo[5][2];
    km[2][7] = mo[3][6] + mo[1][5] + mo[5][3];
    km[3][3] = 2.0 * mo[3][3] + (mo[0][0] + mo[1][0]) * THIRD;
    km[3][4] = mo[4][2] + mo[5][1];
    km[3][5] = mo[0][6] + mo[4][3] + mo[3][5] + mo[5][0] * THIRD;
    km[3][6] = mo[3][6] + mo[1][5] + mo[5][3] + mo[4][0] * THIRD;
    km[3][7] = 2.0 * mo[3][7] + (mo[0][4] + mo[4][1] + mo[1][4] + mo[5][2]) * THIRD;
    km[4][4] = mo[2][0];
    km[4][5] = mo[4][4] + mo[2][1];
    km[4][6] = mo[5][4] + mo[2][2];
    km[4][7] = mo[4][6] + mo[5][5] + mo[2][3];
    km[5][5] = 2.0 * mo[4][5] + (mo[0][0] + mo[2][0]) * THIRD;
    km[5][6] = mo[4][6] + mo[5][5] + mo[2][3] + mo[3][0] * THIRD;
    km[5][7] = 2.0 * mo[4][7] + (mo[0][2] + mo[3][1] + mo[5][4] + mo[2][2]) * THIRD;
    km[6][6] = 2.0 * mo[5][6] + (mo[1][0] + mo[2][0]) * THIRD;
    km[6][7] = 2.0 * mo[5][7] + (mo[3][2] + mo[1][1] + mo[4][4] + mo[2][1]) * THIRD;
    km[7][7] = (2.0 * mo[3][3] + 2.0 * mo[4][5] + 2.0 * mo[5][6]) * THIRD + (mo[0][0] + mo[1][0] + mo[2][0]) * NINTH;

    mirror(&mut km, false);
    km
}

/// Copies the upper triangle of `km` onto the lower one, or (`swap`) swaps the two: a transpose.
#[allow(clippy::needless_range_loop)] // (i, j) and (j, i) of one matrix
#[inline(always)]
fn mirror(km: &mut [[f64; 8]; 8], swap: bool) {
    for i in 0..8 {
        for j in i + 1..8 {
            let upper = km[i][j];
            if swap {
                km[i][j] = km[j][i];
            }
            km[j][i] = upper;
        }
    }
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

/// The cofactors c_b = j_{b+1} × j_{b+2} (det·J⁻ᵀ = [c0 c1 c2]) and det J at the eight points
/// side by side, J's columns from the positions' modes.
#[inline(always)]
fn cofactors(p: &[[f64; 3]], t: &Tables) -> ([[[f64; 8]; 3]; 3], [f64; 8]) {
    let p = &p[..8];
    // The positions' modes, per component.
    let mut a = [[0.0f64; 8]; 3];
    for (corner, pk) in p.iter().enumerate() {
        for (ac, &x) in a.iter_mut().zip(pk) {
            ac[BINARY[corner]] = x;
        }
    }
    a.iter_mut().for_each(forward);
    // J's column b at point q: Σ over the modes r | b (r without b) of A_{r|b} g^|r| / 8 · ±1.
    let mut j = [[[0.0f64; 8]; 3]; 3];
    for (b, jb) in j.iter_mut().enumerate() {
        let bit = 1 << b;
        let others: [usize; 4] = {
            let (o1, o2) = (((bit << 1) | (bit >> 2)) & 7, ((bit << 2) | (bit >> 1)) & 7);
            [0, o1, o2, o1 | o2]
        };
        for (jba, ac) in jb.iter_mut().zip(&a) {
            let u = others.map(|r| ac[r | bit] * t.scale[r]);
            for (q, x) in jba.iter_mut().enumerate() {
                *x = u[0] + u[1] * t.sign[others[1]][q] + u[2] * t.sign[others[2]][q] + u[3] * t.sign[others[3]][q];
            }
        }
    }
    let mut c = [[[0.0f64; 8]; 3]; 3];
    for (b, cb) in c.iter_mut().enumerate() {
        let (s, u) = (&j[(b + 1) % 3], &j[(b + 2) % 3]);
        for (r, cr) in cb.iter_mut().enumerate() {
            let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
            for q in 0..8 {
                cr[q] = s[r1][q] * u[r2][q] - s[r2][q] * u[r1][q];
            }
        }
    }
    let mut det = [0.0f64; 8];
    for q in 0..8 {
        det[q] = j[0][0][q] * c[0][0][q] + j[0][1][q] * c[0][1][q] + j[0][2][q] * c[0][2][q];
    }
    (c, det)
}

/// The lumped mass ∫φ_i of the eight corners alone: `stiffness_and_mass`'s, bitwise.
pub(super) fn lumped_mass(p: &[[f64; 3]], m: &mut [f64]) {
    let t = tables();
    let (_, det) = cofactors(p, t);
    mass(det, t, m);
}

/// ∫φ_k = Σ_q φ_k(q) det_q: det's moments scaled by g^|m| / 8, transformed back to the corners.
#[inline(always)]
fn mass(mut det: [f64; 8], t: &Tables, m: &mut [f64]) {
    forward(&mut det);
    for (d, s) in det.iter_mut().zip(&t.scale) {
        *d *= s;
    }
    transposed(&mut det);
    for (corner, mc) in m[..8].iter_mut().enumerate() {
        *mc = det[BINARY[corner]];
    }
}

/// K_ij = ∫∇φ_i·∇φ_j for the 28 corner pairs in `CellType::Hexahedron.couplings()` order and
/// the lumped mass ∫φ_i of the eight corners (see the module's comment), inlined into the
/// caller's loop: called inside `Lanes::run` it runs on those lanes, with the same values on
/// any.
#[inline(always)]
pub(super) fn stiffness_and_mass(p: &[[f64; 3]], k: &mut [f64], m: &mut [f64]) {
    let t = tables();
    let (c, det) = cofactors(p, t);
    let mut w = [0.0f64; 8];
    for q in 0..8 {
        w[q] = 1.0 / det[q];
    }
    let mut moments = [[0.0f64; 8]; 6];
    for (e, (b, cc)) in [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)].into_iter().enumerate() {
        for q in 0..8 {
            moments[e][q] = (c[b][0][q] * c[cc][0][q] + c[b][1][q] * c[cc][1][q] + c[b][2][q] * c[cc][2][q]) * w[q];
        }
    }
    for mo in moments.iter_mut() {
        forward(mo);
        for (x, sc) in mo.iter_mut().zip(&t.moment) {
            *x *= sc;
        }
    }
    let mut km = modes_stiffness(&moments);
    // Kᵀ = Hᵀ (Hᵀ Km)ᵀ: the transform down Km's columns, a transpose, the transform down
    // again (whole rows at a time, on the lanes); K is symmetric, so its pairs are read from it.
    transposed_rows(&mut km);
    mirror(&mut km, true);
    transposed_rows(&mut km);
    for (kk, &[i, jj]) in k[..28].iter_mut().zip(super::CellType::Hexahedron.couplings()) {
        *kk = km[BINARY[i as usize]][BINARY[jj as usize]];
    }
    mass(det, t, m);
}

#[cfg(test)]
mod tests {
    use super::super::tensor::hex_stiffness_and_mass_by_points;
    use super::Lanes;

    /// Distorted hexahedra (corners of the unit cube moved by up to 0.2 or 0.75 of its side,
    /// some cells inverted, far from the origin): the modal K and V are the point-by-point
    /// formulation's to rounding (relative to the cell's largest entry), and the same bits
    /// compiled for the baseline and (where the processor has it, inside `Lanes::run`) for AVX2.
    #[test]
    fn the_modes_are_the_point_by_point_kernel() {
        let cube = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]];
        let mut seed = 987654321u64;
        let mut jitter = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut worst = 0.0f64;
        let mut nonzero = 0;
        for cell in 0..2000 {
            let size = if cell % 2 == 0 { 0.4 } else { 1.5 };
            let shift = [3.0, -7.0, 11.0];
            let p: [[f64; 3]; 8] = cube.map(|c| [0, 1, 2].map(|a| 1e3 * (c[a] + size * jitter()) + shift[a]));
            let (mut k0, mut m0) = ([0.0; 28], [0.0; 8]);
            hex_stiffness_and_mass_by_points(&p, &mut k0, &mut m0);
            let (mut k1, mut m1) = ([0.0; 28], [0.0; 8]);
            super::stiffness_and_mass(&p, &mut k1, &mut m1);
            let kmax = k0.iter().fold(0.0f64, |x, y| x.max(y.abs()));
            let mmax = m0.iter().fold(0.0f64, |x, y| x.max(y.abs()));
            for (x, y) in k1.iter().zip(&k0) {
                worst = worst.max((x - y).abs() / kmax);
            }
            for (x, y) in m1.iter().zip(&m0) {
                worst = worst.max((x - y).abs() / mmax);
            }
            let bits = |k: &[f64; 28], m: &[f64; 8]| k.iter().chain(m).map(|x| x.to_bits()).collect::<Vec<_>>();
            let with = Lanes::detect();
            let (mut k2, mut m2) = ([0.0; 28], [0.0; 8]);
            with.run(|| super::stiffness_and_mass(&p, &mut k2, &mut m2));
            assert_eq!(bits(&k2, &m2), bits(&k1, &m1), "cell {cell}, {with:?} run");
            nonzero += k0.iter().filter(|x| **x != 0.0).count();
        }
        assert!(worst < 1e-11, "largest difference {worst:e}");
        assert!(nonzero > 2000 * 20);
    }

    /// The unit cube's K and V in closed form: edge neighbours 0, face diagonals −1/12, the
    /// opposite corners −1/12 (with the 2×2×2 rule, exact for the trilinear element), mass 1/8.
    #[test]
    fn the_unit_cube() {
        let p = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.], [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.]];
        let (mut k, mut m) = ([0.0; 28], [0.0; 8]);
        super::stiffness_and_mass(&p, &mut k, &mut m);
        for (x, &[i, j]) in k.iter().zip(super::super::CellType::Hexahedron.couplings()) {
            let differ = (0..3).filter(|&a| p[i as usize][a] != p[j as usize][a]).count();
            let want = [0.0, 0.0, -1.0 / 12.0, -1.0 / 12.0][differ];
            assert!((x - want).abs() < 1e-15, "pair ({i}, {j}): {x} against {want}");
        }
        assert!(m.iter().all(|&x| (x - 0.125).abs() < 1e-16), "{m:?}");
    }
}
