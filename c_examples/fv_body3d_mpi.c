/* The mesh motion of fv_body3d.c run as an MPI code runs it: the box [-1,1]^3 as a 12^3 grid of
 * hexahedra without the cells of the body [-1/3,1/3]^3, walls FIXED (patch 1), body CLAMPED
 * (patch 2) and turned rigidly by 5 degrees about the y axis (its held wall spacing turning with
 * it). Every rank owns a slab of cells in x and
 * holds one layer of ghost cells around it, as a finite-volume code's partition does; it hands
 * meshmove its local cells (through the serial meshmove_mesh_create), the global id of each
 * local vertex and its ghost-cell flags, and moves its part with the distributed solver:
 *     meshmove_dist_mesh_create(MPI_COMM_WORLD, local, gids, nv, ghost, nc, &dm);
 *     meshmove_dist_solver_create(dm, bcs, options, &ds);   (the serial options handle)
 *     meshmove_dist_solver_set_rigid_motion(ds, BODY, t, (0, angle, 0), centre);
 *     meshmove_dist_solver_move(ds, boundary_displacement, 3 * nv, xyz, 3 * nv, &report);
 *     meshmove_dist_solver_move_in_steps(ds, motion, 3 * nv, steps, xyz, 3 * nv, n, reports);
 * Each rank checks its part against the serial solver on the whole mesh (to 1e-10 of the motion,
 * both solved to 1e-12): a solve, a move and a move in two steps from the original mesh (the
 * serial calls meshmove_solver_move and _move_in_steps beside them); that the report is the same
 * on every rank and the serial quality's; that the progress callback runs on rank 0 after each
 * step; and that one rank's wrong array length makes every rank return
 * MESHMOVE_STATUS_INVALID_ARGUMENT.
 * Run: mpirun -np 1..4 fv_body3d_mpi */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "meshmove_mpi.h"

#define N 12
#define LO 4
#define HI 8
#define ANGLE (5.0 * 3.14159265358979323846 / 180.0)
enum { WALL = 1, BODY = 2 };
static const double ZERO[3] = {0.0, 0.0, 0.0}, TURN[3] = {0.0, ANGLE, 0.0};

static const int HEX_FACE[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
static const int HEX_DIR[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};

static int vid(int i, int j, int k) { return (k * (N + 1) + j) * (N + 1) + i; }
static int hole(int i, int j, int k) { return i >= LO && i < HI && j >= LO && j < HI && k >= LO && k < HI; }
static int inside(int i, int j, int k) { return i >= 0 && i < N && j >= 0 && j < N && k >= 0 && k < N; }
static int cell_rank(int i, int size) { return i * size / N; }

/* The progress callback: counts the sub-steps it is told of. */
static int count_steps(void *user_data, const meshmove_step_report *report, int32_t steps) {
    (void)report;
    (void)steps;
    ++*(int *)user_data;
    return 0;
}

/* A mesh's arrays: vertices by grid id (local ones renumbered), hexahedra, tagged faces. */
typedef struct {
    int32_t nv, nc, nf;
    double *xyz;
    int32_t *gid, *cells, *offsets, *types, *regions, *ghost, *faces, *face_offsets, *patch;
} part;

/* The cells with owner `rank` among `size` (all cells when size = 0) and, with ghosts, every
 * cell sharing a vertex with them; their vertices and boundary faces. */
static part make_part(int rank, int size) {
    const int NV = (N + 1) * (N + 1) * (N + 1);
    int *touch = calloc(NV, sizeof(int)), *local = malloc(NV * sizeof(int));
    int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    part p;
    memset(&p, 0, sizeof p);
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < N; k++)
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    if (hole(i, j, k)) continue;
                    int own = size == 0 || cell_rank(i, size) == rank, near = 0;
                    for (int c = 0; c < 8; c++) near |= touch[vid(i + corner[c][0], j + corner[c][1], k + corner[c][2])] & 1;
                    if (pass == 0 && own)
                        for (int c = 0; c < 8; c++) touch[vid(i + corner[c][0], j + corner[c][1], k + corner[c][2])] |= 1;
                    if (pass == 1 && (own || near))
                        for (int c = 0; c < 8; c++) touch[vid(i + corner[c][0], j + corner[c][1], k + corner[c][2])] |= 2;
                }
    for (int v = 0; v < NV; v++) local[v] = (touch[v] & 2) ? p.nv++ : -1;
    p.xyz = malloc(3 * p.nv * sizeof(double));
    p.gid = malloc(p.nv * sizeof(int32_t));
    for (int k = 0; k <= N; k++)
        for (int j = 0; j <= N; j++)
            for (int i = 0; i <= N; i++) {
                int l = local[vid(i, j, k)];
                if (l < 0) continue;
                p.xyz[3 * l] = -1.0 + 2.0 * i / N;
                p.xyz[3 * l + 1] = -1.0 + 2.0 * j / N;
                p.xyz[3 * l + 2] = -1.0 + 2.0 * k / N;
                p.gid[l] = vid(i, j, k);
            }
    int maxc = N * N * N;
    p.cells = malloc(8 * maxc * sizeof(int32_t));
    p.offsets = malloc((maxc + 1) * sizeof(int32_t));
    p.types = malloc(maxc * sizeof(int32_t));
    p.regions = calloc(maxc, sizeof(int32_t));
    p.ghost = malloc(maxc * sizeof(int32_t));
    p.faces = malloc(24 * maxc * sizeof(int32_t));
    p.face_offsets = malloc((6 * maxc + 1) * sizeof(int32_t));
    p.patch = malloc(6 * maxc * sizeof(int32_t));
    p.offsets[0] = p.face_offsets[0] = 0;
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                if (hole(i, j, k)) continue;
                int own = size == 0 || cell_rank(i, size) == rank, v[8], all = 1;
                for (int c = 0; c < 8; c++) {
                    v[c] = local[vid(i + corner[c][0], j + corner[c][1], k + corner[c][2])];
                    all &= v[c] >= 0;
                }
                int near = 0;
                for (int c = 0; c < 8; c++) near |= touch[vid(i + corner[c][0], j + corner[c][1], k + corner[c][2])] & 1;
                if (!(own || near) || !all) continue;
                for (int c = 0; c < 8; c++) p.cells[8 * p.nc + c] = v[c];
                p.types[p.nc] = MESHMOVE_CELL_TYPE_HEXAHEDRON;
                p.ghost[p.nc] = !own;
                p.offsets[p.nc + 1] = 8 * (p.nc + 1);
                p.nc++;
                for (int f = 0; f < 6; f++) {
                    int a = i + HEX_DIR[f][0], b = j + HEX_DIR[f][1], c = k + HEX_DIR[f][2];
                    if (inside(a, b, c) && !hole(a, b, c)) continue;
                    for (int q = 0; q < 4; q++) p.faces[4 * p.nf + q] = v[HEX_FACE[f][q]];
                    p.patch[p.nf] = inside(a, b, c) ? BODY : WALL;
                    p.face_offsets[p.nf + 1] = 4 * (p.nf + 1);
                    p.nf++;
                }
            }
    free(touch);
    free(local);
    return p;
}

static void free_part(part *p) {
    free(p->xyz); free(p->gid); free(p->cells); free(p->offsets); free(p->types); free(p->regions);
    free(p->ghost); free(p->faces); free(p->face_offsets); free(p->patch);
}

static meshmove_mesh *mesh_of(const part *p) {
    meshmove_mesh *m = NULL;
    CHECK(meshmove_mesh_create(3, p->nv, p->xyz, p->nc, p->offsets, 8 * p->nc, p->cells, p->types, p->nf,
                               p->face_offsets, 4 * p->nf, p->faces, p->patch, p->regions, 0, &m));
    return m;
}

/* The body turned by ANGLE about the y axis through the origin (what its rigid motion gives
 * too); nothing else moves. */
static void boundary_motion(const part *p, double *d) {
    const double a = ANGLE;
    for (int v = 0; v < p->nv; v++) {
        const double *x = p->xyz + 3 * v;
        int on_body = fabs(x[0]) <= 1.0 / 3 + 1e-12 && fabs(x[1]) <= 1.0 / 3 + 1e-12 && fabs(x[2]) <= 1.0 / 3 + 1e-12;
        d[3 * v] = on_body ? cos(a) * x[0] + sin(a) * x[2] - x[0] : 0.0;
        d[3 * v + 1] = 0.0;
        d[3 * v + 2] = on_body ? -sin(a) * x[0] + cos(a) * x[2] - x[2] : 0.0;
    }
}

int main(int argc, char **argv) {
    MPI_Init(&argc, &argv);
    int rank, size, failed = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    meshmove_bcs *bcs = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, BODY, MESHMOVE_KIND_CLAMPED));

    /* The serial reference on the whole mesh, on every rank. */
    part whole = make_part(0, 0);
    meshmove_mesh *wm = mesh_of(&whole);
    meshmove_options *o = NULL;
    CHECK(meshmove_options_create(&o));
    CHECK(meshmove_options_set_tol(o, 1e-12));
    /* The biharmonic's distributed solve is preconditioned by its smoother alone: more iterations. */
    CHECK(meshmove_options_set_max_cycles(o, 5000));
    CHECK(meshmove_options_set_reference_mode(o, MESHMOVE_REFERENCE_ORIGINAL));
    meshmove_solver *serial = NULL;
    CHECK(meshmove_solver_create(wm, bcs, o, &serial));
    CHECK(meshmove_solver_set_rigid_motion(serial, BODY, ZERO, TURN, ZERO));
    double *dw = malloc(3 * whole.nv * sizeof(double)), *ref = malloc(3 * whole.nv * sizeof(double));
    boundary_motion(&whole, dw);
    CHECK(meshmove_solver_solve(serial, 3 * whole.nv, dw, NULL, ref, NULL));
    double scale = 0.0;
    for (int i = 0; i < 3 * whole.nv; i++) scale = fmax(scale, fabs(ref[i]));
    int *at = malloc((N + 1) * (N + 1) * (N + 1) * sizeof(int));
    for (int v = 0; v < whole.nv; v++) at[whole.gid[v]] = v;

    /* This rank's part, moved by the distributed solver. */
    part p = make_part(rank, size);
    meshmove_mesh *lm = mesh_of(&p);
    int64_t *gids = malloc(p.nv * sizeof(int64_t));
    for (int v = 0; v < p.nv; v++) gids[v] = p.gid[v];
    meshmove_dist_mesh *dm = NULL;
    CHECK(meshmove_dist_mesh_create(MPI_COMM_WORLD, lm, gids, p.nv, p.ghost, p.nc, &dm));
    CHECK(meshmove_mesh_free(lm));
    meshmove_dist_solver *ds = NULL;
    CHECK(meshmove_dist_solver_create(dm, bcs, o, &ds));
    CHECK(meshmove_dist_solver_set_rigid_motion(ds, BODY, ZERO, TURN, ZERO));
    double *d = malloc(3 * p.nv * sizeof(double)), *out = malloc(3 * p.nv * sizeof(double));
    double *xyz = malloc(3 * p.nv * sizeof(double));
    boundary_motion(&p, d);
    meshmove_dist_report rep;
    CHECK(meshmove_dist_solver_solve(ds, d, 3 * p.nv, out, 3 * p.nv, &rep));
    double worst = 0.0;
    for (int v = 0; v < p.nv; v++)
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(out[3 * v + c] - ref[3 * at[p.gid[v]] + c]));
    if (worst > 1e-10 * scale) {
        fprintf(stderr, "rank %d: differs from the serial solver by %.3e (motion %.3e)\n", rank, worst, scale);
        failed = 1;
    }
    meshmove_quality q;
    CHECK(meshmove_solver_quality(serial, 3 * whole.nv, ref, &q));
    if (rep.inverted != q.inverted || fabs(rep.min_area_ratio - q.min_volume_ratio) > 1e-9) {
        fprintf(stderr, "rank %d: quality %d %.12f, serial %d %.12f\n", rank, rep.inverted, rep.min_area_ratio,
                q.inverted, q.min_volume_ratio);
        failed = 1;
    }
    /* The same report on every rank. */
    double mine[2] = {rep.min_area_ratio, (double)rep.iterations}, lo[2], hi[2];
    MPI_Allreduce(mine, lo, 2, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(mine, hi, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (lo[0] != hi[0] || lo[1] != hi[1]) {
        fprintf(stderr, "rank %d: the ranks' reports differ\n", rank);
        failed = 1;
    }
    /* The step: the moved positions become the current mesh, here and serially. */
    memcpy(xyz, p.xyz, 3 * p.nv * sizeof(double));
    CHECK(meshmove_dist_solver_move(ds, d, 3 * p.nv, xyz, 3 * p.nv, &rep));
    for (int i = 0; i < 3 * p.nv; i++)
        if (fabs(xyz[i] - (p.xyz[i] + out[i])) > 1e-14) {
            fprintf(stderr, "rank %d: the moved position %d is not the solved one\n", rank, i);
            failed = 1;
            break;
        }
    double *wxyz = malloc(3 * whole.nv * sizeof(double));
    memcpy(wxyz, whole.xyz, 3 * whole.nv * sizeof(double));
    CHECK(meshmove_solver_move(serial, 3 * whole.nv, dw, wxyz, NULL, NULL));
    /* Two more steps of the turn (the total of the call) from the original mesh, with rank 0's
     * progress callback. */
    int told = 0;
    CHECK(meshmove_dist_solver_set_progress(ds, count_steps, &told));
    meshmove_dist_step_report steps[4];
    CHECK(meshmove_dist_solver_move_in_steps(ds, d, 3 * p.nv, 2, xyz, 3 * p.nv, 4, steps));
    CHECK(meshmove_solver_move_in_steps(serial, 3 * whole.nv, dw, 2, 0, NULL));
    CHECK(meshmove_solver_get_coords(serial, 3 * whole.nv, wxyz));
    double off = 0.0;
    for (int v = 0; v < p.nv; v++)
        for (int c = 0; c < 3; c++) off = fmax(off, fabs(xyz[3 * v + c] - wxyz[3 * at[p.gid[v]] + c]));
    int32_t nsteps = 0;
    meshmove_status asked = meshmove_dist_solver_step_reports(ds, 0, NULL, &nsteps);
    if (asked != MESHMOVE_STATUS_BUFFER_TOO_SMALL || off > 1e-10 * scale || nsteps != 2 || !steps[1].step.accepted || told != (rank == 0 ? 2 : 0)) {
        fprintf(stderr, "rank %d: in steps: differs from the serial solver by %.3e, %d step reports, told of %d\n",
                rank, off, (int)nsteps, told);
        failed = 1;
    }
    /* One rank's wrong length: every rank returns the error. */
    int len = rank == size - 1 ? 3 * p.nv - 1 : 3 * p.nv;
    meshmove_status st = meshmove_dist_solver_solve(ds, d, len, out, 3 * p.nv, NULL);
    if (st != MESHMOVE_STATUS_INVALID_ARGUMENT) {
        fprintf(stderr, "rank %d: a wrong length on rank %d gave status %d\n", rank, size - 1, (int)st);
        failed = 1;
    }
    if (rank == 0)
        printf("fv_body3d_mpi on %d ranks: %d vertices, %d iterations, largest difference %.2e of the motion "
               "(in two steps %.2e, %d and %d iterations), min volume ratio %.6f on rank %d\n",
               size, whole.nv, rep.iterations, worst / scale, off / scale, steps[0].step.cycles, steps[1].step.cycles,
               rep.min_area_ratio, rep.worst_rank);
    CHECK(meshmove_dist_solver_free(ds));
    CHECK(meshmove_dist_mesh_free(dm));
    CHECK(meshmove_solver_free(serial));
    CHECK(meshmove_options_free(o));
    CHECK(meshmove_mesh_free(wm));
    CHECK(meshmove_bcs_free(bcs));
    free_part(&p);
    free_part(&whole);
    free(dw); free(ref); free(at); free(gids); free(d); free(out); free(xyz); free(wxyz);
    int any = 0;
    MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return any;
}
