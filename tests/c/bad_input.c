/* Every C entry point with bad input: NULL handles and arrays, negative and out-of-range counts,
 * offsets and indices, unknown cell types, NaN coordinates, degenerate cells, unknown enum values,
 * options out of range, mismatched links, stale and foreign handles. Each call must return the expected status and a message that names the
 * problem. Run under valgrind by ctest: zero errors, nothing definitely lost. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "meshmove.h"

static int failures = 0, checks = 0;

static void expect(int line, meshmove_status got, meshmove_status want, const char *needle) {
    char msg[1024];
    size_t needed = 0;
    meshmove_status s = meshmove_last_error_message(msg, sizeof msg, &needed);
    checks++;
    if (got != want) {
        fprintf(stderr, "line %d: got %s, want %s (%s)\n", line, meshmove_status_name(got), meshmove_status_name(want),
                msg);
        failures++;
        return;
    }
    if (s != MESHMOVE_STATUS_OK || needed != strlen(msg) + 1) {
        fprintf(stderr, "line %d: last_error_message returned %s, needed %zu\n", line, meshmove_status_name(s), needed);
        failures++;
    }
    if (want != MESHMOVE_STATUS_OK && (msg[0] == 0 || (needle && !strstr(msg, needle)))) {
        fprintf(stderr, "line %d: message \"%s\" does not mention \"%s\"\n", line, msg, needle ? needle : "");
        failures++;
    }
    if (want == MESHMOVE_STATUS_OK && msg[0] != 0) {
        fprintf(stderr, "line %d: success left message \"%s\"\n", line, msg);
        failures++;
    }
}
#define EXPECT(call, want, needle) expect(__LINE__, (call), (want), (needle))

/* meshmove_mesh_create_triangles without regions. */
static meshmove_status create_tris(int32_t nv, const double *xy, int32_t nc, const int32_t *cells, int32_t base, int32_t nt,
                            const int32_t *edges, const int32_t *patches, meshmove_mesh **out) {
    return meshmove_mesh_create_triangles(nv, xy, nc, cells, base, nt, edges, patches, NULL, out);
}
#define OK MESHMOVE_STATUS_OK
#define NUL MESHMOVE_STATUS_NULL_POINTER
#define HANDLE MESHMOVE_STATUS_INVALID_HANDLE
#define ARG MESHMOVE_STATUS_INVALID_ARGUMENT

int main(void) {
    /* The unit square split into four triangles around its centre; right side is patch 2. */
    double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5};
    int32_t cells[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    int32_t cells1[12] = {1, 2, 5, 2, 3, 5, 3, 4, 5, 4, 1, 5};
    int32_t tedge[2] = {1, 2}, tpatch[1] = {2};
    meshmove_mesh *mesh = NULL, *m2 = NULL, *m3 = NULL;
    meshmove_bcs *bcs = NULL;
    meshmove_solver *solver = NULL;
    double d[10] = {0}, out[10];
    int32_t n, buf[8];
    meshmove_report rep;
    meshmove_quality q;
    meshmove_options *o = NULL;
    const int32_t T = MESHMOVE_CELL_TYPE_TRIANGLE, tris[4] = {T, T, T, T}, offs[5] = {0, 3, 6, 9, 12};
    const double zero2[2] = {0.0, 0.0}, angle[1] = {0.0};

    /* free(NULL) is fine */
    EXPECT(meshmove_mesh_free(NULL), OK, NULL);
    EXPECT(meshmove_bcs_free(NULL), OK, NULL);
    EXPECT(meshmove_solver_free(NULL), OK, NULL);
    EXPECT(meshmove_options_free(NULL), OK, NULL);
    EXPECT(meshmove_version(NULL, NULL, NULL), OK, NULL);
    EXPECT(meshmove_options_create(NULL), NUL, "out");
    if (strcmp(meshmove_status_name(4), "MESHMOVE_STATUS_INVALID_MESH") || strcmp(meshmove_status_name(-7), "MESHMOVE_STATUS_UNKNOWN")) {
        fprintf(stderr, "status names wrong\n");
        failures++;
    }

    /* mesh_create_triangles */
    EXPECT(create_tris(5, xy, 4, cells, 0, 1, tedge, tpatch, NULL), NUL, "out");
    EXPECT(create_tris(5, NULL, 4, cells, 0, 1, tedge, tpatch, &mesh), NUL, "coords");
    EXPECT(create_tris(5, xy, 4, NULL, 0, 1, tedge, tpatch, &mesh), NUL, "cells");
    EXPECT(create_tris(5, xy, 4, cells, 0, 1, NULL, tpatch, &mesh), NUL, "tagged_edges");
    EXPECT(create_tris(-5, xy, 4, cells, 0, 1, tedge, tpatch, &mesh), ARG, "num_vertices");
    EXPECT(create_tris(5, xy, -1, cells, 0, 1, tedge, tpatch, &mesh), ARG, "num_cells");
    EXPECT(create_tris(5, xy, 4, cells, 0, -1, tedge, tpatch, &mesh), ARG, "num_tagged");
    EXPECT(create_tris(5, xy, 4, cells, 2, 1, tedge, tpatch, &mesh), ARG, "index base");
    EXPECT(create_tris(0, xy, 0, cells, 0, 0, NULL, NULL, &mesh), MESHMOVE_STATUS_INVALID_MESH, "no vertices");
    EXPECT(create_tris(4, xy, 4, cells, 0, 1, tedge, tpatch, &mesh), MESHMOVE_STATUS_INVALID_MESH, "vertex index 4");
    EXPECT(create_tris(5, xy, 4, cells, 1, 1, tedge, tpatch, &mesh), MESHMOVE_STATUS_INVALID_MESH, "index");
    xy[8] = NAN;
    EXPECT(create_tris(5, xy, 4, cells, 0, 1, tedge, tpatch, &mesh), MESHMOVE_STATUS_INVALID_MESH, "non-finite");
    xy[8] = 0.5;
    {
        double flat[6] = {0, 0, 1, 0, 2, 0};
        int32_t tri[3] = {0, 1, 2};
        EXPECT(create_tris(3, flat, 1, tri, 0, 0, NULL, NULL, &mesh), MESHMOVE_STATUS_INVALID_MESH, "zero area");
        int32_t rep3[3] = {0, 1, 1};
        EXPECT(create_tris(3, flat, 1, rep3, 0, 0, NULL, NULL, &mesh), MESHMOVE_STATUS_INVALID_MESH, "repeats");
    }
    {
        int32_t bad_edge[2] = {0, 2};
        EXPECT(create_tris(5, xy, 4, cells, 0, 1, bad_edge, tpatch, &mesh), MESHMOVE_STATUS_INVALID_MESH, "not a face");
    }
    if (mesh != NULL) { fprintf(stderr, "failed create left a handle\n"); failures++; }
    EXPECT(create_tris(5, xy, 4, cells1, 1, 1, (int32_t[]){2, 3}, tpatch, &m2), OK, NULL);

    /* the generic mesh_create: every size, offset, type and index checked, each named */
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, NULL), NUL, "out");
    EXPECT(meshmove_mesh_create(1, 5, xy, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG, "dim is 1");
    EXPECT(meshmove_mesh_create(4, 5, xy, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG, "dim is 4");
    EXPECT(meshmove_mesh_create(3, INT32_MAX / 3 + 1, xy, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG,
           "num_vertices (a 3D mesh)");
    EXPECT(meshmove_mesh_create(2, 5, NULL, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), NUL, "coords");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, NULL, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), NUL, "cell_connectivity");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, cells, NULL, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), NUL, "cell_types");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, -12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG, "num_cell_vertices");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, cells, tris, 1, NULL, -2, tedge, tpatch, NULL, 0, &mesh), ARG, "num_face_vertices");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, cells, tris, -1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG, "num_faces");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, NULL, NULL, 0, &mesh), NUL, "face_patch");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, (int32_t[]){1, 3, 6, 9, 12}, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh),
           ARG, "`cell_offsets[0]` is 1");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, (int32_t[]){0, 3, 7, 9, 12}, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh),
           ARG, "give cell 1 4 vertices");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, (int32_t[]){0, 3, 2, 9, 12}, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh),
           ARG, "decreases");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 11, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG,
           "must be num_cell_vertices, 11");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 11, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG,
           "12 vertex indices are needed, 11 were given");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells, (int32_t[]){T, 0, T, T}, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), ARG,
           "cell 1 has type 0");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells, (int32_t[]){T, T, T, -9}, 1, NULL, 2, tedge, tpatch, NULL, 1, &mesh), ARG,
           "cell 4 has type -9");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells, tris, 1, (int32_t[]){0, 3}, 3, (int32_t[]){1, 2, 3}, tpatch, NULL, 0,
               &mesh), ARG, "give face 0 3 vertices; a face of a 2D mesh has [2]");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells, tris, 1, NULL, 3, tedge, tpatch, NULL, 0, &mesh), ARG, "every face has 2");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells, tris, 1, NULL, 2, (int32_t[]){1, 5}, tpatch, NULL, 0, &mesh),
           MESHMOVE_STATUS_INVALID_MESH, "tagged face 0 refers to vertex index 5, outside 0..5");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells1, tris, 1, NULL, 2, (int32_t[]){2, 3}, tpatch, NULL, 1, &mesh), OK, NULL);
    EXPECT(meshmove_mesh_free(mesh), OK, NULL);
    mesh = NULL;
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells1, tris, 0, NULL, 0, NULL, NULL, NULL, 0, &mesh),
           MESHMOVE_STATUS_INVALID_MESH, "cell 0 refers to vertex index 5, outside 0..5 (numbered from 0");
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, NULL, 13, (int32_t[]){0, 1, 2, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4},
                                (int32_t[]){MESHMOVE_CELL_TYPE_TETRA, T, T, T}, 0, NULL, 0, NULL, NULL, NULL, 0, &mesh),
           MESHMOVE_STATUS_INVALID_MESH, "cell 0 is a tetrahedron, which is not a cell of a 2D mesh");
    {
        /* 4 vertices, 1 quad */
        int32_t quad[4] = {0, 1, 2, 3}, qt[1] = {MESHMOVE_CELL_TYPE_QUAD};
        EXPECT(meshmove_mesh_create(2, 4, xy, 1, NULL, 4, quad, qt, 0, NULL, 0, NULL, NULL, NULL, 0, &mesh), OK, NULL);
        EXPECT(meshmove_mesh_free(mesh), OK, NULL);
        mesh = NULL;
    }
    EXPECT(meshmove_mesh_create(2, 5, xy, 4, offs, 12, cells, tris, 1, NULL, 2, tedge, tpatch, NULL, 0, &mesh), OK, NULL);

    /* read_msh */
    EXPECT(meshmove_mesh_read_msh("/nonexistent/x.msh", &m3), MESHMOVE_STATUS_IO, "nonexistent");
    EXPECT(meshmove_mesh_read_msh(NULL, &m3), NUL, "path");

    /* mesh queries */
    EXPECT(meshmove_mesh_sizes(NULL, &n, &n, NULL, NULL, NULL, NULL), NUL, "mesh");
    EXPECT(meshmove_mesh_sizes(mesh, NULL, &n, NULL, NULL, NULL, NULL), OK, NULL);
    EXPECT(meshmove_mesh_sizes(mesh, (int32_t *)((char *)buf + 1), NULL, NULL, NULL, NULL, NULL), ARG, "aligned");
    EXPECT(meshmove_mesh_get_coords(mesh, 9, out), ARG, "length 9");
    EXPECT(meshmove_mesh_get_coords(mesh, -2, out), ARG, "negative");
    EXPECT(meshmove_mesh_get_coords(mesh, 10, NULL), NUL, "coords");
    EXPECT(meshmove_mesh_get_coords(mesh, 10, out), OK, NULL);
    {
        int32_t off[5], conn[12], ty[4];
        EXPECT(meshmove_mesh_get_cells(mesh, 0, 5, off, 11, conn, 4, ty), ARG, "`connectivity` has length 11");
        EXPECT(meshmove_mesh_get_cells(mesh, 0, 5, off, 12, NULL, 4, ty), NUL, "connectivity");
        EXPECT(meshmove_mesh_get_cells(mesh, 3, 5, off, 12, conn, 4, ty), ARG, "index base");
        EXPECT(meshmove_mesh_get_cells(mesh, 0, 0, NULL, 0, NULL, 0, NULL), OK, NULL);
        EXPECT(meshmove_mesh_get_faces(mesh, 0, 4, off, 8, conn, 4, ty), ARG, "`offsets` has length 4");
        EXPECT(meshmove_mesh_get_faces(mesh, 1, 5, off, 8, conn, 4, ty), OK, NULL);
    }
    EXPECT(meshmove_mesh_get_regions(mesh, 3, buf), ARG, "len");
    EXPECT(meshmove_mesh_patch_vertices(mesh, 2, 0, 1, buf, &n), MESHMOVE_STATUS_BUFFER_TOO_SMALL, "capacity");
    if (n != 2) { fprintf(stderr, "patch 2 count %d\n", n); failures++; }
    EXPECT(meshmove_mesh_patch_vertices(mesh, 2, 0, 8, buf, NULL), NUL, "count");
    EXPECT(meshmove_mesh_patch_vertices(mesh, 2, 0, -1, buf, &n), ARG, "capacity");
    EXPECT(meshmove_mesh_patch_vertices(mesh, 2, 1, 8, buf, &n), OK, NULL);
    if (n != 2 || buf[0] != 2 || buf[1] != 3) { fprintf(stderr, "patch 2 vertices wrong\n"); failures++; }
    EXPECT(meshmove_mesh_write_vtu(mesh, NULL, 0, NULL), NUL, "path");
    EXPECT(meshmove_mesh_write_vtu(mesh, "/nonexistent/dir/x.vtu", 0, NULL), MESHMOVE_STATUS_IO, "nonexistent");
    EXPECT(meshmove_mesh_write_vtu(mesh, "bad_input_mesh.vtu", 4, d), ARG, "length 4");

    /* bcs */
    EXPECT(meshmove_bcs_create(NULL), NUL, "out");
    EXPECT(meshmove_bcs_create(&bcs), OK, NULL);
    EXPECT(meshmove_bcs_set_kind(NULL, 0, 0, MESHMOVE_KIND_FIXED), NUL, "bcs");
    /* z (component 2) is a component of 3D meshes: accepted, and ignored on a 2D mesh */
    EXPECT(meshmove_bcs_set_kind(bcs, 0, 2, MESHMOVE_KIND_FIXED), OK, NULL);
    EXPECT(meshmove_bcs_set_kind(bcs, 0, 3, MESHMOVE_KIND_FIXED), ARG, "component 3");
    EXPECT(meshmove_bcs_set_kind(bcs, 0, -1, MESHMOVE_KIND_FIXED), ARG, "component -1");
    EXPECT(meshmove_bcs_set_kind(bcs, 0, 0, 7), ARG, "kind 7");
    EXPECT(meshmove_bcs_set_kinds(bcs, 0, -3), ARG, "kind -3");
    EXPECT(meshmove_bcs_set_default_kind(bcs, 99), ARG, "kind 99");
    EXPECT(meshmove_bcs_set_interface(bcs, 3, 5), ARG, "interface variant 5");
    EXPECT(meshmove_bcs_link_periodic(bcs, 1, 1, 2, (double[]){1.0, 0.0}, 1e-9), ARG, "itself");
    EXPECT(meshmove_bcs_link_periodic(bcs, 1, 2, 2, (double[]){NAN, 0.0}, 1e-9), ARG, "not finite");
    EXPECT(meshmove_bcs_link_periodic(bcs, 1, 2, 2, (double[]){1.0, 0.0}, -1.0), ARG, "tol");
    EXPECT(meshmove_bcs_link_periodic(bcs, 1, 2, 2, NULL, 1e-9), NUL, "offset");
    EXPECT(meshmove_bcs_link_periodic(bcs, 1, 2, 5, (double[]){1.0, 0.0}, 1e-9), ARG, "dim is 5");
    {
        /* A 3D offset is taken by the conditions; a z component is refused when a 2D solver
         * resolves the link (tests/bad_input.rs). */
        meshmove_bcs *b3 = NULL;
        EXPECT(meshmove_bcs_create(&b3), OK, NULL);
        EXPECT(meshmove_bcs_link_periodic(b3, 1, 2, 3, (double[]){1.0, 0.0, 0.0}, 1e-9), OK, NULL);
        EXPECT(meshmove_bcs_free(b3), OK, NULL);
    }
    EXPECT(meshmove_bcs_link_pairs(bcs, -1, buf, 0), ARG, "num_pairs");
    EXPECT(meshmove_bcs_link_pairs(bcs, 0, buf, 0), ARG, "num_pairs");
    EXPECT(meshmove_bcs_link_pairs(bcs, 1, NULL, 0), NUL, "pairs");
    EXPECT(meshmove_bcs_link_pairs(bcs, 1, (int32_t[]){0, 1}, 1), ARG, "below the index base");
    EXPECT(meshmove_bcs_link_pairs(bcs, 1, (int32_t[]){1, 1}, 0), ARG, "itself");
    EXPECT(meshmove_bcs_set_kinds(bcs, 0, MESHMOVE_KIND_FIXED), OK, NULL);
    EXPECT(meshmove_bcs_set_kinds(bcs, 2, MESHMOVE_KIND_FIXED), OK, NULL);

    /* wrong handle types and unknown patches */
    EXPECT(meshmove_mesh_sizes((meshmove_mesh *)bcs, &n, &n, NULL, NULL, NULL, NULL), HANDLE,
           "meshmove_bcs handle, not a meshmove_mesh");
    EXPECT(meshmove_bcs_free((meshmove_bcs *)mesh), HANDLE, "not a meshmove_bcs");
    EXPECT(meshmove_mesh_sizes((meshmove_mesh *)xy, &n, &n, NULL, NULL, NULL, NULL), HANDLE,
           "not a meshmove_mesh handle made by meshmove");
    EXPECT(meshmove_options_set_tol((meshmove_options *)bcs, 1.0), HANDLE, "meshmove_bcs handle, not a meshmove_options");

    /* solver_create */
    EXPECT(meshmove_solver_create(mesh, bcs, NULL, NULL), NUL, "out");
    EXPECT(meshmove_solver_create(NULL, bcs, NULL, &solver), NUL, "mesh");
    EXPECT(meshmove_solver_create(mesh, NULL, NULL, &solver), NUL, "bcs");
    /* options: every setter checks its value, names it and leaves the options as they were */
    EXPECT(meshmove_options_create(&o), OK, NULL);
    EXPECT(meshmove_options_set_method(NULL, 0), NUL, "options");
    EXPECT(meshmove_options_set_method(o, 3), ARG, "method 3");
    EXPECT(meshmove_options_set_mode(o, -1), ARG, "mode -1");
    EXPECT(meshmove_options_set_criterion(o, 2), ARG, "criterion 2");
    EXPECT(meshmove_options_set_tol(o, NAN), ARG, "tol is");
    EXPECT(meshmove_options_set_tol(o, 0.0), ARG, "tol is 0");
    EXPECT(meshmove_options_set_threads(o, -2), ARG, "threads is -2");
    EXPECT(meshmove_options_set_threads(o, MESHMOVE_MAX_THREADS + 1), ARG, "threads is 1025");
    EXPECT(meshmove_options_set_max_cycles(o, 0), ARG, "max_cycles is 0");
    EXPECT(meshmove_options_set_max_cycles(o, MESHMOVE_MAX_CYCLES + 1), ARG, "max_cycles");
    EXPECT(meshmove_options_set_cheb_degree(o, MESHMOVE_MAX_CHEB_DEGREE + 1), ARG, "cheb_degree is 65");
    EXPECT(meshmove_options_set_cheb_coarse_degree(o, -1), ARG, "cheb_coarse_degree is -1");
    EXPECT(meshmove_options_set_cheb_lower_ratio(o, 0.5), ARG, "cheb_lower_ratio");
    EXPECT(meshmove_options_set_substepping(o, -1, 0.0), ARG, "max_substeps");
    EXPECT(meshmove_options_set_substepping(o, 2, NAN), ARG, "min_volume_ratio");
    EXPECT(meshmove_options_set_reference_mode(o, 7), ARG, "reference mode 7");
    EXPECT(meshmove_solver_create(mesh, bcs, o, &solver), OK, NULL); /* the defaults, unchanged */
    EXPECT(meshmove_solver_free(solver), OK, NULL);
    solver = NULL;
    EXPECT(meshmove_solver_create(mesh, bcs, (meshmove_options *)bcs, &solver), HANDLE, "not a meshmove_options");
    {
        meshmove_bcs *b2 = NULL;
        EXPECT(meshmove_bcs_create(&b2), OK, NULL);
        EXPECT(meshmove_bcs_set_kinds(b2, 42, MESHMOVE_KIND_FIXED), OK, NULL);
        EXPECT(meshmove_solver_create(mesh, b2, NULL, &solver), MESHMOVE_STATUS_INVALID_BCS, "patch 42");
        EXPECT(meshmove_bcs_free(b2), OK, NULL);
        EXPECT(meshmove_bcs_create(&b2), OK, NULL);
        EXPECT(meshmove_bcs_set_default_kind(b2, MESHMOVE_KIND_FREE), OK, NULL);
        EXPECT(meshmove_solver_create(mesh, b2, NULL, &solver), MESHMOVE_STATUS_ILL_POSED, "no prescribed");
        EXPECT(meshmove_bcs_free(b2), OK, NULL);
        /* mismatched periodic link: patch 0 (three sides) cannot map onto patch 2 by (1, 0) */
        EXPECT(meshmove_bcs_create(&b2), OK, NULL);
        EXPECT(meshmove_bcs_link_periodic(b2, 0, 2, 2, (double[]){1.0, 0.0}, 1e-9), OK, NULL);
        EXPECT(meshmove_solver_create(mesh, b2, NULL, &solver), MESHMOVE_STATUS_INVALID_BCS, NULL);
        EXPECT(meshmove_bcs_free(b2), OK, NULL);
        /* link pair index beyond the mesh */
        EXPECT(meshmove_bcs_create(&b2), OK, NULL);
        EXPECT(meshmove_bcs_link_pairs(b2, 1, (int32_t[]){0, 77}, 0), OK, NULL);
        EXPECT(meshmove_solver_create(mesh, b2, NULL, &solver), MESHMOVE_STATUS_INVALID_BCS, "77");
        EXPECT(meshmove_bcs_free(b2), OK, NULL);
    }
    EXPECT(meshmove_solver_create(mesh, bcs, NULL, &solver), OK, NULL);

    /* solver calls */
    EXPECT(meshmove_solver_sizes(NULL, &n, &n, &n), NUL, "solver");
    EXPECT(meshmove_solver_sizes((meshmove_solver *)mesh, &n, &n, &n), HANDLE, "meshmove_mesh handle");
    EXPECT(meshmove_solver_sizes(solver, &n, NULL, NULL), OK, NULL);
    if (n != 2) { fprintf(stderr, "solver dim %d\n", n); failures++; }
    EXPECT(meshmove_solver_set_rigid_motion(solver, 9, zero2, angle, zero2), ARG, "patch 9");
    EXPECT(meshmove_solver_set_rigid_motion(solver, 2, (double[]){NAN, 0.0}, angle, zero2), ARG, "not finite");
    EXPECT(meshmove_solver_set_rigid_motion(solver, 2, zero2, (double[]){INFINITY}, zero2), ARG, "not finite");
    EXPECT(meshmove_solver_set_rigid_motion(solver, 2, NULL, angle, zero2), NUL, "translation");
    EXPECT(meshmove_solver_set_rigid_motion(solver, 2, zero2, angle, NULL), NUL, "center");
    EXPECT(meshmove_solver_set_rigid_motion(solver, 2, zero2, angle, zero2), OK, NULL);
    EXPECT(meshmove_solver_clear_rigid_motions(solver), OK, NULL);
    EXPECT(meshmove_solver_clear_rigid_motions(NULL), NUL, "solver");
    EXPECT(meshmove_solver_solve(solver, 10, NULL, NULL, out, &rep), NUL, "prescribed");
    EXPECT(meshmove_solver_solve(solver, 10, d, NULL, NULL, &rep), NUL, "displacement");
    EXPECT(meshmove_solver_solve(solver, 8, d, NULL, out, &rep), ARG, "length 8");
    EXPECT(meshmove_solver_solve(solver, -10, d, NULL, out, &rep), ARG, "negative");
    d[5] = NAN;
    EXPECT(meshmove_solver_solve(solver, 10, d, NULL, out, &rep), ARG, "not finite");
    d[5] = 0.0;
    {
        double g[10] = {0};
        g[9] = INFINITY;
        EXPECT(meshmove_solver_solve(solver, 10, d, g, out, &rep), ARG, "not finite");
    }
    d[4] = 0.1; /* vertex 2 (right side) moves in x */
    EXPECT(meshmove_solver_solve(solver, 10, d, NULL, out, &rep), OK, NULL);
    EXPECT(meshmove_solver_solve(solver, 10, d, NULL, out, NULL), OK, NULL);
    EXPECT(meshmove_solver_cycle(solver, 10, d, NULL, &rep), NUL, "displacement");
    EXPECT(meshmove_solver_cycle(solver, 11, d, out, &rep), ARG, "length 11");
    EXPECT(meshmove_solver_cycle(solver, 10, d, out, &rep), OK, NULL);
    EXPECT(meshmove_solver_move_in_steps(solver, 10, d, 0, 0, NULL), ARG, "steps is 0");
    EXPECT(meshmove_solver_move_in_steps(solver, 10, d, -3, 0, NULL), ARG, "steps");
    EXPECT(meshmove_solver_move_in_steps(solver, 10, d, 2, -1, NULL), ARG, "num_reports");
    EXPECT(meshmove_solver_move_in_steps(solver, 10, d, 2, 2, NULL), NUL, "reports");
    EXPECT(meshmove_solver_move_in_steps(solver, 10, d, MESHMOVE_MAX_STEPS + 1, 0, NULL), ARG, "1000000");
    EXPECT(meshmove_solver_step_reports(solver, 0, NULL, NULL), NUL, "count");
    EXPECT(meshmove_solver_step_reports(solver, -1, NULL, &n), ARG, "capacity");
    EXPECT(meshmove_solver_move_in_steps(solver, 10, NULL, 2, 0, NULL), NUL, "prescribed");
    EXPECT(meshmove_solver_quality(solver, 10, d, NULL), NUL, "quality");
    EXPECT(meshmove_solver_quality(solver, 10, NULL, &q), NUL, "displacement");
    EXPECT(meshmove_solver_quality(solver, 10, out, &q), OK, NULL);
    EXPECT(meshmove_solver_get_coords(solver, 3, out), ARG, "length 3");
    EXPECT(meshmove_solver_get_displacement(solver, 10, NULL), NUL, "displacement");
    EXPECT(meshmove_solver_set_reference(solver, 10, NULL), NUL, "coords");
    {
        double x2[10];
        memcpy(x2, xy, sizeof x2);
        x2[3] = NAN;
        EXPECT(meshmove_solver_set_reference(solver, 10, x2), ARG, "not finite");
        EXPECT(meshmove_solver_move(solver, 10, d, x2, &rep, &q), ARG, "not finite");
        memcpy(x2, xy, sizeof x2);
        EXPECT(meshmove_solver_move(solver, 10, NULL, x2, &rep, &q), NUL, "boundary_displacement");
        EXPECT(meshmove_solver_move(solver, 10, d, NULL, &rep, &q), NUL, "coords");
        EXPECT(meshmove_solver_move(solver, 12, d, x2, &rep, &q), ARG, "length 12");
        EXPECT(meshmove_solver_move(solver, 10, d, x2, &rep, &q), OK, NULL);
        if (fabs(x2[4] - 1.1) > 1e-15 || q.inverted) { fprintf(stderr, "move did not move vertex 2\n"); failures++; }
    }
    EXPECT(meshmove_solver_write_vtu(solver, NULL, 0, NULL), NUL, "path");
    EXPECT(meshmove_solver_write_vtu(solver, "bad_input_solver.vtu", 10, NULL), NUL, "displacement");

    /* buffers of the last error message */
    EXPECT(meshmove_solver_write_vtu(solver, NULL, 0, NULL), NUL, "path");
    {
        char small[8];
        size_t needed = 0;
        meshmove_status s = meshmove_last_error_message(small, sizeof small, &needed);
        checks++;
        if (s != MESHMOVE_STATUS_BUFFER_TOO_SMALL || strlen(small) != 7 || needed < 10) {
            fprintf(stderr, "truncation: %s, \"%s\", needed %zu\n", meshmove_status_name(s), small, needed);
            failures++;
        }
        checks++;
        if (meshmove_last_error_message(NULL, 4, NULL) != NUL) { fprintf(stderr, "NULL buffer accepted\n"); failures++; }
        checks++;
        if (strstr(meshmove_last_error(), "path") == NULL) { fprintf(stderr, "last_error pointer wrong\n"); failures++; }
    }

    /* stale handles: freed twice, used after free */
    EXPECT(meshmove_solver_free(solver), OK, NULL);
    EXPECT(meshmove_solver_free(solver), HANDLE, "already freed");
    EXPECT(meshmove_solver_solve(solver, 10, d, NULL, out, &rep), HANDLE, "already freed");
    EXPECT(meshmove_bcs_free(bcs), OK, NULL);
    EXPECT(meshmove_bcs_set_kinds(bcs, 0, MESHMOVE_KIND_FIXED), HANDLE, "already freed");
    EXPECT(meshmove_mesh_free(mesh), OK, NULL);
    EXPECT(meshmove_mesh_free(m2), OK, NULL);
    EXPECT(meshmove_options_free(o), OK, NULL);
    EXPECT(meshmove_options_set_method(o, 0), HANDLE, "already freed");
    EXPECT(meshmove_mesh_get_coords(mesh, 10, out), HANDLE, "already freed");
    EXPECT(meshmove_mesh_free(mesh), HANDLE, "already freed");

    printf("bad_input: %d checks, %d failures\n", checks, failures);
    return failures != 0;
}
