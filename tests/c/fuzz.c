/* Random call sequences on the C ABI with a fixed seed: live, freed, foreign and wrong-type
 * handles, NULL and mis-sized arrays, negative and huge counts, NaN and huge values, options
 * beyond their bounds. After every call: the status is a known one, a failure has a message and
 * success none, an OK solve or move has finite output, and a failed call on a solver left its
 * reference mesh bitwise as it was. Every array passed is at least as long as any length the
 * library could accept, so the harness itself never makes the library read past a buffer.
 *
 *   fuzz_c SEED SEQUENCES [SECONDS]   (stops early after SECONDS, default 20)
 * Exit status 0 when every check passed. ctest runs it natively and, shorter, under valgrind. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "meshmove.h"

#define NH 3     /* handles of each type kept per sequence */
#define MAXN 6   /* largest grid side */
#define CAP (2 * MAXN * MAXN + 8)

static uint64_t rng;
static int failures = 0, calls = 0;
#define LAST_STATUS MESHMOVE_STATUS_OUT_OF_MEMORY
static long seen[LAST_STATUS + 1]; /* calls per status, printed at the end */

static uint64_t next(void) {
    rng ^= rng >> 12;
    rng ^= rng << 25;
    rng ^= rng >> 27;
    return rng * 2685821657736338717ULL;
}
static int below(int n) { return (int)(next() % (uint64_t)n); }
static int chance(int percent) { return below(100) < percent; }

/* A count: usually `valid`, sometimes a neighbour or a hostile value. */
static int32_t count(int32_t valid) {
    static const int32_t bad[] = {-1, 0, INT32_MAX, INT32_MIN, 1};
    if (chance(80)) return valid;
    if (chance(50)) return valid + (chance(50) ? 1 : -1);
    return bad[below(5)];
}
static double value(double valid) {
    static const double bad[] = {NAN, INFINITY, -INFINITY, 1e308, -0.0, 1e-308};
    return chance(95) ? valid : bad[below(6)];
}

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void check(meshmove_status s, const char *what) {
    const char *m = meshmove_last_error();
    calls++;
    if ((int)s >= 0 && (int)s <= LAST_STATUS) seen[s]++;
    if ((int)s < 0 || (int)s > LAST_STATUS || s == MESHMOVE_STATUS_PANIC) {
        fprintf(stderr, "%s: status %d (%s): %s\n", what, (int)s, meshmove_status_name(s), m);
        failures++;
    } else if ((s == MESHMOVE_STATUS_OK) != (m[0] == 0)) {
        fprintf(stderr, "%s: status %s with message \"%s\"\n", what, meshmove_status_name(s), m);
        failures++;
    }
}

static int finite_all(const double *a, int n) {
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(a[i])) return 0;
    return 1;
}

typedef struct {
    meshmove_mesh *mesh[NH];
    meshmove_bcs *bcs[NH];
    meshmove_solver *solver[NH];
    int nv[NH];  /* vertices of each solver's mesh */
    int dim[NH]; /* and its dimension */
    meshmove_mesh *stale_mesh;
    meshmove_solver *stale_solver;
} world;

static double foreign[8]; /* an address meshmove never made */

static meshmove_mesh *pick_mesh(world *w) {
    switch (below(10)) {
    case 0: return NULL;
    case 1: return w->stale_mesh;
    case 2: return (meshmove_mesh *)(void *)foreign;
    case 3: return (meshmove_mesh *)(void *)w->bcs[below(NH)];
    default: return w->mesh[below(NH)];
    }
}
static meshmove_bcs *pick_bcs(world *w) {
    switch (below(10)) {
    case 0: return NULL;
    case 1: return (meshmove_bcs *)(void *)w->mesh[below(NH)];
    default: return w->bcs[below(NH)];
    }
}
static int pick_solver(world *w, meshmove_solver **s) {
    int k = below(NH);
    switch (below(12)) {
    case 0: *s = NULL; return -1;
    case 1: *s = w->stale_solver; return -1;
    case 2: *s = (meshmove_solver *)(void *)foreign; return -1;
    case 3: *s = (meshmove_solver *)(void *)w->mesh[k]; return -1;
    default: *s = w->solver[k]; return w->solver[k] ? k : -1;
    }
}

/* A grid mesh through the triangle call or the generic one, with hostile counts, indices, base,
 * offsets and cell types now and then. */
static void grid_mesh(world *w, int k) {
    int n = 3 + below(MAXN - 2), i, j, c = 0, generic = chance(50);
    double xy[3 * MAXN * MAXN] = {0}; /* room for 3D: the generic call is sometimes told dim 3 */
    int32_t cells[6 * MAXN * MAXN], edges[2 * MAXN], patches[MAXN], regions[2 * MAXN * MAXN];
    int32_t types[2 * MAXN * MAXN], offsets[2 * MAXN * MAXN + 1];
    meshmove_mesh *m = NULL;
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            xy[2 * (j * n + i)] = value((double)i / (n - 1));
            xy[2 * (j * n + i) + 1] = (double)j / (n - 1);
        }
    for (j = 0; j + 1 < n; j++)
        for (i = 0; i + 1 < n; i++) {
            int32_t a = j * n + i, t[6] = {a, a + 1, a + n + 1, a, a + n + 1, a + n};
            memcpy(&cells[3 * c], t, sizeof t);
            regions[c] = regions[c + 1] = 0;
            c += 2;
        }
    for (i = 0; i <= c; i++) offsets[i] = 3 * i;
    for (i = 0; i < c; i++) types[i] = MESHMOVE_CELL_TYPE_TRIANGLE;
    if (chance(10)) cells[below(3 * c)] = count(n * n - 1); /* maybe out of range */
    if (chance(10)) offsets[below(c + 1)] = count(3 * c);   /* maybe inconsistent */
    if (chance(10)) types[below(c)] = chance(50) ? MESHMOVE_CELL_TYPE_QUAD : count(MESHMOVE_CELL_TYPE_TETRA);
    for (i = 0; i + 1 < n; i++) {
        edges[2 * i] = (n - 1) * n + i;
        edges[2 * i + 1] = (n - 1) * n + i + 1;
        patches[i] = 1 + below(2);
    }
    /* counts never exceed the arrays: only smaller or hostile values */
    {
        int32_t nv = count(n * n), nc = count(c), nt = count(n - 1), ncv = count(3 * c), base = chance(95) ? 0 : below(3);
        if (nv > n * n && nv != INT32_MAX) nv = n * n;
        if (nc > c && nc != INT32_MAX) nc = c;
        if (nt > n - 1 && nt != INT32_MAX) nt = n - 1;
        if (ncv > 3 * c && ncv != INT32_MAX) ncv = 3 * c;
        /* the faces' length: 2 nt when that fits, else the hostile count itself */
        if (generic)
            check(meshmove_mesh_create(chance(95) ? 2 : below(5), nv, chance(97) ? xy : NULL, nc, chance(50) ? offsets : NULL,
                                       ncv, cells, types, nt, NULL, nt > 0 && nt <= n ? 2 * nt : nt, edges, patches, chance(20) ? regions : NULL,
                                       base, chance(98) ? &m : NULL),
                  "mesh_create");
        else
            check(meshmove_mesh_create_triangles(nv, chance(97) ? xy : NULL, nc, cells, base, nt, edges, patches,
                                                 chance(20) ? regions : NULL, chance(98) ? &m : NULL),
                  "mesh_create_triangles");
    }
    if (m) {
        check(meshmove_mesh_free(w->mesh[k]), "mesh_free replaced");
        w->mesh[k] = m;
    }
}

static void solver_call(world *w) {
    meshmove_solver *s;
    int k = pick_solver(w, &s), nv = k >= 0 ? w->nv[k] : MAXN * MAXN, dim = k >= 0 ? w->dim[k] : 2;
    int len = count(dim * nv), i;
    double d[CAP], out[CAP], xy[CAP], before[CAP], after[CAP];
    meshmove_report r;
    meshmove_quality q;
    meshmove_step_report sr[4];
    meshmove_status st;
    const char *what = "";
    int32_t n;
    if (len > CAP && len != INT32_MAX) len = CAP;
    memset(d, 0, sizeof d);
    memset(xy, 0, sizeof xy);
    if (k >= 0) check(meshmove_solver_get_coords(s, dim * nv, xy), "get_coords");
    for (i = 0; i < nv; i++)
        if (xy[dim * i + 1] > 0.999) d[dim * i] = value(0.01 * below(20));
    if (k >= 0) check(meshmove_solver_get_coords(s, dim * nv, before), "get_coords");
    switch (below(11)) {
    case 0: st = meshmove_solver_solve(s, len, chance(97) ? d : NULL, chance(20) ? d : NULL, out, chance(50) ? &r : NULL);
        what = "solve";
        if (st == MESHMOVE_STATUS_OK && !finite_all(out, dim * nv)) { fprintf(stderr, "solve: OK, non-finite\n"); failures++; }
        break;
    case 1: memcpy(out, d, sizeof d);
        st = meshmove_solver_cycle(s, len, d, out, &r);
        what = "cycle";
        if (st == MESHMOVE_STATUS_OK && (!finite_all(out, dim * nv) || !isfinite(r.rel_residual))) { fprintf(stderr, "cycle: OK, non-finite\n"); failures++; }
        break;
    case 2: for (i = 0; i < dim * nv; i++) out[i] = xy[i] + (chance(5) ? value(0.3 * (below(3) - 1)) : 0.0);
        st = meshmove_solver_move(s, len, d, out, &r, chance(50) ? &q : NULL);
        what = "move";
        if (st == MESHMOVE_STATUS_OK && !finite_all(out, dim * nv)) { fprintf(stderr, "move: OK, non-finite\n"); failures++; }
        break;
    case 3: st = meshmove_solver_move_in_steps(s, len, d, count(1 + below(3)), count(4) % 5, chance(80) ? sr : NULL);
        what = "move_in_steps";
        break;
    case 4: for (i = 0; i < dim * nv; i++) out[i] = xy[i] + (chance(10) ? value(0.5 * (below(3) - 1)) : 0.0);
        st = meshmove_solver_set_reference(s, len, out);
        what = "set_reference";
        break;
    case 5: st = meshmove_solver_get_displacement(s, len, chance(95) ? out : NULL); what = "get_displacement"; break;
    case 6: st = meshmove_solver_quality(s, len, d, chance(95) ? &q : NULL); what = "quality"; break;
    case 7: st = meshmove_solver_step_reports(s, count(4) % 5, sr, chance(95) ? &n : NULL); what = "step_reports"; break;
    case 8: {
        double t[3] = {value(0.01), 0.0, 0.0}, r[3] = {value(0.1), 0.0, 0.0}, c[3] = {0.5, 0.5, 0.0};
        st = meshmove_solver_set_rigid_motion(s, below(4), t, chance(97) ? r : NULL, c);
        what = "set_rigid_motion";
        break;
    }
    case 9: st = meshmove_solver_clear_rigid_motions(s); what = "clear_rigid_motions"; break;
    default: st = meshmove_solver_sizes(s, chance(50) ? &n : NULL, &n, chance(50) ? &n : NULL); what = "sizes"; break;
    }
    check(st, what);
    if (k >= 0 && st != MESHMOVE_STATUS_OK && st != MESHMOVE_STATUS_NOT_CONVERGED) {
        check(meshmove_solver_get_coords(s, dim * nv, after), "get_coords after");
        if (memcmp(before, after, sizeof(double) * (size_t)dim * (size_t)nv) != 0) {
            fprintf(stderr, "%s failed (%s) and changed the solver's reference\n", what, meshmove_status_name(st));
            failures++;
        }
    }
}

static void step(world *w) {
    int k = below(NH);
    meshmove_options *o = NULL;
    int32_t n, buf[CAP];
    double xy[CAP];
    switch (below(12)) {
    case 0: grid_mesh(w, k); break;
    case 1: {
        /* one quad or tetrahedron with hostile offsets: a type the core may not handle yet */
        static const double xyz[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 1};
        int32_t conn[4] = {0, 1, 2, 3}, off[2] = {0, count(4)}, dim = chance(50) ? 2 : 3;
        int32_t type[1] = {dim == 2 ? MESHMOVE_CELL_TYPE_QUAD : MESHMOVE_CELL_TYPE_TETRA};
        meshmove_mesh *m = NULL;
        check(meshmove_mesh_create(dim, 4, xyz, 1, chance(50) ? off : NULL, count(4) % 5, conn, type, 0, NULL, 0, NULL,
                                   NULL, NULL, 0, &m),
              "mesh_create one cell");
        if (m) {
            check(meshmove_mesh_free(w->mesh[k]), "mesh_free replaced");
            w->mesh[k] = m;
        }
        break;
    }
    case 2: if (w->mesh[k] && chance(30)) {
            check(meshmove_mesh_free(w->mesh[k]), "mesh_free");
            w->stale_mesh = w->mesh[k];
            w->mesh[k] = NULL;
        } else check(meshmove_mesh_free(pick_mesh(w) == w->stale_mesh ? w->stale_mesh : NULL), "mesh_free stale");
        break;
    case 3: {
        meshmove_mesh *m = pick_mesh(w);
        check(meshmove_mesh_sizes(m, NULL, &n, NULL, NULL, NULL, NULL), "mesh_sizes");
        if (m == w->mesh[k] && m) {
            int32_t nc = 0, ncv = 0;
            check(meshmove_mesh_sizes(m, NULL, &n, &nc, &ncv, NULL, NULL), "mesh_sizes");
            check(meshmove_mesh_get_coords(m, count(2 * n), xy), "mesh_get_coords");
            check(meshmove_mesh_patch_vertices(m, below(3), below(3), count(8) % 16, buf, &n), "patch_vertices");
            /* the lists: lengths at most the buffer's (or hostile), types skipped */
            if (ncv + nc + 1 <= CAP) {
                int32_t no = count(nc + 1), nn = count(ncv);
                if (no > nc + 1 && no != INT32_MAX) no = nc + 1;
                if (nn > ncv && nn != INT32_MAX) nn = ncv;
                check(meshmove_mesh_get_cells(m, below(3), no, buf, nn, buf + nc + 1, 0, NULL), "mesh_get_cells");
            }
        }
        break;
    }
    case 4: if (!w->bcs[k]) check(meshmove_bcs_create(&w->bcs[k]), "bcs_create");
        check(meshmove_bcs_set_kind(pick_bcs(w), below(3), below(4) - 1, below(4) - 1), "bcs_set_kind");
        break;
    case 5: check(meshmove_bcs_set_kinds(pick_bcs(w), below(3), below(4)), "bcs_set_kinds");
        if (chance(20)) {
            double off[3] = {value(1.0), 0.0, 0.0};
            check(meshmove_bcs_link_periodic(pick_bcs(w), 0, below(3), 1 + below(3), off, value(1e-9)), "link_periodic");
        }
        break;
    case 6: if (w->bcs[k] && chance(20)) { check(meshmove_bcs_free(w->bcs[k]), "bcs_free"); w->bcs[k] = NULL; }
        break;
    case 7: case 8: {
        meshmove_solver *s = NULL;
        int32_t threads = chance(90) ? 1 : count(2);
        if (threads > 2) threads = chance(50) ? 2 : MESHMOVE_MAX_THREADS + 1;
        check(meshmove_options_create(&o), "options_create");
        /* a refused setter leaves the option as it was: threads stays 1 if it is refused */
        check(meshmove_options_set_threads(o, 1), "options_set_threads");
        check(meshmove_options_set_threads(o, threads), "options_set_threads");
        check(meshmove_options_set_max_cycles(o, chance(80) ? 50 : count(3)), "options_set_max_cycles");
        check(meshmove_options_set_cheb_degree(o, chance(90) ? below(5) : count(MESHMOVE_MAX_CHEB_DEGREE + 1)),
              "options_set_cheb_degree");
        check(meshmove_options_set_method(o, chance(95) ? below(3) : 7), "options_set_method");
        check(meshmove_options_set_tol(o, value(1e-8)), "options_set_tol");
        if (chance(10)) check(meshmove_options_set_substepping(o, count(4), value(0.1)), "options_set_substepping");
        check(meshmove_solver_create(pick_mesh(w), pick_bcs(w), chance(90) ? o : NULL, chance(98) ? &s : NULL),
              "solver_create");
        check(meshmove_options_free(o), "options_free");
        if (s) {
            if (w->solver[k]) check(meshmove_solver_free(w->solver[k]), "solver_free");
            w->solver[k] = s;
            check(meshmove_solver_sizes(s, &w->dim[k], &w->nv[k], NULL), "solver_sizes");
        }
        break;
    }
    case 9: if (w->solver[k] && chance(20)) {
            check(meshmove_solver_free(w->solver[k]), "solver_free");
            w->stale_solver = w->solver[k];
            w->solver[k] = NULL;
        } else check(meshmove_solver_free(w->stale_solver), "solver_free stale");
        break;
    default: solver_call(w); break;
    }
}

/* A valid mesh, boundary conditions and solver in slot 0, so that most sequences reach the
 * solver's deeper paths (solves, moves, steps) rather than only the argument checks. */
static void seed_world(world *w) {
    static double xy[2 * 16];
    static int32_t cells[3 * 18], edges[6] = {12, 13, 13, 14, 14, 15}, patches[3] = {1, 1, 1};
    meshmove_options *o = NULL;
    int i, j, c = 0;
    for (j = 0; j < 4; j++)
        for (i = 0; i < 4; i++) {
            xy[2 * (4 * j + i)] = i / 3.0;
            xy[2 * (4 * j + i) + 1] = j / 3.0;
        }
    for (j = 0; j < 3; j++)
        for (i = 0; i < 3; i++) {
            int32_t a = 4 * j + i, t[6] = {a, a + 1, a + 5, a, a + 5, a + 4};
            memcpy(&cells[3 * c], t, sizeof t);
            c += 2;
        }
    check(meshmove_options_create(&o), "seed options");
    check(meshmove_options_set_threads(o, 1), "seed threads");
    check(meshmove_mesh_create_triangles(16, xy, 18, cells, 0, 3, edges, patches, NULL, &w->mesh[0]), "seed mesh");
    check(meshmove_bcs_create(&w->bcs[0]), "seed bcs");
    check(meshmove_solver_create(w->mesh[0], w->bcs[0], o, &w->solver[0]), "seed solver");
    check(meshmove_options_free(o), "seed options free");
    w->nv[0] = 16;
    w->dim[0] = 2;
}

int main(int argc, char **argv) {
    uint64_t seed = argc > 1 ? strtoull(argv[1], NULL, 10) : 1;
    long sequences = argc > 2 ? strtol(argv[2], NULL, 10) : 200, q;
    double seconds = argc > 3 ? strtod(argv[3], NULL) : 20.0, t0 = now();
    int k;
    rng = seed * 0x9E3779B97F4A7C15ULL + 1;
    for (q = 0; q < sequences && now() - t0 < seconds; q++) {
        world w;
        int i;
        memset(&w, 0, sizeof w);
        seed_world(&w);
        for (i = 0; i < 40; i++) step(&w);
        for (k = 0; k < NH; k++) {
            check(meshmove_solver_free(w.solver[k]), "final solver_free");
            check(meshmove_bcs_free(w.bcs[k]), "final bcs_free");
            check(meshmove_mesh_free(w.mesh[k]), "final mesh_free");
            if (w.solver[k] && meshmove_solver_free(w.solver[k]) != MESHMOVE_STATUS_INVALID_HANDLE) {
                fprintf(stderr, "double free accepted\n");
                failures++;
            }
        }
        if (failures) {
            fprintf(stderr, "sequence %ld (seed %llu) failed\n", q, (unsigned long long)seed);
            break;
        }
    }
    printf("fuzz: seed %llu, %ld sequences, %d calls, %d failures, %.1f s\n", (unsigned long long)seed, q, calls, failures,
           now() - t0);
    for (k = 0; k <= LAST_STATUS; k++)
        if (seen[k]) printf("  %-34s %ld\n", meshmove_status_name(k), seen[k]);
    return failures != 0;
}
