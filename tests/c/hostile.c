/* The C ABI survives its caller (issue 14): each defect found by fuzzing and probing, as a test.
 *   - threads = 1 runs on one worker thread (no global pool);
 *   - counts and options beyond their documented bounds fail at once (steps INT32_MAX,
 *     cheb_degree INT32_MAX, threads INT32_MAX);
 *   - a failing call leaves the solver exactly as it was: single vertices of 3x3 and 4x4 grids
 *     are perturbed into degenerate or tangled references, and after every failure a solve
 *     gives bitwise the result it gave before;
 *   - non-finite output is refused and nothing is written;
 *   - two threads on one solver: the second call gets BUSY, free during a move gets BUSY;
 *   - a stale handle is refused even after many new handles were created (no address reuse);
 *   - fork(): the child can use the solver it inherited and a new one; the parent's is unaffected.
 * Exit status 0 when every check passed. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "../../c_examples/box_grid.h"
#include "check.h"

static const char *msg(void) { return meshmove_last_error(); }

/* OS threads of this process. */
static int os_threads(void) {
    DIR *d = opendir("/proc/self/task");
    struct dirent *e;
    int n = 0;
    if (!d) return -1;
    while ((e = readdir(d)) != NULL)
        if (e->d_name[0] != '.') n++;
    closedir(d);
    return n;
}

/* An n x n grid of vertices on the unit square, two triangles per square; the top side is
 * patch 1, the rest of the boundary patch 0. */
typedef struct {
    int n, nv, nc;
    double xy[2 * 64];
    int32_t cells[3 * 2 * 49];
    int32_t edges[2 * 7], patches[7];
} grid;

static void make_grid(grid *g, int n) {
    int i, j, c = 0;
    g->n = n;
    g->nv = n * n;
    g->nc = 2 * (n - 1) * (n - 1);
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            g->xy[2 * (j * n + i)] = (double)i / (n - 1);
            g->xy[2 * (j * n + i) + 1] = (double)j / (n - 1);
        }
    for (j = 0; j + 1 < n; j++)
        for (i = 0; i + 1 < n; i++) {
            int32_t a = j * n + i, b = a + 1, d = a + n, e = d + 1;
            int32_t t[6] = {a, b, e, a, e, d};
            memcpy(&g->cells[3 * c], t, sizeof t);
            c += 2;
        }
    for (i = 0; i + 1 < n; i++) {
        g->edges[2 * i] = (n - 1) * n + i;
        g->edges[2 * i + 1] = (n - 1) * n + i + 1;
        g->patches[i] = 1;
    }
}

/* Options with `threads` workers (the caller frees them). */
static meshmove_options *options_with(int threads) {
    meshmove_options *o = NULL;
    STATUS(meshmove_options_create(&o), MESHMOVE_STATUS_OK);
    STATUS(meshmove_options_set_threads(o, threads), MESHMOVE_STATUS_OK);
    return o;
}

/* A solver with options `o` on `m` (every patch FIXED); `m` is freed. */
static meshmove_solver *solver_with(meshmove_mesh *m, const meshmove_options *o) {
    meshmove_bcs *b = NULL;
    meshmove_solver *s = NULL;
    STATUS(meshmove_bcs_create(&b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_create(m, b, o, &s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_bcs_free(b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_OK);
    return s;
}

/* A solver with `threads` workers on `m` (every patch FIXED); `m` is freed. */
static meshmove_solver *solver_on(meshmove_mesh *m, int threads) {
    meshmove_options *o = options_with(threads);
    meshmove_solver *s = solver_with(m, o);
    STATUS(meshmove_options_free(o), MESHMOVE_STATUS_OK);
    return s;
}

static meshmove_mesh *grid_mesh(const grid *g) {
    meshmove_mesh *m = NULL;
    STATUS(meshmove_mesh_create_triangles(g->nv, g->xy, g->nc, g->cells, 0, g->n - 1, g->edges, g->patches, NULL, &m),
           MESHMOVE_STATUS_OK);
    return m;
}

static meshmove_solver *grid_solver(const grid *g, int threads) { return solver_on(grid_mesh(g), threads); }

/* The grid's top moves right by 0.05. */
static void top_shift(const grid *g, double *d) {
    int i;
    memset(d, 0, sizeof(double) * 2 * (size_t)g->nv);
    for (i = 0; i < g->n; i++) d[2 * ((g->n - 1) * g->n + i)] = 0.05;
}

/* The box [0,1]x[-1,0] in n x n squares of two triangles (box_grid.h), its top y = 0 on patch 3. */
static meshmove_mesh *box_mesh(int n, int *nv) {
    box_grid g;
    meshmove_mesh *m = NULL;
    box_grid_make(&g, n, n, (const double[]){0.0, 1.0, -1.0, 0.0}, 0, (const int32_t[]){1, 2, 3, 4});
    STATUS(box_grid_mesh(&g, &m), MESHMOVE_STATUS_OK);
    *nv = g.nv;
    box_grid_free(&g);
    return m;
}

/* A finer mesh whose solves take long enough to overlap with another thread's call. */
static meshmove_solver *box_solver(int n, int threads, int *nv) { return solver_on(box_mesh(n, nv), threads); }

/* The top (y = 0) of the box rises by 0.02 sin(pi x). */
static double *box_motion(meshmove_solver *s, int nv) {
    double *d = calloc(2 * (size_t)nv, sizeof(double)), *xy = malloc(2 * (size_t)nv * sizeof(double));
    int v;
    STATUS(meshmove_solver_get_coords(s, 2 * nv, xy), MESHMOVE_STATUS_OK);
    for (v = 0; v < nv; v++)
        if (xy[2 * v + 1] == 0.0) d[2 * v + 1] = 0.02 * sin(3.14159265358979 * xy[2 * v]);
    free(xy);
    return d;
}

static void test_one_thread(void) {
    int nv = 0, before = os_threads(), after;
    meshmove_solver *s = box_solver(96, 1, &nv); /* above the rows run serially */
    double *d = box_motion(s, nv), *out = malloc(2 * (size_t)nv * sizeof(double));
    meshmove_report r;
    STATUS(meshmove_solver_solve(s, 2 * nv, d, NULL, out, &r), MESHMOVE_STATUS_OK);
    after = os_threads();
    /* the caller's thread and the solver's one worker */
    CHECK(after <= before + 1, "threads = 1: %d OS threads after a solve, %d before", after, before);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    free(d);
    free(out);
}

static void test_bounds(void) {
    grid g;
    meshmove_solver *s;
    meshmove_mesh *m = NULL;
    meshmove_options *o = NULL;
    double d[2 * 64], t0;
    int32_t nd = 0;
    make_grid(&g, 3);
    s = grid_solver(&g, 1);
    top_shift(&g, d);
    /* processor time of this process, which other jobs on the machine do not add to */
    t0 = (double)clock() / CLOCKS_PER_SEC;
    STATUS(meshmove_solver_move_in_steps(s, 2 * g.nv, d, INT32_MAX, 0, NULL), MESHMOVE_STATUS_INVALID_ARGUMENT);
    CHECK(strstr(msg(), "steps") != NULL, "message does not name steps");
    STATUS(meshmove_solver_move_in_steps(s, 2 * g.nv, d, 200000000, 0, NULL), MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_solver_move_in_steps(s, 2 * g.nv, d, MESHMOVE_MAX_STEPS + 1, 0, NULL),
           MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_solver_sizes(s, &nd, NULL, NULL), MESHMOVE_STATUS_OK);
    CHECK(nd == 2, "solver dim %d", nd);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_mesh_create_triangles(INT32_MAX, g.xy, g.nc, g.cells, 0, 0, NULL, NULL, NULL, &m),
           MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_mesh_create_triangles(g.nv, g.xy, INT32_MAX, g.cells, 0, 0, NULL, NULL, NULL, &m),
           MESHMOVE_STATUS_INVALID_ARGUMENT);
    /* the generic call: huge counts and lengths fail before anything is read or allocated */
    STATUS(meshmove_mesh_create(3, INT32_MAX / 3 + 1, g.xy, g.nc, NULL, 3 * g.nc, g.cells, NULL, 0, NULL, 0, NULL, NULL,
                                NULL, 0, &m),
           MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_mesh_create(2, g.nv, g.xy, INT32_MAX, NULL, 3 * g.nc, g.cells, NULL, 0, NULL, 0, NULL, NULL, NULL, 0,
                                &m),
           MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_mesh_create(2, g.nv, g.xy, g.nc, NULL, 3 * g.nc, g.cells, NULL, INT32_MAX, NULL, 0, NULL, NULL, NULL,
                                0, &m),
           MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_options_create(&o), MESHMOVE_STATUS_OK);
    STATUS(meshmove_options_set_cheb_degree(o, INT32_MAX), MESHMOVE_STATUS_INVALID_ARGUMENT);
    CHECK(strstr(msg(), "cheb_degree") != NULL, "message does not name cheb_degree");
    STATUS(meshmove_options_set_threads(o, INT32_MAX), MESHMOVE_STATUS_INVALID_ARGUMENT);
    CHECK(strstr(msg(), "threads") != NULL, "message does not name threads");
    STATUS(meshmove_options_set_max_cycles(o, INT32_MAX), MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_options_set_substepping(o, INT32_MAX, 0.0), MESHMOVE_STATUS_INVALID_ARGUMENT);
    t0 = (double)clock() / CLOCKS_PER_SEC - t0;
    CHECK(t0 < 1.0, "refusing out-of-bound arguments took %.2f s of processor time", t0);
    STATUS(meshmove_options_free(o), MESHMOVE_STATUS_OK);
}

/* After every failure the solver must give bitwise the displacement it gave before. */
static void same_as_before(meshmove_solver *s, const grid *g, const double *d, const double *want, int line) {
    double out[2 * 64], xy[2 * 64];
    meshmove_status st = meshmove_solver_solve(s, 2 * g->nv, d, NULL, out, NULL);
    checks++;
    if (st != MESHMOVE_STATUS_OK || memcmp(out, want, sizeof(double) * 2 * (size_t)g->nv) != 0) {
        fprintf(stderr, "line %d: after a failed call the solver changed (%s: %s)\n", line, meshmove_status_name(st),
                msg());
        failures++;
    }
    STATUS(meshmove_solver_get_coords(s, 2 * g->nv, xy), MESHMOVE_STATUS_OK);
    checks++;
    if (memcmp(xy, g->xy, sizeof(double) * 2 * (size_t)g->nv) != 0) {
        fprintf(stderr, "line %d: after a failed call the reference changed\n", line);
        failures++;
    }
}

static void test_transactional(int n) {
    grid g;
    meshmove_solver *s;
    double d[2 * 64], want[2 * 64], x[2 * 64];
    int v, k, failed = 0, tried = 0;
    make_grid(&g, n);
    s = grid_solver(&g, 1);
    top_shift(&g, d);
    STATUS(meshmove_solver_solve(s, 2 * g.nv, d, NULL, want, NULL), MESHMOVE_STATUS_OK);
    for (v = 0; v < g.nv; v++) {
        int i = v % n, j = v / n;
        /* onto each neighbour (zero-area cells), beyond it (inverted cells), not finite */
        double moves[7][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {2, 0}, {0, 2}, {NAN, 0}};
        for (k = 0; k < 7; k++) {
            meshmove_status st;
            int nb;
            double dx, dy;
            if (k < 6 && (i + moves[k][0] < 0 || i + moves[k][0] > n - 1 || j + moves[k][1] < 0 || j + moves[k][1] > n - 1))
                continue;
            memcpy(x, g.xy, sizeof x);
            if (k < 6) {
                /* exactly onto the neighbour (k < 4) or as far beyond it (k 4, 5): the vertex
                 * neighbour nb = v + (mx, my) steps */
                int mx = (int)moves[k][0], my = (int)moves[k][1], step = k < 4 ? 1 : 2;
                nb = v + (mx / step) + (my / step) * n;
                x[2 * v] = g.xy[2 * v] + step * (g.xy[2 * nb] - g.xy[2 * v]);
                x[2 * v + 1] = g.xy[2 * v + 1] + step * (g.xy[2 * nb + 1] - g.xy[2 * v + 1]);
            } else
                x[2 * v] = NAN;
            dx = x[2 * v] - g.xy[2 * v];
            dy = x[2 * v + 1] - g.xy[2 * v + 1];
            tried++;
            st = meshmove_solver_set_reference(s, 2 * g.nv, x);
            CHECK(st != MESHMOVE_STATUS_OK, "%dx%d: set_reference with vertex %d moved by (%g, %g) was accepted", n, n, v,
                  dx, dy);
            if (st == MESHMOVE_STATUS_OK) {
                STATUS(meshmove_solver_set_reference(s, 2 * g.nv, g.xy), MESHMOVE_STATUS_OK);
                continue;
            }
            CHECK(st != MESHMOVE_STATUS_PANIC && strlen(msg()) > 0, "no message");
            failed++;
            same_as_before(s, &g, d, want, __LINE__);
            /* the drop-in move from the same coordinates: fails, coords untouched */
            st = meshmove_solver_move(s, 2 * g.nv, d, x, NULL, NULL);
            CHECK(st != MESHMOVE_STATUS_OK, "%dx%d: move from a bad reference (vertex %d) was accepted", n, n, v);
            if (st != MESHMOVE_STATUS_OK && k < 6) {
                double x2[2 * 64];
                memcpy(x2, g.xy, sizeof x2);
                x2[2 * v] += dx;
                x2[2 * v + 1] += dy;
                CHECK(memcmp(x, x2, sizeof(double) * 2 * (size_t)g.nv) == 0, "a failed move wrote coords");
            }
            if (st == MESHMOVE_STATUS_OK) STATUS(meshmove_solver_set_reference(s, 2 * g.nv, g.xy), MESHMOVE_STATUS_OK);
            same_as_before(s, &g, d, want, __LINE__);
        }
    }
    CHECK(failed > 0 && failed == tried, "%dx%d: %d of %d perturbations refused", n, n, failed, tried);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
}

static void test_non_finite(void) {
    grid g;
    meshmove_solver *s;
    double d[2 * 64], out[2 * 64], sentinel[2 * 64];
    meshmove_report r;
    meshmove_status st;
    int i;
    make_grid(&g, 4);
    s = grid_solver(&g, 1);
    top_shift(&g, d);
    for (i = 0; i < 2 * g.nv; i++) d[i] *= 1e307; /* finite in, overflows inside */
    for (i = 0; i < 2 * g.nv; i++) sentinel[i] = out[i] = 12345.0;
    st = meshmove_solver_cycle(s, 2 * g.nv, d, out, &r);
    for (i = 0; i < 2 * g.nv && st == MESHMOVE_STATUS_OK; i++) CHECK(isfinite(out[i]), "cycle returned OK with out[%d] = %g", i, out[i]);
    if (st != MESHMOVE_STATUS_OK)
        CHECK(memcmp(out, sentinel, sizeof(double) * 2 * (size_t)g.nv) == 0, "a failed cycle wrote its output");
    st = meshmove_solver_solve(s, 2 * g.nv, d, NULL, out, &r);
    for (i = 0; i < 2 * g.nv && st == MESHMOVE_STATUS_OK; i++) CHECK(isfinite(out[i]), "solve returned OK with out[%d] = %g", i, out[i]);
    if (st == MESHMOVE_STATUS_OK)
        CHECK(isfinite(r.rel_residual) && isfinite(r.max_correction), "OK with a non-finite report");
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
}

/* NOT_CONVERGED, INVERTED, step reports and the sub-stepping and reference-mode setters. */
static void test_statuses(void) {
    grid g;
    meshmove_solver *s;
    meshmove_options *o = NULL;
    meshmove_report r;
    meshmove_quality q;
    meshmove_step_report sr[8];
    double d[2 * 64], x[2 * 64], back[2 * 64];
    int32_t count = -1;
    int i;
    make_grid(&g, 4);
    top_shift(&g, d);

    /* one cycle to 1e-14: not converged; _solve writes the result, _move writes nothing */
    {
        int nv = 0;
        meshmove_solver *c = NULL;
        double *cd, *cout, *cx, *cback;
        meshmove_mesh *m = box_mesh(32, &nv);
        meshmove_bcs *b = NULL;
        o = options_with(1);
        STATUS(meshmove_options_set_max_cycles(o, 1), MESHMOVE_STATUS_OK);
        STATUS(meshmove_options_set_tol(o, 1e-14), MESHMOVE_STATUS_OK);
        STATUS(meshmove_bcs_create(&b), MESHMOVE_STATUS_OK);
        STATUS(meshmove_solver_create(m, b, o, &c), MESHMOVE_STATUS_OK);
        STATUS(meshmove_options_free(o), MESHMOVE_STATUS_OK);
        cd = box_motion(c, nv);
        cout = malloc(2 * (size_t)nv * sizeof(double));
        cx = malloc(2 * (size_t)nv * sizeof(double));
        cback = malloc(2 * (size_t)nv * sizeof(double));
        for (i = 0; i < 2 * nv; i++) cout[i] = 12345.0;
        STATUS(meshmove_solver_solve(c, 2 * nv, cd, NULL, cout, &r), MESHMOVE_STATUS_NOT_CONVERGED);
        CHECK(strstr(msg(), "not converged") != NULL, "NOT_CONVERGED message");
        for (i = 0; i < 2 * nv && cout[i] != 12345.0; i++) continue;
        CHECK(i == 2 * nv && r.converged == 0 && r.cycles == 1, "NOT_CONVERGED solve did not write its result and report");
        STATUS(meshmove_mesh_get_coords(m, 2 * nv, cx), MESHMOVE_STATUS_OK);
        STATUS(meshmove_solver_move(c, 2 * nv, cd, cx, &r, &q), MESHMOVE_STATUS_NOT_CONVERGED);
        STATUS(meshmove_mesh_get_coords(m, 2 * nv, cback), MESHMOVE_STATUS_OK);
        CHECK(memcmp(cx, cback, sizeof(double) * 2 * (size_t)nv) == 0, "NOT_CONVERGED move wrote coords");
        STATUS(meshmove_solver_get_coords(c, 2 * nv, cx), MESHMOVE_STATUS_OK);
        CHECK(memcmp(cx, cback, sizeof(double) * 2 * (size_t)nv) == 0, "NOT_CONVERGED move changed the solver");
        STATUS(meshmove_solver_free(c), MESHMOVE_STATUS_OK);
        STATUS(meshmove_bcs_free(b), MESHMOVE_STATUS_OK);
        STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_OK);
        free(cd);
        free(cout);
        free(cx);
        free(cback);
    }

    /* the Laplacian sheared far: a converged result with inverted cells is INVERTED, written */
    o = options_with(1);
    STATUS(meshmove_options_set_method(o, MESHMOVE_METHOD_LAPLACIAN), MESHMOVE_STATUS_OK);
    s = solver_with(grid_mesh(&g), o);
    STATUS(meshmove_options_free(o), MESHMOVE_STATUS_OK);
    for (i = 0; i < 2 * g.nv; i++) d[i] *= 40.0; /* the top moves 2 to the right */
    memcpy(x, g.xy, sizeof x);
    STATUS(meshmove_solver_move(s, 2 * g.nv, d, x, &r, &q), MESHMOVE_STATUS_INVERTED);
    CHECK(q.inverted > 0 && r.converged == 1, "INVERTED without a count (%d) or unconverged", q.inverted);
    CHECK(x[2 * (g.nv - 1)] == g.xy[2 * (g.nv - 1)] + 2.0, "INVERTED move did not write coords");
    STATUS(meshmove_solver_get_coords(s, 2 * g.nv, back), MESHMOVE_STATUS_OK);
    CHECK(memcmp(back, g.xy, sizeof(double) * 2 * (size_t)g.nv) == 0, "INVERTED move changed the solver's reference");
    /* with sub-stepping: either a valid mesh (OK) or a failure that changes nothing */
    STATUS(meshmove_solver_set_substepping(s, MESHMOVE_MAX_SUBSTEPS + 1, 0.0), MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_solver_set_substepping(s, 8, 1.5), MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_solver_set_substepping(s, 8, NAN), MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_solver_set_substepping(s, 8, 0.0), MESHMOVE_STATUS_OK);
    memcpy(x, g.xy, sizeof x);
    {
        meshmove_status st = meshmove_solver_move(s, 2 * g.nv, d, x, &r, &q);
        CHECK(st != MESHMOVE_STATUS_INVERTED && st != MESHMOVE_STATUS_PANIC, "sub-stepped move: %s",
              meshmove_status_name(st));
        if (st == MESHMOVE_STATUS_OK) CHECK(q.inverted == 0, "OK with %d inverted cells", q.inverted);
        if (st != MESHMOVE_STATUS_OK) {
            CHECK(memcmp(x, g.xy, sizeof(double) * 2 * (size_t)g.nv) == 0, "a failed sub-stepped move wrote coords");
            STATUS(meshmove_solver_get_coords(s, 2 * g.nv, back), MESHMOVE_STATUS_OK);
            CHECK(memcmp(back, g.xy, sizeof(double) * 2 * (size_t)g.nv) == 0, "a failed move changed the solver");
        }
        STATUS(meshmove_solver_step_reports(s, 8, sr, &count), count > 8 ? MESHMOVE_STATUS_BUFFER_TOO_SMALL : MESHMOVE_STATUS_OK);
        CHECK(count > 1, "sub-stepping left %d step reports (move: %s)", count, meshmove_status_name(st));
    }
    STATUS(meshmove_solver_set_reference_mode(s, 2), MESHMOVE_STATUS_INVALID_ARGUMENT);
    STATUS(meshmove_solver_set_reference_mode(s, MESHMOVE_REFERENCE_ORIGINAL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_set_reference_mode(s, MESHMOVE_REFERENCE_INCREMENTAL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);

    /* three equal steps: three step reports, the first two copied into room for two */
    s = grid_solver(&g, 1);
    top_shift(&g, d);
    STATUS(meshmove_solver_move_in_steps(s, 2 * g.nv, d, 3, 2, sr), MESHMOVE_STATUS_OK);
    CHECK(sr[0].step == 1 && sr[1].step == 2 && sr[1].accepted == 1 && fabs(sr[1].fraction - 2.0 / 3.0) < 1e-15,
          "step reports wrong");
    STATUS(meshmove_solver_step_reports(s, 1, sr, &count), MESHMOVE_STATUS_BUFFER_TOO_SMALL);
    CHECK(count == 3, "%d step reports, want 3", count);
    STATUS(meshmove_solver_step_reports(s, 8, sr, &count), MESHMOVE_STATUS_OK);
    CHECK(count == 3 && sr[2].fraction == 1.0 && sr[2].converged == 1, "last step report wrong");
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
}

/* ---- two threads on one solver ---- */
typedef struct {
    meshmove_solver *s;
    int nv, rounds;
    double *d;
    volatile int started, done, stop;
    int busy;  /* BUSY statuses seen by the worker */
    int other; /* statuses other than OK and BUSY seen by the worker */
} shared;

/* Solves until `rounds` of them succeeded or the main thread says stop (BUSY ones are counted
 * and retried); stops at any other status (e.g. after the main thread freed the solver). */
static void *mover(void *arg) {
    shared *sh = arg;
    double *out = malloc(2 * (size_t)sh->nv * sizeof(double));
    int ok = 0;
    while (ok < sh->rounds && !sh->stop) {
        meshmove_status st;
        sh->started = 1;
        st = meshmove_solver_solve(sh->s, 2 * sh->nv, sh->d, NULL, out, NULL);
        if (st == MESHMOVE_STATUS_OK)
            ok++;
        else if (st == MESHMOVE_STATUS_BUSY)
            sh->busy++;
        else {
            sh->other++;
            break;
        }
    }
    free(out);
    sh->done = 1;
    return NULL;
}

static void test_busy(void) {
    shared sh;
    pthread_t t;
    double *out;
    int busy_solve = 0, busy_free = 0, other = 0, freed = 0;
    memset(&sh, 0, sizeof sh);
    sh.s = box_solver(64, 1, &sh.nv);
    sh.d = box_motion(sh.s, sh.nv);
    /* The worker keeps moving until the main thread has seen what it tests (a BUSY solve, then a
     * refused or clean free), so the outcome rests on counts, not on how the threads are
     * scheduled; the bound on rounds only keeps a broken build from running forever. */
    sh.rounds = 1000000;
    out = malloc(2 * (size_t)sh.nv * sizeof(double));
    pthread_create(&t, NULL, mover, &sh);
    while (!sh.started) sched_yield();
    while (!sh.done) {
        meshmove_status st = meshmove_solver_solve(sh.s, 2 * sh.nv, sh.d, NULL, out, NULL);
        if (st == MESHMOVE_STATUS_OK) {
            /* this thread won: give the worker time to start its next call */
            struct timespec pause = {0, 2000000};
            nanosleep(&pause, NULL);
            continue;
        }
        if (st != MESHMOVE_STATUS_BUSY) {
            other++;
            continue;
        }
        busy_solve++;
        CHECK(strstr(msg(), "in use") != NULL, "BUSY message");
        if (busy_free > 0) continue; /* a refused free was seen: wait for the worker to stop */
        /* the worker is (or just was) inside a call: free must be refused, or done cleanly */
        st = meshmove_solver_free(sh.s);
        if (st == MESHMOVE_STATUS_BUSY) {
            busy_free++;
            sh.stop = 1;
        } else if (st == MESHMOVE_STATUS_OK) {
            freed = 1; /* the worker's later calls must see INVALID_HANDLE, not crash */
            break;
        } else
            other++;
    }
    pthread_join(t, NULL);
    CHECK(busy_solve > 0, "two threads on one solver: no BUSY seen");
    CHECK(other == 0, "%d statuses other than OK/BUSY in the main thread", other);
    CHECK(freed || busy_free > 0, "free during a move was neither refused (BUSY) nor done");
    if (freed)
        CHECK(sh.other >= 0, "unreachable");
    else
        CHECK(sh.other == 0, "the worker saw %d statuses other than OK/BUSY", sh.other);
    if (!freed) STATUS(meshmove_solver_free(sh.s), MESHMOVE_STATUS_OK);
    printf("busy: %d BUSY solves, %d BUSY frees in this thread, %d BUSY solves in the worker%s\n", busy_solve, busy_free,
           sh.busy, freed ? " (then freed between its calls)" : "");
    free(sh.d);
    free(out);
}

static void test_stale(void) {
    grid g;
    meshmove_mesh *m = NULL, *fresh[64];
    meshmove_solver *s, *s2;
    double d[2 * 64], out[2 * 64];
    int k, n;
    make_grid(&g, 3);
    top_shift(&g, d);
    /* a freed mesh, then as many new ones: none may get its address */
    m = grid_mesh(&g);
    STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_OK);
    for (k = 0; k < 64; k++) {
        fresh[k] = grid_mesh(&g);
        CHECK(fresh[k] != m, "a new mesh got the address of a freed one");
    }
    STATUS(meshmove_mesh_sizes(m, NULL, &n, NULL, NULL, NULL, NULL), MESHMOVE_STATUS_INVALID_HANDLE);
    CHECK(strstr(msg(), "freed") != NULL, "message does not say freed");
    STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_INVALID_HANDLE);
    for (k = 0; k < 64; k++) STATUS(meshmove_mesh_free(fresh[k]), MESHMOVE_STATUS_OK);
    /* free, create: the stale solver is refused and a second free does not destroy the live one */
    s = grid_solver(&g, 1);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    s2 = grid_solver(&g, 1);
    CHECK(s2 != s, "a new solver got the address of a freed one");
    STATUS(meshmove_solver_solve(s, 2 * g.nv, d, NULL, out, NULL), MESHMOVE_STATUS_INVALID_HANDLE);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_INVALID_HANDLE);
    STATUS(meshmove_solver_solve(s2, 2 * g.nv, d, NULL, out, NULL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_free(s2), MESHMOVE_STATUS_OK);
}

/* In a child (alarm: a hang fails the test): the inherited solver works (bitwise the parent's
 * result: its pool is rebuilt there) and can be freed; a new solver from an inherited mesh works. */
static int child_work(meshmove_solver *s, meshmove_mesh *m, meshmove_bcs *b, const grid *g, const double *want) {
    double d[2 * 64], out[2 * 64];
    meshmove_solver *s2 = NULL;
    meshmove_status st;
    int bad = 0;
    alarm(10);
    top_shift(g, d);
    st = meshmove_solver_solve(s, 2 * g->nv, d, NULL, out, NULL);
    if (st != MESHMOVE_STATUS_OK || memcmp(out, want, sizeof(double) * 2 * (size_t)g->nv) != 0) {
        fprintf(stderr, "child: inherited solver: %s: %s\n", meshmove_status_name(st), msg());
        bad = 1;
    }
    if (meshmove_solver_free(s) != MESHMOVE_STATUS_OK) {
        fprintf(stderr, "child: freeing the inherited solver: %s\n", msg());
        bad = 1;
    }
    memcpy(out, g->xy, sizeof(double) * 2 * (size_t)g->nv);
    if (meshmove_solver_create(m, b, NULL, &s2) != MESHMOVE_STATUS_OK ||
        meshmove_solver_move(s2, 2 * g->nv, d, out, NULL, NULL) != MESHMOVE_STATUS_OK) {
        fprintf(stderr, "child: new solver: %s\n", msg());
        bad = 1;
    }
    if (meshmove_solver_free(s2) != MESHMOVE_STATUS_OK) bad = 1;
    return bad || failures;
}

static void test_fork(int threads) {
    grid g;
    meshmove_mesh *m = NULL;
    meshmove_bcs *b = NULL;
    meshmove_solver *s = NULL;
    meshmove_options *o = options_with(threads);
    double d[2 * 64], want[2 * 64];
    pid_t pid;
    int status = 0;
    make_grid(&g, 4);
    m = grid_mesh(&g);
    STATUS(meshmove_bcs_create(&b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_create(m, b, o, &s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_options_free(o), MESHMOVE_STATUS_OK);
    top_shift(&g, d);
    STATUS(meshmove_solver_solve(s, 2 * g.nv, d, NULL, want, NULL), MESHMOVE_STATUS_OK);
    fflush(NULL);
    pid = fork();
    if (pid == 0) _exit(child_work(s, m, b, &g, want));
    CHECK(pid > 0, "fork failed");
    if (pid > 0) {
        waitpid(pid, &status, 0);
        CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0, "threads = %d: the forked child %s", threads,
              WIFSIGNALED(status) ? "was killed (hung: alarm)" : "failed");
    }
    /* the parent's solver is unaffected */
    STATUS(meshmove_solver_solve(s, 2 * g.nv, d, NULL, want, NULL), MESHMOVE_STATUS_OK);
    STATUS(meshmove_solver_free(s), MESHMOVE_STATUS_OK);
    STATUS(meshmove_bcs_free(b), MESHMOVE_STATUS_OK);
    STATUS(meshmove_mesh_free(m), MESHMOVE_STATUS_OK);
}

/* `hostile_c [GROUP]`: one group, or all of them. */
int main(int argc, char **argv) {
    const char *only = argc > 1 ? argv[1] : "";
#define GROUP(name) (!only[0] || !strcmp(only, name))
    if (GROUP("one_thread")) test_one_thread(); /* first: no other solver's threads exist yet */
    if (GROUP("bounds")) test_bounds();
    if (GROUP("transactional")) {
        test_transactional(3);
        test_transactional(4);
    }
    if (GROUP("non_finite")) test_non_finite();
    if (GROUP("statuses")) test_statuses();
    if (GROUP("stale")) test_stale();
    if (GROUP("busy")) test_busy();
    if (GROUP("fork")) {
        test_fork(1);
        test_fork(0);
    }
    printf("hostile %s: %d checks, %d failures\n", only, checks, failures);
    return failures != 0;
}
