/* A host that moves its mesh in several calls: the top of the unit square (triangles, 8 x 8
 * cells) moved up by 0.04 at x = 0.5 (a sine bump), in four meshmove_solver_move calls of a
 * quarter each (increments), then read back:
 *   - meshmove_solver_get_displacement: the last call's increment only;
 *   - meshmove_solver_get_total_displacement: the current positions minus the initial ones
 *     (bitwise), the full bump on the top;
 *   - meshmove_solver_total_quality: the area ratios against the initial mesh, further from 1
 *     than any single move's;
 *   - meshmove_solver_write_vtu(s, path, 0, NULL): the initial mesh moved by the total.
 * Usage: totals OUT.vtu */
#include <math.h>
#include <string.h>
#include "../../c_examples/check.h"

#define N 8
#define NV ((N + 1) * (N + 1))
#define FAIL(...)                                                                                  \
    do {                                                                                           \
        fprintf(stderr, __VA_ARGS__);                                                              \
        fprintf(stderr, "\n");                                                                     \
        return 1;                                                                                  \
    } while (0)

int main(int argc, char **argv) {
    const double pi = 3.14159265358979323846;
    static double xy[2 * NV], x0[2 * NV], inc[2 * NV], d[2 * NV], total[2 * NV];
    static int32_t cells[6 * N * N], edges[2 * N], patches[N];
    meshmove_mesh *mesh = NULL;
    meshmove_bcs *bcs = NULL;
    meshmove_solver *s = NULL;
    meshmove_quality q, qt;
    double worst_step = 1.0, top = 0.0;
    int i, j, k, c = 0;
    if (argc < 2) FAIL("usage: totals OUT.vtu");
    for (j = 0; j <= N; j++)
        for (i = 0; i <= N; i++) {
            xy[2 * (j * (N + 1) + i)] = (double)i / N;
            xy[2 * (j * (N + 1) + i) + 1] = (double)j / N;
        }
    for (j = 0; j < N; j++)
        for (i = 0; i < N; i++) {
            int32_t a = j * (N + 1) + i, b = a + 1, e = a + N + 1, f = e + 1;
            int32_t t[6] = {a, b, f, a, f, e};
            memcpy(cells + 6 * c++, t, sizeof t);
        }
    for (i = 0; i < N; i++) { /* the top, patch 2 */
        edges[2 * i] = N * (N + 1) + i;
        edges[2 * i + 1] = N * (N + 1) + i + 1;
        patches[i] = 2;
    }
    CHECK(meshmove_mesh_create_triangles(NV, xy, 2 * N * N, cells, 0, N, edges, patches, NULL, &mesh));
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_solver_create(mesh, bcs, NULL, &s));
    memcpy(x0, xy, sizeof xy);
    /* the increment of each call: a quarter of the bump on the top */
    for (k = 0; k < 2 * NV; k++) inc[k] = 0.0;
    for (i = 0; i <= N; i++) inc[2 * (N * (N + 1) + i) + 1] = 0.01 * sin(pi * (double)i / N);
    for (k = 0; k < 4; k++) {
        CHECK(meshmove_solver_move(s, 2 * NV, inc, xy, NULL, &q));
        if (q.min_volume_ratio < worst_step) worst_step = q.min_volume_ratio;
    }
    CHECK(meshmove_solver_get_displacement(s, 2 * NV, d));
    CHECK(meshmove_solver_get_total_displacement(s, 2 * NV, total));
    CHECK(meshmove_solver_total_quality(s, &qt));
    for (k = 0; k < 2 * NV; k++) {
        if (total[k] != xy[k] - x0[k]) FAIL("total displacement %d: %.17g, positions say %.17g", k, total[k], xy[k] - x0[k]);
    }
    /* the middle of the top: 0.04 in all, 0.01 in the last call */
    k = 2 * (N * (N + 1) + N / 2) + 1;
    top = total[k];
    if (fabs(top - 0.04) > 1e-15) FAIL("total at the top's middle %.17g, expected 0.04", top);
    if (fabs(d[k] - 0.01) > 1e-15) FAIL("last increment at the top's middle %.17g, expected 0.01", d[k]);
    /* against the initial mesh the cells under the bump stretch about four times as much */
    if (!(qt.max_volume_ratio - 1.0 > 3.0 * (q.max_volume_ratio - 1.0)))
        FAIL("total max area ratio %.6f, last move's %.6f", qt.max_volume_ratio, q.max_volume_ratio);
    if (qt.inverted != 0 || !(qt.min_angle_deg > 0.0)) FAIL("total quality: %d inverted", qt.inverted);
    /* Triangles: no negative area, and the corner Jacobian ratio is the area ratio. */
    if (qt.negative_volume_cells != 0 || fabs(qt.min_corner_jacobian_ratio - qt.min_volume_ratio) > 1e-12)
        FAIL("total quality: %d negative areas, corner Jacobian ratio %g, area ratio %g", qt.negative_volume_cells,
             qt.min_corner_jacobian_ratio, qt.min_volume_ratio);
    CHECK(meshmove_solver_write_vtu(s, argv[1], 0, NULL));
    printf("totals: top %.3f (last move %.3f), max area ratio %.4f in all, %.4f in the last move, min %.4f (worst move %.4f)\n",
           top, d[k], qt.max_volume_ratio, q.max_volume_ratio, qt.min_volume_ratio, worst_step);
    CHECK(meshmove_solver_free(s));
    CHECK(meshmove_bcs_free(bcs));
    CHECK(meshmove_mesh_free(mesh));
    return 0;
}
