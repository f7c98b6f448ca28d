/* Links the installed meshmove and moves a small mesh. */
#include <stdio.h>
#include "meshmove.h"

int main(void) {
    double xy[10] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5};
    int32_t cells[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4}, edge[2] = {1, 2}, patch[1] = {2};
    double bd[10] = {0, 0, 0, 0, 0, 0.1, 0, 0, 0, 0};
    meshmove_mesh *m = NULL;
    meshmove_bcs *b = NULL;
    meshmove_solver *s = NULL;
    int32_t major = -1;
    if (meshmove_version(&major, NULL, NULL) || major != MESHMOVE_VERSION_MAJOR) return 1;
    if (meshmove_mesh_create(5, xy, 4, cells, 0, 1, edge, patch, NULL, &m)) return 1;
    if (meshmove_bcs_create(&b) || meshmove_solver_create(m, b, NULL, &s)) return 1;
    bd[7] = 0.1; /* vertex 3 is on patch 0, fixed: it is told 0.1 too, so both top corners rise */
    if (meshmove_solver_move(s, 10, bd, xy, NULL, NULL)) return 1;
    printf("consumer: centre moved to (%g, %g)\n", xy[8], xy[9]);
    meshmove_solver_free(s), meshmove_bcs_free(b), meshmove_mesh_free(m);
    return xy[9] > 0.5 ? 0 : 1;
}
