/* A small cell-centred finite-volume code (a passive scalar advected by u = (1, 0) and diffused,
 * ALE form) on the box [0,2]x[-1,1] around a cylinder of diameter 1 at (1, 0) that oscillates
 * vertically, y_c(t) = 0.25 sin(2 pi t / 20). The code owns its mesh (an O-grid of triangles,
 * made below and handed to meshmove as arrays) and moves it every time step by ONE call,
 *     meshmove_solver_move(solver, 2 * nv, boundary_displacement, xy, &report, &quality);
 * exactly where a spring mover used to be called. The run is made with SPRING and then with
 * BIHARMONIC: the only difference is the method argument of run().
 *
 * Every step checks: the total cell area equals the domain area (to 1e-12 relative), no cell is
 * inverted, and the discrete geometric conservation law (swept face areas = cell area change).
 * Usage: fv_cylinder OUT_BIHARMONIC.vtu [OUT_SPRING.vtu] */
#include <math.h>
#include <string.h>
#include "check.h"

#define STEPS 20
#define NS 12          /* segments per side of the box */
#define NT (4 * NS)    /* vertices per ring */
#define NR 10          /* rings of cells between the cylinder and the box */
enum { WALL = 1, CYLINDER = 2 };

typedef struct {
    int32_t a, b;   /* vertices, a -> b with cell c0 on the left */
    int32_t c0, c1; /* c1 = -1 on the boundary */
} face;

static double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

static int cmp_key(const void *p, const void *q) {
    const int64_t *x = p, *y = q;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

/* Faces of the mesh from its (counter-clockwise) cells. */
static face *build_faces(int32_t nc, const int32_t *cells, int32_t nv, int32_t *nf_out) {
    int64_t *keys = malloc(sizeof(int64_t) * 2 * 3 * (size_t)nc);
    for (int32_t c = 0; c < nc; c++)
        for (int k = 0; k < 3; k++) {
            int64_t a = cells[3 * c + k], b = cells[3 * c + (k + 1) % 3];
            int64_t lo = a < b ? a : b, hi = a < b ? b : a;
            keys[2 * (3 * c + k)] = lo * nv + hi;
            keys[2 * (3 * c + k) + 1] = 3 * (int64_t)c + k;
        }
    qsort(keys, 3 * (size_t)nc, 2 * sizeof(int64_t), cmp_key);
    face *f = malloc(sizeof(face) * 3 * (size_t)nc);
    int32_t nf = 0;
    for (int32_t i = 0; i < 3 * nc;) {
        int64_t ck = keys[2 * i + 1];
        int32_t c = (int32_t)(ck / 3), k = (int32_t)(ck % 3);
        face fc = {cells[3 * c + k], cells[3 * c + (k + 1) % 3], c, -1};
        if (i + 1 < 3 * nc && keys[2 * (i + 1)] == keys[2 * i]) {
            fc.c1 = (int32_t)(keys[2 * (i + 1) + 1] / 3);
            i += 2;
        } else {
            i += 1;
        }
        f[nf++] = fc;
    }
    free(keys);
    *nf_out = nf;
    return f;
}

/* The O-grid: ring k (0 = the cylinder, NR = the box) has NT vertices, vertex k NT + t at the
 * blend (1 - s) c + s q of the cylinder's point c at angle -3 pi / 4 + 2 pi t / NT and the box's
 * point q at t / NS sides counter-clockwise from the corner (0, -1), s = k / NR. Each ring
 * quad (k, t), (k, t+1), (k+1, t+1), (k+1, t) is two counter-clockwise triangles. The cylinder's
 * and the box's edges are tagged CYLINDER and WALL. examples/reference_case.rs makes the same. */
static void o_grid(double *xy, int32_t *cells, int32_t *edges, int32_t *patches) {
    const double pi = 3.14159265358979323846;
    int32_t k, t, c = 0;
    for (k = 0; k <= NR; k++)
        for (t = 0; t < NT; t++) {
            double th = -0.75 * pi + 2.0 * pi * t / NT, u = 2.0 * (t % NS) / NS, s = (double)k / NR;
            double cx = 1.0 + 0.5 * cos(th), cy = 0.5 * sin(th), qx, qy;
            switch (t / NS) {
            case 0: qx = u, qy = -1.0; break;
            case 1: qx = 2.0, qy = -1.0 + u; break;
            case 2: qx = 2.0 - u, qy = 1.0; break;
            default: qx = 0.0, qy = 1.0 - u; break;
            }
            xy[2 * (k * NT + t)] = (1.0 - s) * cx + s * qx;
            xy[2 * (k * NT + t) + 1] = (1.0 - s) * cy + s * qy;
        }
    for (k = 0; k < NR; k++)
        for (t = 0; t < NT; t++) {
            int32_t a = k * NT + t, b = k * NT + (t + 1) % NT, d = a + NT, e = b + NT;
            int32_t tri[6] = {a, d, e, a, e, b};
            memcpy(&cells[3 * c], tri, sizeof tri);
            c += 2;
        }
    for (t = 0; t < NT; t++) {
        edges[2 * t] = t, edges[2 * t + 1] = (t + 1) % NT, patches[t] = CYLINDER;
        edges[2 * (NT + t)] = NR * NT + t, edges[2 * (NT + t) + 1] = NR * NT + (t + 1) % NT, patches[NT + t] = WALL;
    }
}

static void cell_geometry(int32_t nc, const int32_t *cells, const double *xy, double *area, double *cen) {
    for (int32_t c = 0; c < nc; c++) {
        const double *p = xy + 2 * cells[3 * c], *q = xy + 2 * cells[3 * c + 1], *r = xy + 2 * cells[3 * c + 2];
        area[c] = 0.5 * cross(q[0] - p[0], q[1] - p[1], r[0] - p[0], r[1] - p[1]);
        cen[2 * c] = (p[0] + q[0] + r[0]) / 3.0;
        cen[2 * c + 1] = (p[1] + q[1] + r[1]) / 3.0;
    }
}

/* Returns 0 when every check passed. */
static int run(int32_t method, const char *name, const char *vtu) {
    const double pi = 3.14159265358979323846, amp = 0.25, w = 2.0 * pi / STEPS;
    const double dt = 0.05, ux = 1.0, kappa = 1e-3;
    const int32_t nv = (NR + 1) * NT, nc = 2 * NR * NT, ncyl = NT; /* the cylinder: vertices 0 .. NT-1 */
    int32_t nf;
    double *xy = malloc(sizeof(double) * 2 * (size_t)nv), *xo = malloc(sizeof(double) * 2 * (size_t)nv);
    double *bd = calloc(2 * (size_t)nv, sizeof(double));
    int32_t *cells = malloc(sizeof(int32_t) * 3 * (size_t)nc), *edges = malloc(sizeof(int32_t) * 4 * NT);
    int32_t *patches = malloc(sizeof(int32_t) * 2 * NT);
    o_grid(xy, cells, edges, patches);
    meshmove_mesh *mesh = NULL;
    CHECK(meshmove_mesh_create_triangles(nv, xy, nc, cells, 0, 2 * NT, edges, patches, NULL, &mesh));
    face *faces = build_faces(nc, cells, nv, &nf);

    meshmove_bcs *bcs = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, WALL, MESHMOVE_KIND_FIXED));
    CHECK(meshmove_bcs_set_kinds(bcs, CYLINDER, MESHMOVE_KIND_CLAMPED));
    meshmove_options *opts = NULL;
    CHECK(meshmove_options_create(&opts));
    CHECK(meshmove_options_set_method(opts, method)); /* <- the one argument that changes */
    meshmove_solver *solver = NULL;
    CHECK(meshmove_solver_create(mesh, bcs, opts, &solver));
    CHECK(meshmove_options_free(opts));

    double *ao = malloc(sizeof(double) * (size_t)nc), *an = malloc(sizeof(double) * (size_t)nc);
    double *cen = malloc(sizeof(double) * 2 * (size_t)nc), *ceno = malloc(sizeof(double) * 2 * (size_t)nc);
    double *q = calloc((size_t)nc, sizeof(double)), *phi = calloc((size_t)nc, sizeof(double));
    double *swept_sum = malloc(sizeof(double) * (size_t)nc);
    cell_geometry(nc, cells, xy, ao, cen);
    double domain = 0.0;
    for (int32_t c = 0; c < nc; c++) domain += ao[c];
    int failed = 0;
    double worst_area = 0.0, worst_gcl = 0.0, min_ratio = 1e300;
    printf("fv_cylinder (%s): %d vertices, %d cells, domain area %.15f\n", name, nv, nc, domain);
    for (int n = 1; n <= STEPS; n++) {
        /* The flow code's boundary motion: the cylinder moves by dy this step. */
        double dy = amp * (sin(w * n) - sin(w * (n - 1)));
        memset(bd, 0, sizeof(double) * 2 * (size_t)nv);
        for (int32_t i = 0; i < ncyl; i++) bd[2 * i + 1] = dy;
        memcpy(xo, xy, sizeof(double) * 2 * (size_t)nv);
        memcpy(ceno, cen, sizeof(double) * 2 * (size_t)nc);

        meshmove_report rep;
        meshmove_quality qual;
        CHECK(meshmove_solver_move(solver, 2 * nv, bd, xy, &rep, &qual)); /* was: spring_move(xy, bd) */

        cell_geometry(nc, cells, xy, an, cen);
        double total = 0.0;
        int inverted = 0;
        for (int32_t c = 0; c < nc; c++) {
            total += an[c];
            inverted += an[c] <= 0.0;
            phi[c] = q[c] / ao[c];
            swept_sum[c] = 0.0;
        }
        /* ALE fluxes: volume through each face = dt u.n L - swept area (face moving outward). */
        for (int32_t i = 0; i < nf; i++) {
            const face *f = &faces[i];
            const double *a0 = xo + 2 * f->a, *b0 = xo + 2 * f->b, *a1 = xy + 2 * f->a, *b1 = xy + 2 * f->b;
            /* Area swept by the face a->b (cell c0 on its left) to its right, shoelace of a0 b0 b1 a1. */
            double swept = -0.5 * cross(b1[0] - a0[0], b1[1] - a0[1], a1[0] - b0[0], a1[1] - b0[1]);
            double mx = 0.5 * (a1[0] + b1[0] + a0[0] + b0[0]) * 0.5;
            double nx = 0.5 * ((b0[1] - a0[1]) + (b1[1] - a1[1])); /* outward normal of c0 times L, x part */
            double vol = dt * ux * nx - swept;                       /* out of c0 */
            swept_sum[f->c0] += swept;
            double pin; /* value carried by the volume */
            if (f->c1 >= 0) {
                swept_sum[f->c1] -= swept;
                pin = vol > 0.0 ? phi[f->c0] : phi[f->c1];
                double dx = ceno[2 * f->c1] - ceno[2 * f->c0], dyc = ceno[2 * f->c1 + 1] - ceno[2 * f->c0 + 1];
                double L = hypot(b0[0] - a0[0], b0[1] - a0[1]);
                double diff = dt * kappa * L * (phi[f->c1] - phi[f->c0]) / hypot(dx, dyc);
                q[f->c0] += diff - vol * pin;
                q[f->c1] -= diff - vol * pin;
            } else {
                pin = vol > 0.0 ? phi[f->c0] : (mx < 1e-9 ? 1.0 : 0.0); /* inflow at x = 0 carries 1 */
                q[f->c0] -= vol * pin;
            }
        }
        double qtot = 0.0, pmin = 1e300, pmax = -1e300;
        for (int32_t c = 0; c < nc; c++) {
            double gcl = fabs(swept_sum[c] - (an[c] - ao[c]));
            if (gcl > worst_gcl) worst_gcl = gcl;
            ao[c] = an[c];
            qtot += q[c];
            double p = q[c] / an[c];
            if (p < pmin) pmin = p;
            if (p > pmax) pmax = p;
        }
        double area_err = fabs(total - domain) / domain;
        if (area_err > worst_area) worst_area = area_err;
        if (qual.min_volume_ratio < min_ratio) min_ratio = qual.min_volume_ratio;
        printf("  step %2d: %2d cycles, area error %.1e, inverted %d, min area ratio %.4f, min angle %5.2f, "
               "scalar %.6f in [%.3f, %.3f]\n",
               n, rep.cycles, area_err, inverted, qual.min_volume_ratio, qual.min_angle_deg, qtot, pmin, pmax);
        if (area_err > 1e-12 || inverted || qual.inverted || !rep.converged) failed = 1;
    }
    if (worst_gcl > 1e-12) failed = 1;
    printf("  %s: worst area error %.2e, worst GCL defect %.2e, min area ratio %.4f -> %s\n", name, worst_area,
           worst_gcl, min_ratio, failed ? "FAILED" : "ok");
    if (vtu) CHECK(meshmove_solver_write_vtu(solver, vtu, 0, NULL));

    CHECK(meshmove_solver_free(solver));
    CHECK(meshmove_bcs_free(bcs));
    CHECK(meshmove_mesh_free(mesh));
    free(xy), free(xo), free(bd), free(cells), free(edges), free(patches), free(faces), free(ao), free(an), free(cen);
    free(ceno);
    free(q), free(phi), free(swept_sum);
    return failed;
}

int main(int argc, char **argv) {
    const char *bih = argc > 1 ? argv[1] : "fv_cylinder_biharmonic.vtu";
    const char *spr = argc > 2 ? argv[2] : NULL;
    int failed = run(MESHMOVE_METHOD_SPRING, "SPRING", spr);
    failed |= run(MESHMOVE_METHOD_BIHARMONIC, "BIHARMONIC", bih);
    return failed;
}
