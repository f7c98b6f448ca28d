/* The robustness cases through the C ABI: statuses and step reports of multi-step motions.
 *   - the Laplacian turning a thin ellipse 90 degrees in 10 steps: MESHMOVE_STATUS_TANGLED at
 *     the step that inverts, the solver unchanged, the reports saying which step;
 *   - the biharmonic turning it 270 degrees with sub-stepping: OK, a split step in the reports,
 *     the ellipse where the rotation puts it, no inverted cell; without sub-stepping the last
 *     step's inverted result comes back as MESHMOVE_STATUS_INVERTED;
 *   - a rigid motion moving a FREE component: MESHMOVE_STATUS_INVALID_ARGUMENT;
 *   - an unreachable tolerance: MESHMOVE_STATUS_NOT_CONVERGED, the solver unchanged.
 * Usage: steps tests/data/ellipse_box.msh   (patch 1: the box, patch 2: the ellipse) */
#include <math.h>
#include <string.h>
#include "../../c_examples/check.h"

#define EXPECT(call, want)                                                                      \
    do {                                                                                       \
        meshmove_status s_ = (call);                                                           \
        if (s_ != (want)) {                                                                    \
            fprintf(stderr, "%s:%d: %s gave %d, expected %d: %s\n", __FILE__, __LINE__, #call, \
                    (int)s_, (int)(want), meshmove_last_error());                              \
            return 1;                                                                          \
        }                                                                                      \
    } while (0)

static int32_t nv;
static double *x0;

static meshmove_solver *solver_for(meshmove_mesh *mesh, int32_t method, int32_t max_substeps) {
    meshmove_bcs *bcs = NULL;
    meshmove_solver *s = NULL;
    meshmove_options *o = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, 1, MESHMOVE_KIND_FIXED));
    CHECK(meshmove_bcs_set_kinds(bcs, 2, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_options_create(&o));
    CHECK(meshmove_options_set_method(o, method));
    CHECK(meshmove_solver_create(mesh, bcs, o, &s));
    CHECK(meshmove_solver_set_substepping(s, max_substeps, 0.0));
    CHECK(meshmove_options_free(o));
    CHECK(meshmove_bcs_free(bcs));
    return s;
}

/* Turns `patch` of `s` by `angle` about the origin in the following moves. */
static void turn(meshmove_solver *s, int32_t patch, double angle) {
    const double zero[2] = {0.0, 0.0}, rotation[1] = {angle};
    CHECK(meshmove_solver_set_rigid_motion(s, patch, zero, rotation, zero));
}

/* 1 when the solver's reference is still the original mesh, bitwise. */
static int unchanged(meshmove_solver *s) {
    double *x = malloc(sizeof(double) * 2 * (size_t)nv);
    int same = meshmove_solver_get_coords(s, 2 * nv, x) == MESHMOVE_STATUS_OK &&
               memcmp(x, x0, sizeof(double) * 2 * (size_t)nv) == 0;
    free(x);
    return same;
}

int main(int argc, char **argv) {
    const double pi = 3.14159265358979323846;
    if (argc < 2) {
        fprintf(stderr, "usage: steps ellipse_box.msh\n");
        return 2;
    }
    meshmove_mesh *mesh = NULL;
    CHECK(meshmove_mesh_read_msh(argv[1], &mesh));
    CHECK(meshmove_mesh_sizes(mesh, NULL, &nv, NULL, NULL, NULL, NULL));
    x0 = malloc(sizeof(double) * 2 * (size_t)nv);
    double *zero = calloc(2 * (size_t)nv, sizeof(double));
    CHECK(meshmove_mesh_get_coords(mesh, 2 * nv, x0));
    meshmove_step_report reps[256];
    int32_t n = 0;

    /* The Laplacian tangles the mesh at some step: TANGLED, nothing changed, reports to there. */
    meshmove_solver *lap = solver_for(mesh, MESHMOVE_METHOD_LAPLACIAN, 0);
    turn(lap, 2, 0.5 * pi);
    EXPECT(meshmove_solver_move_in_steps(lap, 2 * nv, zero, 10, 256, reps), MESHMOVE_STATUS_TANGLED);
    CHECK(meshmove_solver_step_reports(lap, 256, reps, &n));
    if (n < 2 || reps[n - 1].inverted == 0 || !reps[n - 1].converged || reps[n - 2].inverted != 0) {
        fprintf(stderr, "laplacian: %d reports, last inverted %d\n", n, n ? reps[n - 1].inverted : -1);
        return 1;
    }
    if (!unchanged(lap)) {
        fprintf(stderr, "laplacian: the failed call changed the solver\n");
        return 1;
    }
    printf("laplacian 90 deg: TANGLED at step %d (%d inverted cells)\n", reps[n - 1].step, reps[n - 1].inverted);

    /* The biharmonic turns it 270 degrees with sub-stepping. */
    meshmove_solver *bih = solver_for(mesh, MESHMOVE_METHOD_BIHARMONIC, 64);
    turn(bih, 2, 1.5 * pi);
    CHECK(meshmove_solver_move_in_steps(bih, 2 * nv, zero, 10, 0, NULL));
    CHECK(meshmove_solver_step_reports(bih, 256, reps, &n));
    int rejected = 0;
    for (int32_t i = 0; i < n; i++) {
        rejected += !reps[i].accepted;
        if (reps[i].accepted && (reps[i].inverted || !reps[i].converged)) {
            fprintf(stderr, "biharmonic: accepted sub-step %d.%d inverted %d\n", reps[i].step, reps[i].substep,
                    reps[i].inverted);
            return 1;
        }
    }
    if (rejected == 0 || reps[n - 1].fraction != 1.0) {
        fprintf(stderr, "biharmonic: %d rejected, last fraction %g\n", rejected, reps[n - 1].fraction);
        return 1;
    }
    printf("biharmonic 270 deg with sub-stepping: %d sub-steps, %d rejected\n", n - rejected, rejected);
    /* Without sub-stepping its last step inverts: the result comes back as INVERTED. */
    meshmove_solver *raw = solver_for(mesh, MESHMOVE_METHOD_BIHARMONIC, 0);
    turn(raw, 2, 1.5 * pi);
    EXPECT(meshmove_solver_move_in_steps(raw, 2 * nv, zero, 10, 256, reps), MESHMOVE_STATUS_INVERTED);

    /* A rigid motion moving a FREE component. */
    meshmove_bcs *bcs = NULL;
    meshmove_solver *free_s = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, 2, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, 2, 0, MESHMOVE_KIND_FREE));
    CHECK(meshmove_solver_create(mesh, bcs, NULL, &free_s));
    turn(free_s, 2, 0.1);
    double *d = calloc(2 * (size_t)nv, sizeof(double));
    EXPECT(meshmove_solver_solve(free_s, 2 * nv, zero, NULL, d, NULL), MESHMOVE_STATUS_INVALID_ARGUMENT);

    /* An unreachable tolerance: NOT_CONVERGED, and _move leaves the coordinates alone. */
    meshmove_options *o = NULL;
    meshmove_solver *tight = NULL;
    CHECK(meshmove_options_create(&o));
    CHECK(meshmove_options_set_tol(o, 1e-30));
    CHECK(meshmove_options_set_max_cycles(o, 20));
    CHECK(meshmove_bcs_set_kinds(bcs, 2, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_solver_create(mesh, bcs, o, &tight));
    CHECK(meshmove_options_free(o));
    CHECK(meshmove_solver_set_rigid_motion(tight, 2, (const double[]){0.05, 0.0}, (const double[]){0.0},
                                           (const double[]){0.0, 0.0}));
    double *x = malloc(sizeof(double) * 2 * (size_t)nv);
    memcpy(x, x0, sizeof(double) * 2 * (size_t)nv);
    EXPECT(meshmove_solver_move(tight, 2 * nv, zero, x, NULL, NULL), MESHMOVE_STATUS_NOT_CONVERGED);
    if (memcmp(x, x0, sizeof(double) * 2 * (size_t)nv) != 0 || !unchanged(tight)) {
        fprintf(stderr, "not converged: the coordinates or the solver changed\n");
        return 1;
    }
    printf("FREE motion refused, unreachable tolerance NOT_CONVERGED: ok\n");

    free(x);
    free(d);
    free(zero);
    free(x0);
    CHECK(meshmove_solver_free(tight));
    CHECK(meshmove_solver_free(free_s));
    CHECK(meshmove_solver_free(raw));
    CHECK(meshmove_solver_free(bih));
    CHECK(meshmove_solver_free(lap));
    CHECK(meshmove_bcs_free(bcs));
    CHECK(meshmove_mesh_free(mesh));
    return 0;
}
