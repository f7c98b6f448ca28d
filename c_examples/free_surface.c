/* The paper's first case through the C API: the box [0,1]x[-1,0], its top raised to
 * y = 0.25 cos(2 pi x), bottom FIXED, top CLAMPED, sides x-periodic (x CLAMPED, y FREE).
 * Usage: free_surface OUT.vtu   (ctest compares OUT.vtu with the Rust library's result) */
#include <math.h>
#include "check.h"

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

    meshmove_mesh *mesh = NULL;
    CHECK(meshmove_mesh_create_case("free_surface", 1.0 / 32.0, &mesh));
    int32_t nv, nc;
    CHECK(meshmove_mesh_sizes(mesh, &nv, &nc));

    meshmove_bcs *bcs = NULL;
    CHECK(meshmove_bcs_create(&bcs));
    CHECK(meshmove_bcs_set_kinds(bcs, MESHMOVE_FS_BOTTOM, MESHMOVE_KIND_FIXED));
    CHECK(meshmove_bcs_set_kinds(bcs, MESHMOVE_FS_TOP, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, MESHMOVE_FS_LEFT, 0, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, MESHMOVE_FS_LEFT, 1, MESHMOVE_KIND_FREE));
    CHECK(meshmove_bcs_set_kind(bcs, MESHMOVE_FS_RIGHT, 0, MESHMOVE_KIND_CLAMPED));
    CHECK(meshmove_bcs_set_kind(bcs, MESHMOVE_FS_RIGHT, 1, MESHMOVE_KIND_FREE));
    CHECK(meshmove_bcs_link_periodic(bcs, MESHMOVE_FS_LEFT, MESHMOVE_FS_RIGHT, 1.0, 0.0, 1e-9));

    meshmove_options opts;
    CHECK(meshmove_options_default(&opts));
    meshmove_solver *solver = NULL;
    CHECK(meshmove_solver_create(mesh, bcs, &opts, &solver));
    int32_t levels;
    CHECK(meshmove_solver_sizes(solver, NULL, &levels));

    double *xy = malloc(sizeof(double) * 2 * (size_t)nv);
    double *d = calloc(2 * (size_t)nv, sizeof(double));
    int32_t *top = malloc(sizeof(int32_t) * (size_t)nv);
    int32_t ntop;
    CHECK(meshmove_mesh_get_coords(mesh, 2 * nv, xy));
    CHECK(meshmove_mesh_patch_vertices(mesh, MESHMOVE_FS_TOP, 0, nv, top, &ntop));
    for (int32_t i = 0; i < ntop; i++) {
        int32_t v = top[i];
        d[2 * v + 1] = 0.25 * cos(2.0 * pi * xy[2 * v]);
    }

    meshmove_report rep;
    meshmove_quality q;
    CHECK(meshmove_solver_solve(solver, 2 * nv, d, NULL, d, &rep));
    CHECK(meshmove_solver_quality(solver, 2 * nv, d, &q));
    printf("free_surface (C): %d vertices, %d cells, %d levels\n", nv, nc, levels);
    printf("  %d cycles, rel residual %.3e, max correction %.3e, converged %d, %.3f s\n", rep.cycles,
           rep.rel_residual, rep.max_correction, rep.converged, rep.seconds);
    printf("  inverted %d, area ratio %.4f..%.4f, min angle %.2f deg\n", q.inverted, q.min_area_ratio,
           q.max_area_ratio, q.min_angle_deg);
    CHECK(meshmove_solver_write_vtu(solver, out, 2 * nv, d));

    int ok = rep.converged && q.inverted == 0;
    free(xy);
    free(d);
    free(top);
    CHECK(meshmove_solver_free(solver));
    CHECK(meshmove_bcs_free(bcs));
    CHECK(meshmove_mesh_free(mesh));
    return ok ? 0 : 1;
}
