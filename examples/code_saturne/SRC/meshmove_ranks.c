/* What a rank's usalcl needs from code_saturne's C side to hand its partition to meshmove's
 * distributed mesh, which Fortran's module `mesh` does not give: the global number of each
 * local vertex and the Fortran handle of code_saturne's communicator. */

#include "cs_defs.h"

#include <stdint.h>

#include "cs_base.h"
#include "cs_mesh.h"

/* Called from Fortran (module saturne_ranks in cs_user_modules.f90), declared for C here. */
void meshmove_cs_global_vertices(int32_t n, int64_t *gnum);
int32_t meshmove_cs_comm(void);

/* The global number (1-based) of each of the rank's n local vertices, into gnum. code_saturne
 * keeps no global numbering where the local numbers are the global ones (global_vtx_num is
 * NULL, as in a serial run): the local number is then the global one. */
void
meshmove_cs_global_vertices(int32_t n, int64_t *gnum)
{
  const cs_gnum_t *g = cs_glob_mesh->global_vtx_num;
  for (int32_t i = 0; i < n; i++)
    gnum[i] = (g != NULL) ? (int64_t)g[i] : (int64_t)i + 1;
}

/* code_saturne's communicator as Fortran's integer handle (what meshmove's Fortran calls
 * take); -1 from a code_saturne built without MPI. */
int32_t
meshmove_cs_comm(void)
{
#if defined(HAVE_MPI)
  return (int32_t)MPI_Comm_c2f(cs_glob_mpi_comm);
#else
  return -1;
#endif
}
