/* Wall-layered meshes through the C ABI: a NACA 0012 with 30 quad layers from a first height of
 * 1e-5 (2D) and a prolate spheroid with 10 wedge layers from 1e-4 and tetrahedra outside (3D),
 * their wall (patch 1) CLAMPED and pitched by 10 degrees as a rigid body, the far field (patch 2)
 * FIXED, by every method through meshmove_solver_move:
 *   - no call fails with a panic or any status other than OK, INVERTED (the Laplacian and the
 *     spring may fold the thin layers), NOT_CONVERGED or DIVERGED, and each says which;
 *   - the biharmonic returns OK, no inverted cell, and the cells on the wall (the first layer)
 *     keep their volume within 1 %.
 * Usage: viscous tests/data/viscous_airfoil_22.msh tests/data/viscous_spheroid_22.msh */
#include <math.h>
#include <string.h>
#include "../../c_examples/check.h"

/* Signed volume of the tetrahedron (a, b, c, d). */
static double tet(const double *a, const double *b, const double *c, const double *d) {
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
}

/* Signed measure of a cell of the first layer (quad in 2D, wedge in 3D; anything else: NaN),
 * the same formula before and after, so their ratio is the cell's volume ratio. */
static double measure(int32_t dim, int32_t type, const int32_t *v, const double *x) {
    if (dim == 2 && type == MESHMOVE_CELL_TYPE_QUAD) {
        double a = 0.0;
        for (int k = 0; k < 4; k++) {
            const double *p = x + 2 * v[k], *q = x + 2 * v[(k + 1) % 4];
            a += p[0] * q[1] - p[1] * q[0];
        }
        return 0.5 * a;
    }
    if (dim == 3 && type == MESHMOVE_CELL_TYPE_WEDGE) {
#define P(k) (x + 3 * v[k])
        return tet(P(0), P(1), P(2), P(5)) + tet(P(0), P(1), P(5), P(4)) + tet(P(0), P(4), P(5), P(3));
#undef P
    }
    return NAN;
}

static int run(const char *path) {
    const double pi = 3.14159265358979323846, pitch = -10.0 * pi / 180.0;
    meshmove_mesh *mesh = NULL;
    CHECK(meshmove_mesh_read_msh(path, &mesh));
    int32_t dim, nv, nc, ncv;
    CHECK(meshmove_mesh_sizes(mesh, &dim, &nv, &nc, &ncv, NULL, NULL));
    size_t n = (size_t)dim * (size_t)nv;
    double *x0 = malloc(sizeof(double) * n), *x = malloc(sizeof(double) * n);
    double *zero = calloc(n, sizeof(double));
    int32_t *off = malloc(sizeof(int32_t) * (size_t)(nc + 1)), *con = malloc(sizeof(int32_t) * (size_t)ncv);
    int32_t *types = malloc(sizeof(int32_t) * (size_t)nc);
    CHECK(meshmove_mesh_get_coords(mesh, (int32_t)n, x0));
    CHECK(meshmove_mesh_get_cells(mesh, 0, nc + 1, off, ncv, con, nc, types));
    int32_t nw = 0;
    if (meshmove_mesh_patch_vertices(mesh, 1, 0, 0, NULL, &nw) != MESHMOVE_STATUS_BUFFER_TOO_SMALL || nw <= 0) {
        fprintf(stderr, "%s: no wall (patch 1)\n", path);
        return 1;
    }
    int32_t *wall = malloc(sizeof(int32_t) * (size_t)nw);
    char *on_wall = calloc((size_t)nv, 1);
    CHECK(meshmove_mesh_patch_vertices(mesh, 1, 0, nw, wall, &nw));
    for (int32_t i = 0; i < nw; i++) on_wall[wall[i]] = 1;
    /* The first layer: the cells with a vertex on the wall. */
    int32_t first = 0;
    for (int32_t c = 0; c < nc; c++) {
        for (int32_t k = off[c]; k < off[c + 1]; k++) {
            if (on_wall[con[k]]) {
                first++;
                break;
            }
        }
    }
    const double center2[2] = {0.25, 0.0}, center3[3] = {0.0, 0.0, 0.0};
    const double t2[2] = {0.0, 0.0}, t3[3] = {0.0, 0.0, 0.0};
    const double rot2[1] = {pitch}, rot3[3] = {0.0, 0.0, pitch};
    const int32_t methods[3] = {MESHMOVE_METHOD_BIHARMONIC, MESHMOVE_METHOD_LAPLACIAN, MESHMOVE_METHOD_SPRING};
    const char *names[3] = {"biharmonic", "laplacian", "spring"};
    int failed = 0;
    for (int m = 0; m < 3; m++) {
        meshmove_bcs *bcs = NULL;
        meshmove_options *o = NULL;
        meshmove_solver *s = NULL;
        CHECK(meshmove_bcs_create(&bcs));
        CHECK(meshmove_bcs_set_kinds(bcs, 1, MESHMOVE_KIND_CLAMPED));
        CHECK(meshmove_bcs_set_kinds(bcs, 2, MESHMOVE_KIND_FIXED));
        CHECK(meshmove_options_create(&o));
        CHECK(meshmove_options_set_method(o, methods[m]));
        CHECK(meshmove_solver_create(mesh, bcs, o, &s));
        if (dim == 2) {
            CHECK(meshmove_solver_set_rigid_motion(s, 1, t2, rot2, center2));
        } else {
            CHECK(meshmove_solver_set_rigid_motion(s, 1, t3, rot3, center3));
        }
        memcpy(x, x0, sizeof(double) * n);
        meshmove_report rep;
        meshmove_quality q;
        memset(&rep, 0, sizeof rep);
        memset(&q, 0, sizeof q);
        meshmove_status st = meshmove_solver_move(s, (int32_t)n, zero, x, &rep, &q);
        printf("%s %s: %s, %d iterations, %d inverted, min volume ratio %.4f\n", path, names[m],
               meshmove_status_name(st), rep.cycles, q.inverted, q.min_volume_ratio);
        if (st != MESHMOVE_STATUS_OK && st != MESHMOVE_STATUS_INVERTED && st != MESHMOVE_STATUS_NOT_CONVERGED &&
            st != MESHMOVE_STATUS_DIVERGED) {
            fprintf(stderr, "%s %s: unexpected status %s: %s\n", path, names[m], meshmove_status_name(st),
                    meshmove_last_error());
            failed = 1;
        }
        if (methods[m] == MESHMOVE_METHOD_BIHARMONIC) {
            double lo = INFINITY, hi = -INFINITY;
            for (int32_t c = 0; c < nc; c++) {
                int touches = 0;
                for (int32_t k = off[c]; k < off[c + 1]; k++) touches |= on_wall[con[k]];
                if (!touches) continue;
                double r = measure(dim, types[c], con + off[c], x) / measure(dim, types[c], con + off[c], x0);
                lo = fmin(lo, r);
                hi = fmax(hi, r);
            }
            printf("  first layer: %d cells, volume ratio %.6f .. %.6f\n", first, lo, hi);
            if (st != MESHMOVE_STATUS_OK || q.inverted != 0 || !(q.min_volume_ratio > 0.0) || !(lo > 0.99) ||
                !(hi < 1.01)) {
                fprintf(stderr, "%s biharmonic: status %s, %d inverted, first layer %g .. %g\n", path,
                        meshmove_status_name(st), q.inverted, lo, hi);
                failed = 1;
            }
        }
        CHECK(meshmove_solver_free(s));
        CHECK(meshmove_options_free(o));
        CHECK(meshmove_bcs_free(bcs));
    }
    CHECK(meshmove_mesh_free(mesh));
    free(x0);
    free(x);
    free(zero);
    free(off);
    free(con);
    free(types);
    free(wall);
    free(on_wall);
    return failed;
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: viscous airfoil.msh spheroid.msh\n");
        return 2;
    }
    int failed = run(argv[1]);
    failed |= run(argv[2]);
    if (failed) return 1;
    printf("viscous: ok\n");
    return 0;
}
