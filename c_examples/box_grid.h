/* A host code's own mesh, as the C examples and tests make it: the structured grid of a box
 * [x0,x1]x[y0,y1] with nx x ny squares, each one quad or two triangles, and its boundary faces
 * tagged per side. examples/reference_case.rs and fortran_examples/box_grid.f90 make the same
 * grid, vertex for vertex and cell for cell.
 *
 *   vertex (i, j), 0 <= i <= nx, 0 <= j <= ny:  j (nx + 1) + i, at
 *       x = x0 + (x1 - x0) * i / nx,  y = y0 + (y1 - y0) * j / ny
 *   square (i, j) with corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1):
 *       quads: cell j nx + i = (a, b, c, d); triangles: cells 2 (j nx + i) = (a, b, c) and
 *       2 (j nx + i) + 1 = (a, c, d); all counter-clockwise
 *   faces: the bottom side (left to right), the right side (upwards), the top side (left to
 *       right), the left side (upwards), each on its patch side[0..3]; a side whose patch is
 *       0 is left untagged (the library puts untagged boundary faces on patch 0 anyway). */
#ifndef MESHMOVE_EXAMPLE_BOX_GRID_H
#define MESHMOVE_EXAMPLE_BOX_GRID_H
#include <stdlib.h>
#include "meshmove.h"

typedef struct {
    int32_t nx, ny, nv, nc, corners, nf; /* corners: 3 (triangles) or 4 (quads) */
    double *xy;                          /* 2 nv */
    int32_t *cells;                      /* corners x nc */
    int32_t *types;                      /* nc meshmove_cell_type values */
    int32_t *faces;                      /* 2 nf */
    int32_t *patch;                      /* nf */
} box_grid;

static inline void box_grid_make(box_grid *g, int32_t nx, int32_t ny, const double box[4], int quads,
                                 const int32_t side[4]) {
    int32_t i, j, c = 0, f = 0, k, n;
    g->nx = nx;
    g->ny = ny;
    g->nv = (nx + 1) * (ny + 1);
    g->corners = quads ? 4 : 3;
    g->nc = quads ? nx * ny : 2 * nx * ny;
    g->xy = malloc(sizeof(double) * 2 * (size_t)g->nv);
    g->cells = malloc(sizeof(int32_t) * (size_t)g->corners * (size_t)g->nc);
    g->types = malloc(sizeof(int32_t) * (size_t)g->nc);
    g->faces = malloc(sizeof(int32_t) * 4 * (size_t)(nx + ny));
    g->patch = malloc(sizeof(int32_t) * 2 * (size_t)(nx + ny));
    for (j = 0; j <= ny; j++)
        for (i = 0; i <= nx; i++) {
            g->xy[2 * (j * (nx + 1) + i)] = box[0] + (box[1] - box[0]) * i / nx;
            g->xy[2 * (j * (nx + 1) + i) + 1] = box[2] + (box[3] - box[2]) * j / ny;
        }
    for (j = 0; j < ny; j++)
        for (i = 0; i < nx; i++) {
            int32_t a = j * (nx + 1) + i, b = a + 1, d = a + nx + 1, e = d + 1;
            int32_t quad[4] = {a, b, e, d}, tris[6] = {a, b, e, a, e, d};
            const int32_t *from = quads ? quad : tris;
            for (k = 0; k < (quads ? 4 : 6); k++) g->cells[g->corners * c + k] = from[k];
            for (k = 0; k < (quads ? 1 : 2); k++) g->types[c++] = quads ? MESHMOVE_CELL_TYPE_QUAD : MESHMOVE_CELL_TYPE_TRIANGLE;
        }
    for (k = 0; k < 4; k++) {
        if (side[k] == 0) continue;
        n = k % 2 ? ny : nx;
        for (i = 0; i < n; i++) {
            /* the side's i-th vertex and the next one along it */
            int32_t v = k == 0 ? i : k == 1 ? i * (nx + 1) + nx : k == 2 ? ny * (nx + 1) + i : i * (nx + 1);
            g->faces[2 * f] = v;
            g->faces[2 * f + 1] = v + (k % 2 ? nx + 1 : 1);
            g->patch[f++] = side[k];
        }
    }
    g->nf = f;
}

static inline void box_grid_free(box_grid *g) {
    free(g->xy), free(g->cells), free(g->types), free(g->faces), free(g->patch);
}

/* The grid's mesh through the generic call (offsets NULL: they follow from the cell types). */
static inline meshmove_status box_grid_mesh(const box_grid *g, meshmove_mesh **out) {
    return meshmove_mesh_create(2, g->nv, g->xy, g->nc, NULL, g->corners * g->nc, g->cells, g->types, g->nf, NULL,
                                2 * g->nf, g->faces, g->patch, NULL, 0, out);
}

#endif
