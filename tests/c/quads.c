/* A 16 x 16 QUAD mesh of the unit square built from the test's own arrays through the generic
 * meshmove_mesh_create, its boundary moved by a linear field d(x, y) = A (x, y) + b: the
 * biharmonic and the Laplacian reproduce a linear field exactly (bilinear Q1 elements), so every
 * interior vertex must get it too (to 1e-10). */
#include <math.h>
#include <stdio.h>
#include "../../c_examples/box_grid.h"

static double linear(int k, double x, double y) {
    return k == 0 ? 0.01 + 0.05 * x - 0.02 * y : -0.03 + 0.04 * x + 0.06 * y;
}

/* Solves with `method`; 0 when every vertex has the linear field. */
static int solve(meshmove_mesh *mesh, const box_grid *g, int32_t method) {
    meshmove_bcs *bcs = NULL;
    meshmove_options *o = NULL;
    meshmove_solver *s = NULL;
    meshmove_report rep;
    double *d = malloc(sizeof(double) * 2 * (size_t)g->nv), worst = 0.0;
    int32_t v, k, bad = 0;
    if (meshmove_bcs_create(&bcs) || meshmove_options_create(&o) || meshmove_options_set_method(o, method) ||
        meshmove_options_set_tol(o, 1e-12) || meshmove_solver_create(mesh, bcs, o, &s)) {
        fprintf(stderr, "quads: setting up the solver: %s\n", meshmove_last_error());
        bad = 1;
    }
    for (v = 0; !bad && v < g->nv; v++)
        for (k = 0; k < 2; k++) d[2 * v + k] = linear(k, g->xy[2 * v], g->xy[2 * v + 1]);
    if (!bad && meshmove_solver_solve(s, 2 * g->nv, d, NULL, d, &rep) != MESHMOVE_STATUS_OK) {
        fprintf(stderr, "quads: solve: %s\n", meshmove_last_error());
        bad = 1;
    }
    for (v = 0; !bad && v < g->nv; v++)
        for (k = 0; k < 2; k++) worst = fmax(worst, fabs(d[2 * v + k] - linear(k, g->xy[2 * v], g->xy[2 * v + 1])));
    if (!bad) printf("  method %d: %d cycles, largest error %.2e\n", method, rep.cycles, worst);
    if (worst > 1e-10) bad = 1;
    if (meshmove_solver_free(s) || meshmove_options_free(o) || meshmove_bcs_free(bcs)) bad = 1;
    free(d);
    return bad;
}

int main(void) {
    box_grid g;
    meshmove_mesh *mesh = NULL;
    meshmove_status st;
    int failed = 0;
    int32_t sizes[6];
    box_grid_make(&g, 16, 16, (const double[]){0.0, 1.0, 0.0, 1.0}, 1, (const int32_t[]){1, 2, 3, 4});
    st = box_grid_mesh(&g, &mesh);
    if (st != MESHMOVE_STATUS_OK) {
        fprintf(stderr, "quads: mesh_create returned %s: %s\n", meshmove_status_name(st), meshmove_last_error());
        box_grid_free(&g);
        return 1;
    }
    if (meshmove_mesh_sizes(mesh, &sizes[0], &sizes[1], &sizes[2], &sizes[3], &sizes[4], &sizes[5]) ||
        sizes[0] != 2 || sizes[1] != 289 || sizes[2] != 256 || sizes[3] != 1024 || sizes[4] != 64 || sizes[5] != 128) {
        fprintf(stderr, "quads: sizes %d %d %d %d %d %d\n", sizes[0], sizes[1], sizes[2], sizes[3], sizes[4], sizes[5]);
        failed = 1;
    }
    failed |= solve(mesh, &g, MESHMOVE_METHOD_BIHARMONIC);
    failed |= solve(mesh, &g, MESHMOVE_METHOD_LAPLACIAN);
    if (meshmove_mesh_free(mesh)) failed = 1;
    box_grid_free(&g);
    printf("quads: %s\n", failed ? "FAILED" : "ok");
    return failed;
}
