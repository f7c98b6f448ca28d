/* What a host may rely on at the limits (issues 25 and 29), through the C ABI:
 *   scale   - the solve does not depend on the units: prescribed displacements of 1e-170 give
 *             the normal answer scaled (not zeros), 1e154 and 1e300 give it or an
 *             INVALID_ARGUMENT naming the overflow (never DIVERGED); a mesh scaled by 1e155 is
 *             refused with a message about the overflow (not "zero area");
 *   cancel  - meshmove_solver_cancel stops the next (or running) call within one multigrid
 *             cycle with CANCELLED and changes nothing; called from the progress callback,
 *             while the move holds the solver, and from another thread during a move, it stops
 *             the move in its next step's solve;
 *   quality - a hexahedron folded at one corner: inverted by its corner Jacobian, with a positive
 *             volume (what VTK's cell volume finds), both counts and ratios in meshmove_quality;
 *             pushed further, a negative volume too, and the INVERTED message speaks of volumes.
 * Exit status 0 when every check passed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../../c_examples/box_grid.h"
#include "check.h"

/* The unit square in n x n squares of two triangles, the top side patch 1, the rest patch 0,
 * every patch FIXED, the coordinates multiplied by `unit`. NULL when the mesh is refused. */
static meshmove_solver *square(int n, double unit, meshmove_status *mesh_status) {
    box_grid g;
    meshmove_mesh *m = NULL;
    meshmove_bcs *b = NULL;
    meshmove_solver *s = NULL;
    int i;
    box_grid_make(&g, n, n, (const double[]){0.0, 1.0, 0.0, 1.0}, 0, (const int32_t[]){0, 0, 1, 0});
    for (i = 0; i < 2 * g.nv; i++) g.xy[i] *= unit;
    *mesh_status = box_grid_mesh(&g, &m);
    box_grid_free(&g);
    if (*mesh_status != MESHMOVE_STATUS_OK) return NULL;
    STATUS(meshmove_bcs_create(&b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_create(m, b, NULL, &s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_bcs_free(b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_OK);
    return s;
}

/* The top (y = 1) of the n x n square bends up by a sin(pi x). */
static void bend(int n, double a, double *d) {
    int i, nv = (n + 1) * (n + 1);
    memset(d, 0, sizeof(double) * 2 * (size_t)nv);
    for (i = 0; i <= n; i++) d[2 * (n * (n + 1) + i) + 1] = a * sin(3.14159265358979 * i / n);
}

static void test_scale(void) {
    enum { N = 8, NV = (N + 1) * (N + 1) };
    double d[2 * NV], x1[2 * NV], x[2 * NV], big = 0.0;
    const double amplitudes[] = {1e-170, 1e154, 1e300};
    meshmove_status st;
    meshmove_solver *s = square(N, 1.0, &st);
    int k, i;
    bend(N, 0.05, d);
    STATUS(meshmove_solver_solve(s, 2 * NV, d, NULL, x1, NULL), MESHMOVE_STATUS_OK);
    for (i = 0; i < 2 * NV; i++) big = fmax(big, fabs(x1[i]));
    for (k = 0; k < 3; k++) {
        double f = amplitudes[k] / 0.05, worst = 0.0;
        int interior_moved = 0;
        bend(N, amplitudes[k], d);
        st = meshmove_solver_solve(s, 2 * NV, d, NULL, x, NULL);
        CHECK(st == MESHMOVE_STATUS_OK ||
                  (st == MESHMOVE_STATUS_INVALID_ARGUMENT && strstr(meshmove_last_error(), "overflow")),
              "amplitude %g: %s", amplitudes[k], meshmove_status_name(st));
        if (st != MESHMOVE_STATUS_OK) continue;
        for (i = 0; i < 2 * NV; i++) {
            worst = fmax(worst, fabs(x[i] / f - x1[i]));
            interior_moved |= x1[i] != 0.0 && x[i] != 0.0;
        }
        CHECK(interior_moved && worst <= 1e-9 * big, "amplitude %g: off the scaled answer by %g (of %g)",
              amplitudes[k], worst, big);
    }
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    /* A mesh of cells 1e154 long: areas of 1e308 and more overflow. */
    s = square(N, 1e155 * N, &st);
    CHECK(s == NULL && st == MESHMOVE_STATUS_INVALID_MESH && strstr(meshmove_last_error(), "overflow") &&
              !strstr(meshmove_last_error(), "zero area"),
          "a mesh scaled by 1e155: %s", meshmove_status_name(st));
}

/* The progress callback: asks to cancel the move that holds the solver (user_data) at its
 * first step, and goes on. */
static int cancel_from_callback(void *user, const meshmove_step_report *r, int32_t steps) {
    (void)steps;
    if (r->step == 1) STATUS(meshmove_solver_cancel((meshmove_solver *)user), MESHMOVE_STATUS_OK);
    return 0;
}

/* Two threads' meeting point: the mover's callback says it holds the solver, then waits until
 * the other thread has asked to cancel. */
typedef struct {
    pthread_mutex_t lock;
    pthread_cond_t changed;
    int entered, asked;
    meshmove_solver *solver;
} gate;

static int wait_for_cancel(void *user, const meshmove_step_report *r, int32_t steps) {
    gate *g = user;
    (void)r;
    (void)steps;
    pthread_mutex_lock(&g->lock);
    g->entered = 1;
    pthread_cond_broadcast(&g->changed);
    while (!g->asked) pthread_cond_wait(&g->changed, &g->lock);
    pthread_mutex_unlock(&g->lock);
    return 0;
}

static void *canceller(void *arg) {
    gate *g = arg;
    pthread_mutex_lock(&g->lock);
    while (!g->entered) pthread_cond_wait(&g->changed, &g->lock);
    pthread_mutex_unlock(&g->lock);
    /* The solver is held by the other thread's move: cancel is the one call that takes it. */
    STATUS(meshmove_solver_cancel(g->solver), MESHMOVE_STATUS_OK);
    pthread_mutex_lock(&g->lock);
    g->asked = 1;
    pthread_cond_broadcast(&g->changed);
    pthread_mutex_unlock(&g->lock);
    return NULL;
}

static void test_cancel(void) {
    enum { N = 8, NV = (N + 1) * (N + 1) };
    double d[2 * NV], before[2 * NV], after[2 * NV], moved[2 * NV];
    meshmove_step_report reports[4];
    int32_t count = 0;
    meshmove_status st;
    meshmove_solver *s = square(N, 1.0, &st);
    bend(N, 0.05, d);
    STATUS(meshmove_solver_get_coords(s, 2 * NV, before), MESHMOVE_STATUS_OK);
    /* Asked before the call: the call stops at its first check, changing nothing. */
    memcpy(after, before, sizeof before);
    STATUS(meshmove_solver_cancel(s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_move(s, 2 * NV, d, after, NULL, NULL), MESHMOVE_STATUS_CANCELLED);
    CHECK(strstr(meshmove_last_error(), "cancelled") != NULL, "the message says why");
    CHECK(!memcmp(before, after, sizeof before), "a cancelled move wrote the coordinates");
    STATUS(meshmove_solver_get_coords(s, 2 * NV, after), MESHMOVE_STATUS_OK);
    CHECK(!memcmp(before, after, sizeof before), "a cancelled move changed the solver's coordinates");
    /* The request was consumed: the same move now runs. */
    STATUS(meshmove_solver_move(s, 2 * NV, d, after, NULL, NULL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_get_coords(s, 2 * NV, moved), MESHMOVE_STATUS_OK);
    CHECK(!memcmp(moved, after, sizeof moved), "the move wrote the solver's coordinates");
    /* From the callback after step 1 of 4, while the move holds the solver: step 2's solve
     * stops within its first cycle, and the move changes nothing. */
    STATUS(meshmove_solver_set_progress(s, cancel_from_callback, s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_move_in_steps(s, 2 * NV, d, 4, 0, NULL), MESHMOVE_STATUS_CANCELLED);
    CHECK(strstr(meshmove_last_error(), "cancelled") != NULL, "the message says why");
    STATUS(meshmove_solver_step_reports(s, 4, reports, &count), MESHMOVE_STATUS_OK);
    CHECK(count == 1 && reports[0].accepted, "%d step reports before the cancelled step", count);
    STATUS(meshmove_solver_get_coords(s, 2 * NV, after), MESHMOVE_STATUS_OK);
    CHECK(!memcmp(moved, after, sizeof moved), "a cancelled move_in_steps changed the coordinates");
    /* From another thread while the move holds the solver (a 1000-step move, met at its first
     * step): CANCELLED, nothing changed. */
    {
        gate g = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0, 0, s};
        pthread_t t;
        STATUS(meshmove_solver_set_progress(s, wait_for_cancel, &g), MESHMOVE_STATUS_OK);
        CHECK(pthread_create(&t, NULL, canceller, &g) == 0, "pthread_create");
        STATUS(meshmove_solver_move_in_steps(s, 2 * NV, d, 1000, 0, NULL), MESHMOVE_STATUS_CANCELLED);
        pthread_join(t, NULL);
        STATUS(meshmove_solver_get_coords(s, 2 * NV, after), MESHMOVE_STATUS_OK);
        CHECK(!memcmp(moved, after, sizeof moved), "a move cancelled from another thread changed the coordinates");
    }
    STATUS(meshmove_solver_set_progress(s, NULL, NULL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_move_in_steps(s, 2 * NV, d, 4, 0, NULL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_cancel(s), MESHMOVE_STATUS_INVALID_HANDLE);
}

static void test_quality(void) {
    /* The unit cube as one hexahedron, every face on patch 0 (FIXED). */
    const double xyz[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    const int32_t conn[8] = {0, 1, 2, 3, 4, 5, 6, 7}, type = MESHMOVE_CELL_TYPE_HEXAHEDRON;
    double d[24] = {0}, moved[24];
    meshmove_mesh *m = NULL;
    meshmove_bcs *b = NULL;
    meshmove_solver *s = NULL;
    meshmove_quality q;
    STATUS(meshmove_mesh_create(3, 8, xyz, 1, NULL, 8, conn, &type, 0, NULL, 0, NULL, NULL, NULL, 0, &m),
           MESHMOVE_STATUS_OK);
    STATUS(meshmove_bcs_create(&b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_create(m, b, NULL, &s), MESHMOVE_STATUS_OK);
    if (s == NULL) return;
    /* Corner (1, 1, 1) pushed in to (0.3, 0.3, 0.3): its corner Jacobian turns from -1 to +1.1
     * (its three edges' determinant, in the opposite sense); the volume stays positive. */
    d[18] = d[19] = d[20] = -0.7;
    STATUS(meshmove_solver_quality(s, 24, d, &q), MESHMOVE_STATUS_OK);
    CHECK(q.inverted == 1 && q.negative_volume_cells == 0, "inverted %d, negative volumes %d", q.inverted,
          q.negative_volume_cells);
    CHECK(fabs(q.min_corner_jacobian_ratio + 1.1) < 1e-12, "corner Jacobian ratio %g",
          q.min_corner_jacobian_ratio);
    CHECK(q.min_volume_ratio > 0.4 && q.min_volume_ratio < 0.9, "volume ratio %g", q.min_volume_ratio);
    /* Pushed through the opposite corner's plane: the volume turns negative too. */
    d[18] = d[19] = d[20] = -3.0;
    STATUS(meshmove_solver_quality(s, 24, d, &q), MESHMOVE_STATUS_OK);
    CHECK(q.inverted == 1 && q.negative_volume_cells == 1 && q.min_volume_ratio < 0.0,
          "inverted %d, negative volumes %d, volume ratio %g", q.inverted, q.negative_volume_cells,
          q.min_volume_ratio);
    /* Moved there: INVERTED, and the message speaks of volumes in 3D, not areas. */
    memcpy(moved, xyz, sizeof moved);
    STATUS(meshmove_solver_move(s, 24, d, moved, NULL, &q), MESHMOVE_STATUS_INVERTED);
    CHECK(strstr(meshmove_last_error(), "non-positive volume") && strstr(meshmove_last_error(), "volume ratio") &&
              !strstr(meshmove_last_error(), "area"),
          "the 3D message");
    CHECK(q.negative_volume_cells == 1 && moved[18] == -2.0, "the move's quality and coordinates");
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_bcs_free(b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_OK);
}

/* `limits_c [GROUP]`: one group (scale, cancel, quality), or all of them. */
int main(int argc, char **argv) {
    const char *only = argc > 1 ? argv[1] : "";
#define GROUP(name) (!only[0] || !strcmp(only, name))
    if (GROUP("scale")) test_scale();
    if (GROUP("cancel")) test_cancel();
    if (GROUP("quality")) test_quality();
    printf("limits %s: %d checks, %d failures\n", only, checks, failures);
    return failures != 0;
}
