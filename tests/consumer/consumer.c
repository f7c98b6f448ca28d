/* Links the installed meshmove and moves a small mesh: the unit square around a centre vertex,
 * given through the generic call (2D, triangles, the right edge tagged as patch 2). */
#include <stdio.h>
#include "meshmove.h"

int main(void) {
    double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5};
    int32_t cells[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4}, edge[2] = {1, 2}, patch[1] = {2};
    int32_t types[4] = {MESHMOVE_CELL_TYPE_TRIANGLE, MESHMOVE_CELL_TYPE_TRIANGLE, MESHMOVE_CELL_TYPE_TRIANGLE,
                        MESHMOVE_CELL_TYPE_TRIANGLE};
    double bd[10] = {0, 0, 0, 0, 0, 0.1, 0, 0, 0, 0};
    meshmove_mesh *m = NULL;
    meshmove_bcs *b = NULL;
    meshmove_solver *s = NULL;
    int32_t major = -1, minor = -1;
    if (meshmove_version(&major, &minor, NULL) || major != MESHMOVE_VERSION_MAJOR || minor != MESHMOVE_VERSION_MINOR)
        return 1;
    if (meshmove_mesh_create(2, 5, xy, 4, NULL, 12, cells, types, 1, NULL, 2, edge, patch, NULL, 0, &m)) return 1;
    if (meshmove_bcs_create(&b) || meshmove_solver_create(m, b, NULL, &s)) return 1;
    bd[7] = 0.1; /* vertex 3 is on patch 0, fixed: it is told 0.1 too, so both top corners rise */
    if (meshmove_solver_move(s, 10, bd, xy, NULL, NULL)) return 1;
    printf("consumer: centre moved to (%g, %g)\n", xy[8], xy[9]);
    if (meshmove_solver_free(s) || meshmove_bcs_free(b) || meshmove_mesh_free(m)) return 1;
    return xy[9] > 0.5 ? 0 : 1;
}
