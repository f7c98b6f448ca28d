/* The paper's first case through the C API: the box [0,1]x[-1,0], its top raised to
 * y = 0.25 cos(2 pi x), bottom FIXED, top CLAMPED, sides x-periodic (x CLAMPED, y FREE).
 * The mesh is the code's own: a 32 x 32 grid of quads (box_grid.h), given to meshmove as
 * arrays through the generic meshmove_mesh_create (VTK cell type 9). Usage: free_surface OUT.vtu   (ctest compares OUT.vtu with the Rust library's result) */
#include <math.h>
#include "box_grid.h"
#include "check.h"

enum { BOTTOM = 1, RIGHT = 2, TOP = 3, LEFT = 4 };

int main(int argc, char **argv) {
    const char *out = argc > 1 ? argv[1] : "free_surface_c.vtu";
    const double pi = 3.14159265358979323846;
    int32_t major, minor, patch;
    CHECK(meshmove_version(&major, &minor, &patch));
    if (major != MESHMOVE_VERSION_MAJOR || minor != MESHMOVE_VERSION_MINOR) {
        fprintf(stderr, "header %d.%d does not match library %d.%d\n", MESHMOVE_VERSION_MAJOR,
                MESHMOVE_VERSION_MINOR, major, minor);
        return 1;
    }

    box_grid g;
    box_grid_make(&g, 32, 32, (const double[]){0.0, 1.0, -1.0, 0.0}, 1, (const int32_t[]){BOTTOM, RIGHT, TOP, LEFT});
    meshmove_mesh *mesh = NULL;
    CHECK(box_grid_mesh(&g, &mesh));
    int32_t dim, nv, nc;
    CHECK(meshmove_mesh_sizes(mesh, &dim, &nv, &nc, NULL, NULL, NULL));

    meshmove_bcs *bcs = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, BOTTOM, MESHMOVE_KIND_FIXED));
    CHECK(meshmove_bcs_set_kinds(bcs, TOP, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, LEFT, 0, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, LEFT, 1, MESHMOVE_KIND_FREE));
    CHECK(meshmove_bcs_set_kind(bcs, RIGHT, 0, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, RIGHT, 1, MESHMOVE_KIND_FREE));
    CHECK(meshmove_bcs_link_periodic(bcs, LEFT, RIGHT, 2, (const double[]){1.0, 0.0}, 1e-9));

    meshmove_options *opts = NULL;
    CHECK(meshmove_options_create(&opts)); /* the defaults; meshmove_options_set_* change them */
    meshmove_solver *solver = NULL;
    CHECK(meshmove_solver_create(mesh, bcs, opts, &solver));
    CHECK(meshmove_options_free(opts)); /* the solver keeps its own copy */
    int32_t levels;
    CHECK(meshmove_solver_sizes(solver, NULL, NULL, &levels));

    /* The top row of the grid rises to 0.25 cos(2 pi x). */
    double *d = calloc((size_t)dim * (size_t)nv, sizeof(double));
    for (int32_t i = 0; i <= g.nx; i++) {
        int32_t v = g.ny * (g.nx + 1) + i;
        d[dim * v + 1] = 0.25 * cos(2.0 * pi * g.xy[2 * v]);
    }

    meshmove_report rep;
    meshmove_quality q;
    CHECK(meshmove_solver_solve(solver, dim * nv, d, NULL, d, &rep));
    CHECK(meshmove_solver_quality(solver, dim * nv, d, &q));
    printf("free_surface (C): %d vertices, %d cells, %d levels\n", nv, nc, levels);
    printf("  %d cycles, rel residual %.3e, max correction %.3e, converged %d, %.3f s\n", rep.cycles,
           rep.rel_residual, rep.max_correction, rep.converged, rep.seconds);
    printf("  inverted %d, area ratio %.4f..%.4f, min angle %.2f deg\n", q.inverted, q.min_volume_ratio,
           q.max_volume_ratio, q.min_angle_deg);
    CHECK(meshmove_solver_write_vtu(solver, out, dim * nv, d));

    int ok = rep.converged && q.inverted == 0;
    free(d);
    box_grid_free(&g);
    CHECK(meshmove_solver_free(solver));
    CHECK(meshmove_bcs_free(bcs));
    CHECK(meshmove_mesh_free(mesh));
    return ok ? 0 : 1;
}
