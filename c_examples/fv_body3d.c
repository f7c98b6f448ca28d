/* A small cell-centred finite-volume code in 3D: a passive scalar carried by an incompressible
 * flow (upwind, ALE form) around a cube that pitches, theta(t) = 10 deg sin(2 pi t / 20), a rigid
 * rotation about the y axis through its centre. The code owns its mesh: the box [-1,1]^3 as a
 * 16^3 grid of hexahedra without the 4^3 cells of the body [-0.25,0.25]^3 (made below, handed to
 * meshmove as arrays through the generic meshmove_mesh_create), walls FIXED, body CLAMPED. Every
 * time step is ONE call,
 *     meshmove_solver_set_rigid_motion(solver, BODY, t, (0, dtheta, 0), centre);
 *     meshmove_solver_move(solver, 3 * nv, boundary_displacement, xyz, &report, &quality);
 * the rigid motion turning the body (and its held wall layer) by this step's angle.
 *
 * The finite-volume part works on the code's own faces (quads, each split into two triangles
 * along the diagonal through its lowest vertex, the same split for both cells). Each step:
 *  - swept volumes: the volume each face sweeps between the old and the moved mesh (the closed
 *    surface of the old and the new triangles and the quads their edges sweep); per cell they add
 *    up to its volume change (the discrete geometric conservation law, checked);
 *  - the flow: the fluid volume through each face is a circulation of edge values (a discrete
 *    vector potential), so every cell's net outflow is zero by construction. Its edge values are
 *    the volume an edge sweeps under the body's rotation, blended from 1 at the body to 0 at the
 *    walls, plus a swirl about z blended the other way: on the body's faces the fluid moves with
 *    the body, on the walls it does not cross them (both checked);
 *  - upwind transport of the ALE fluxes (fluid volume minus swept volume) of two scalars: a blob
 *    and the constant 1.
 * Checks every step: the cells fill the box minus the body (volume to 1e-12 relative), no cell
 * inverted, the GCL, the scalar's total (sum phi V) conserved to 1e-12 relative, the constant
 * stays 1 to 1e-12 (free-stream preservation on the moving mesh), the blob stays in [0, 1]
 * (upwind at a Courant number below 1, also checked).
 * Usage: fv_body3d OUT.vtu [STEPS]   (ctest compares OUT.vtu with the Rust library's result) */
#include <math.h>
#include <string.h>
#include "check.h"

#define N 16         /* cells per side of the box */
#define LO 6         /* the body is grid cells LO .. HI-1 in each direction */
#define HI 10
#define STEPS 20     /* one period of the pitching */
enum { WALL = 1, BODY = 2 };

/* The faces of a VTK hexahedron (local corners, right-hand normal out of the cell) and the grid
 * direction of the neighbour behind each. */
static const int HEX_FACE[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
static const int HEX_DIR[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};

typedef struct {
    int32_t v[4];   /* vertices, right-hand normal out of c0 */
    int32_t c0, c1; /* c1 = -1 on the boundary */
} face;

typedef struct {
    int32_t nv, nc, ntag, nf;
    double *xyz;       /* 3 nv */
    int32_t *cells;    /* 8 nc, VTK hexahedron order */
    int32_t *types;    /* nc */
    int32_t *tagged;   /* 4 ntag: the boundary quads, as meshmove's tagged faces */
    int32_t *patch;    /* ntag */
    int32_t *offsets;  /* ntag + 1 */
    face *faces;       /* nf: the finite-volume code's faces, interior ones once (from the lower cell) */
    double *g;         /* nv: the flow's blend, 1 on the body, 0 on the walls */
} body_grid;

static int hole_cell(int i, int j, int k) { return i >= LO && i < HI && j >= LO && j < HI && k >= LO && k < HI; }
static int hole_vertex(int i, int j, int k) { return i > LO && i < HI && j > LO && j < HI && k > LO && k < HI; }
static int inside(int i, int j, int k) { return i >= 0 && i < N && j >= 0 && j < N && k >= 0 && k < N; }

/* The grid: vertices (i, j, k), 0 <= i, j, k <= N, numbered with i fastest, then j, then k,
 * skipping those inside the body, at x = -1 + 2 i / N (same for y, z); cells (i, j, k) in the
 * same order, skipping the body's, corners (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k) and the same
 * at k+1; tagged faces: for each cell in order, each of its faces in HEX_FACE order whose
 * neighbour is outside the box (WALL) or in the body (BODY). examples/reference_case.rs makes
 * the same. */
static void make_grid(body_grid *g) {
    int32_t *vid = malloc(sizeof(int32_t) * (N + 1) * (N + 1) * (N + 1));
    int32_t *cid = malloc(sizeof(int32_t) * N * N * N);
    int i, j, k, l, n;
    g->nv = g->nc = g->ntag = g->nf = 0;
    g->xyz = malloc(sizeof(double) * 3 * (N + 1) * (N + 1) * (N + 1));
    g->g = malloc(sizeof(double) * (N + 1) * (N + 1) * (N + 1));
    g->cells = malloc(sizeof(int32_t) * 8 * N * N * N);
    g->types = malloc(sizeof(int32_t) * N * N * N);
    g->tagged = malloc(sizeof(int32_t) * 4 * 6 * N * N * 2);
    g->patch = malloc(sizeof(int32_t) * 6 * N * N * 2);
    g->offsets = malloc(sizeof(int32_t) * (6 * N * N * 2 + 1));
    g->faces = malloc(sizeof(face) * 3 * (N + 1) * N * N);
    for (k = 0; k <= N; k++)
        for (j = 0; j <= N; j++)
            for (i = 0; i <= N; i++) {
                int32_t *id = &vid[(k * (N + 1) + j) * (N + 1) + i];
                int m = abs(i - N / 2);
                if (hole_vertex(i, j, k)) {
                    *id = -1;
                    continue;
                }
                *id = g->nv++;
                g->xyz[3 * *id] = -1.0 + 2.0 * i / N;
                g->xyz[3 * *id + 1] = -1.0 + 2.0 * j / N;
                g->xyz[3 * *id + 2] = -1.0 + 2.0 * k / N;
                if (abs(j - N / 2) > m) m = abs(j - N / 2);
                if (abs(k - N / 2) > m) m = abs(k - N / 2);
                /* the max-norm distance in cells: N/2 - LO on the body, N/2 on the walls */
                g->g[*id] = (double)(N / 2 - m) / (N / 2 - (HI - LO) / 2);
            }
    for (k = 0; k < N; k++)
        for (j = 0; j < N; j++)
            for (i = 0; i < N; i++) {
                int32_t c;
                if (hole_cell(i, j, k)) {
                    cid[(k * N + j) * N + i] = -1;
                    continue;
                }
                c = cid[(k * N + j) * N + i] = g->nc++;
                for (l = 0; l < 8; l++) {
                    int di = l == 1 || l == 2 || l == 5 || l == 6, dj = l == 2 || l == 3 || l == 6 || l == 7;
                    int dk = l >= 4;
                    g->cells[8 * c + l] = vid[((k + dk) * (N + 1) + j + dj) * (N + 1) + i + di];
                }
                g->types[c] = MESHMOVE_CELL_TYPE_HEXAHEDRON;
            }
    for (k = 0; k < N; k++)
        for (j = 0; j < N; j++)
            for (i = 0; i < N; i++) {
                int32_t c = cid[(k * N + j) * N + i];
                if (c < 0) continue;
                for (n = 0; n < 6; n++) {
                    int a = i + HEX_DIR[n][0], b = j + HEX_DIR[n][1], d = k + HEX_DIR[n][2];
                    int32_t nb = inside(a, b, d) ? cid[(d * N + b) * N + a] : -1;
                    face f;
                    for (l = 0; l < 4; l++) f.v[l] = g->cells[8 * c + HEX_FACE[n][l]];
                    f.c0 = c;
                    f.c1 = nb;
                    if (nb > c || nb < 0) g->faces[g->nf++] = f; /* an interior face once, from its lower cell */
                    if (nb >= 0) continue;
                    memcpy(&g->tagged[4 * g->ntag], f.v, sizeof f.v);
                    g->patch[g->ntag++] = inside(a, b, d) ? BODY : WALL;
                }
            }
    for (n = 0; n <= g->ntag; n++) g->offsets[n] = 4 * n;
    free(vid), free(cid);
}

static void free_grid(body_grid *g) {
    free(g->xyz), free(g->cells), free(g->types), free(g->tagged), free(g->patch), free(g->offsets);
    free(g->faces), free(g->g);
}

/* Signed volume of the tetrahedron (o, a, b, c). */
static double tet(const double *o, const double *a, const double *b, const double *c) {
    double u[3] = {a[0] - o[0], a[1] - o[1], a[2] - o[2]}, v[3] = {b[0] - o[0], b[1] - o[1], b[2] - o[2]};
    double w[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) /
           6.0;
}

/* The two triangles of a quad, split along the diagonal through its lowest vertex. */
static void split(const int32_t *v, int32_t t[2][3]) {
    int m = 0, l;
    for (l = 1; l < 4; l++)
        if (v[l] < v[m]) m = l;
    t[0][0] = t[1][0] = v[m];
    t[0][1] = v[(m + 1) % 4], t[0][2] = t[1][1] = v[(m + 2) % 4], t[1][2] = v[(m + 3) % 4];
}

/* Volume swept (relative to origin o) by the edge p -> q moving from x0 to x1: the quad
 * p, q, q', p' split along the diagonal from the lower vertex's old to the higher one's new
 * position, the same split whichever way the edge runs. */
static double edge_sweep(const double *o, const double *x0, const double *x1, int32_t p, int32_t q) {
    const double *p0 = x0 + 3 * p, *q0 = x0 + 3 * q, *p1 = x1 + 3 * p, *q1 = x1 + 3 * q;
    return p < q ? tet(o, p0, q0, q1) + tet(o, p0, q1, p1) : tet(o, p0, q0, p1) + tet(o, q0, q1, p1);
}

/* Volume a face sweeps to the side of its normal moving from x0 to x1: per triangle, the closed
 * surface of the new triangle, the old one reversed and the quads its edges sweep. */
static double swept(const face *f, const double *x0, const double *x1) {
    int32_t t[2][3];
    double s = 0.0;
    split(f->v, t);
    for (int h = 0; h < 2; h++) {
        const int32_t *r = t[h];
        const double *o = x0 + 3 * r[0];
        s += tet(o, x1 + 3 * r[0], x1 + 3 * r[1], x1 + 3 * r[2]) - tet(o, x0 + 3 * r[0], x0 + 3 * r[1], x0 + 3 * r[2]);
        for (int e = 0; e < 3; e++) s += edge_sweep(o, x0, x1, r[e], r[(e + 1) % 3]);
    }
    return s;
}

/* Cell volumes: the closed surface of the cell's split faces. */
static void volumes(const body_grid *g, const double *x, double *vol) {
    for (int32_t c = 0; c < g->nc; c++) {
        const int32_t *h = g->cells + 8 * c;
        const double *o = x + 3 * h[0];
        double v = 0.0;
        for (int n = 0; n < 6; n++) {
            int32_t q[4], t[2][3];
            for (int l = 0; l < 4; l++) q[l] = h[HEX_FACE[n][l]];
            split(q, t);
            for (int s = 0; s < 2; s++) v += tet(o, x + 3 * t[s][0], x + 3 * t[s][1], x + 3 * t[s][2]);
        }
        vol[c] = v;
    }
}

/* The flow's edge value (fluid volume circulating along the edge p -> q this step): the volume
 * the edge sweeps when the whole mesh x0 turns with the body (xr) about the body's centre,
 * weighted by g, plus a swirl about z weighted by 1 - g, whose potential (1 - x^2)(1 - y^2)
 * (1 - z^2) along z vanishes on the walls. Antisymmetric in p, q. */
static double psi(const body_grid *g, const double *x0, const double *xr, int32_t p, int32_t q) {
    static const double centre[3] = {0.0, 0.0, 0.0};
    const double swirl = 0.03;
    if (p > q) return -psi(g, x0, xr, q, p);
    const double *a = x0 + 3 * p, *b = x0 + 3 * q, ge = 0.5 * (g->g[p] + g->g[q]);
    double m[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
    return ge * edge_sweep(centre, x0, xr, p, q) +
           (1.0 - ge) * swirl * (1.0 - m[0] * m[0]) * (1.0 - m[1] * m[1]) * (1.0 - m[2] * m[2]) * (b[2] - a[2]);
}

int main(int argc, char **argv) {
    const char *vtu = argc > 1 ? argv[1] : "fv_body3d.vtu";
    const int steps = argc > 2 ? atoi(argv[2]) : STEPS;
    const double pi = 3.14159265358979323846, amp = 10.0 * pi / 180.0, w = 2.0 * pi / STEPS;
    const double zero[3] = {0.0, 0.0, 0.0}, centre[3] = {0.0, 0.0, 0.0};
    const double body = pow(2.0 * (HI - LO) / N, 3), domain = 8.0 - body;
    if (steps < 1) {
        fprintf(stderr, "usage: fv_body3d OUT.vtu [STEPS >= 1]\n");
        return 2;
    }
    body_grid g;
    make_grid(&g);
    const int32_t nv = g.nv, nc = g.nc;
    meshmove_mesh *mesh = NULL;
    CHECK(meshmove_mesh_create(3, nv, g.xyz, nc, NULL, 8 * nc, g.cells, g.types, g.ntag, g.offsets, 4 * g.ntag,
                               g.tagged, g.patch, NULL, 0, &mesh));
    meshmove_bcs *bcs = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, WALL, MESHMOVE_KIND_FIXED));
    CHECK(meshmove_bcs_set_kinds(bcs, BODY, MESHMOVE_KIND_CLAMPED));
    meshmove_solver *solver = NULL;
    CHECK(meshmove_solver_create(mesh, bcs, NULL, &solver)); /* the default options: biharmonic */

    double *xyz = malloc(sizeof(double) * 3 * (size_t)nv), *xo = malloc(sizeof(double) * 3 * (size_t)nv);
    double *xr = malloc(sizeof(double) * 3 * (size_t)nv);
    double *bd = calloc(3 * (size_t)nv, sizeof(double)); /* walls and body: nothing beyond the rigid motion */
    double *vo = malloc(sizeof(double) * (size_t)nc), *vn = malloc(sizeof(double) * (size_t)nc);
    double *q = malloc(sizeof(double) * (size_t)nc), *one = malloc(sizeof(double) * (size_t)nc);
    double *phi = malloc(sizeof(double) * (size_t)nc), *phi1 = malloc(sizeof(double) * (size_t)nc);
    double *gcl = malloc(sizeof(double) * (size_t)nc), *outflow = malloc(sizeof(double) * (size_t)nc);
    memcpy(xyz, g.xyz, sizeof(double) * 3 * (size_t)nv);
    volumes(&g, xyz, vo);
    double total0 = 0.0, q0 = 0.0;
    for (int32_t c = 0; c < nc; c++) {
        /* the blob exp(-20 |x - (0.6, 0, 0)|^2) at the cell's first corner's cube centre */
        const double *p = xyz + 3 * g.cells[8 * c], h = 1.0 / N;
        double r2 = pow(p[0] + h - 0.6, 2) + pow(p[1] + h, 2) + pow(p[2] + h, 2);
        total0 += vo[c];
        q[c] = exp(-20.0 * r2) * vo[c];
        one[c] = vo[c];
        q0 += q[c];
    }
    int failed = fabs(total0 - domain) > 1e-12 * domain;
    double worst_vol = 0.0, worst_gcl = 0.0, worst_wall = 0.0, worst_q = 0.0, worst_one = 0.0, min_ratio = 1e300;
    printf("fv_body3d: %d vertices, %d hexahedra, %d boundary faces, fluid volume %.15f (box - body %.15f)\n", nv,
           nc, g.ntag, total0, domain);
    for (int n = 1; n <= steps; n++) {
        /* The flow code's body motion: this step's pitch angle, about y through the centre. */
        double dth = amp * (sin(w * n) - sin(w * (n - 1)));
        double rot[3] = {0.0, dth, 0.0}, cs = cos(dth), sn = sin(dth);
        CHECK(meshmove_solver_set_rigid_motion(solver, BODY, zero, rot, centre));
        memcpy(xo, xyz, sizeof(double) * 3 * (size_t)nv);
        meshmove_report rep;
        meshmove_quality qual;
        CHECK(meshmove_solver_move(solver, 3 * nv, bd, xyz, &rep, &qual)); /* was: spring_move(xyz, bd) */

        volumes(&g, xyz, vn);
        for (int32_t i = 0; i < nv; i++) { /* the whole mesh turned with the body: the flow's potential */
            const double *p = xo + 3 * i;
            xr[3 * i] = cs * p[0] + sn * p[2], xr[3 * i + 1] = p[1], xr[3 * i + 2] = -sn * p[0] + cs * p[2];
        }
        double total = 0.0, wall = 0.0;
        int inverted = 0;
        for (int32_t c = 0; c < nc; c++) {
            total += vn[c];
            inverted += vn[c] <= 0.0;
            phi[c] = q[c] / vo[c];
            phi1[c] = one[c] / vo[c];
            gcl[c] = vo[c] - vn[c];
            outflow[c] = 0.0;
        }
        for (int32_t i = 0; i < g.nf; i++) {
            const face *f = &g.faces[i];
            double s = swept(f, xo, xyz), fluid = 0.0;
            for (int l = 0; l < 4; l++) fluid += psi(&g, xo, xr, f->v[l], f->v[(l + 1) % 4]);
            double vol = fluid - s; /* out of c0 through the moving face */
            gcl[f->c0] += s;
            if (f->c1 < 0) { /* no flow through the boundary: the fluid moves with it */
                if (fabs(vol) > wall) wall = fabs(vol);
                continue;
            }
            gcl[f->c1] -= s;
            int from_c0 = vol > 0.0;
            outflow[from_c0 ? f->c0 : f->c1] += fabs(vol);
            double carried = vol * (from_c0 ? phi[f->c0] : phi[f->c1]);
            double unit = vol * (from_c0 ? phi1[f->c0] : phi1[f->c1]);
            q[f->c0] -= carried, q[f->c1] += carried;
            one[f->c0] -= unit, one[f->c1] += unit;
        }
        double qtot = 0.0, pmin = 1e300, pmax = -1e300, dev1 = 0.0, dgcl = 0.0, courant = 0.0;
        for (int32_t c = 0; c < nc; c++) {
            courant = fmax(courant, outflow[c] / vo[c]);
            double p = q[c] / vn[c];
            qtot += q[c];
            pmin = fmin(pmin, p), pmax = fmax(pmax, p);
            dev1 = fmax(dev1, fabs(one[c] / vn[c] - 1.0));
            dgcl = fmax(dgcl, fabs(gcl[c]));
            vo[c] = vn[c];
        }
        double vol_err = fabs(total - domain) / domain, q_err = fabs(qtot - q0) / q0;
        worst_vol = fmax(worst_vol, vol_err), worst_gcl = fmax(worst_gcl, dgcl), worst_wall = fmax(worst_wall, wall);
        worst_q = fmax(worst_q, q_err), worst_one = fmax(worst_one, dev1);
        min_ratio = fmin(min_ratio, qual.min_volume_ratio);
        printf("  step %2d: pitch %6.2f deg, %d cycles, volume error %.1e, inverted %d, min volume ratio %.4f, "
               "min angle %5.2f, Courant %.2f, scalar %.12f in [%.3f, %.3f]\n",
               n, amp * sin(w * n) * 180.0 / pi, rep.cycles, vol_err, inverted, qual.min_volume_ratio,
               qual.min_angle_deg, courant, qtot, pmin, pmax);
        if (vol_err > 1e-12 || q_err > 1e-12 || dev1 > 1e-12 || inverted || qual.inverted || !rep.converged) failed = 1;
        /* upwind at a Courant number below 1 is monotone: the blob stays within its first bounds */
        if (pmin < -1e-12 || pmax > 1.0 || courant >= 1.0) failed = 1;
    }
    if (worst_gcl > 1e-12 || worst_wall > 1e-12) failed = 1;
    printf("  worst: volume error %.2e, GCL defect %.2e, boundary flux %.2e, scalar total %.2e, constant %.2e; "
           "min volume ratio %.4f -> %s\n",
           worst_vol, worst_gcl, worst_wall, worst_q, worst_one, min_ratio, failed ? "FAILED" : "ok");
    CHECK(meshmove_solver_write_vtu(solver, vtu, 0, NULL));

    CHECK(meshmove_solver_free(solver));
    CHECK(meshmove_bcs_free(bcs));
    CHECK(meshmove_mesh_free(mesh));
    free_grid(&g);
    free(xyz), free(xo), free(xr), free(bd), free(vo), free(vn), free(q), free(one), free(phi), free(phi1), free(gcl);
    free(outflow);
    return failed;
}
