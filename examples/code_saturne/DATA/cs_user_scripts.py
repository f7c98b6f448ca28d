# code_saturne's run-time settings of the meshmove example: the mesh, and meshmove linked into
# the solver that code_saturne builds from the user files in SRC.
#
# MESHMOVE_FFLAGS: the Fortran flags that find meshmove's modules (-I<dir of meshmove.mod>);
# MESHMOVE_LIBS: the link flags (-L<dir> -lmeshmove_fortran -lmeshmove -Wl,-rpath,<dir>).
# Unset, pkg-config's meshmove-fortran (an installed meshmove) gives them (an MPI build's lists
# -lmeshmove_fortran_mpi before -lmeshmove_fortran). For runs on several ranks meshmove is built
# with MPI and MESHMOVE_FFLAGS adds -DMESHMOVE_MPI (the user files' distributed part).
import os
import subprocess


def meshmove_flags(variable, pkg_config_option):
    value = os.environ.get(variable)
    if value is None:
        value = subprocess.check_output(['pkg-config', pkg_config_option, 'meshmove-fortran'],
                                        universal_newlines=True).strip()
    return value


def define_domain_parameters(domain):
    # Found in the study's MESH directory (run.sh puts it there).
    domain.meshes = ['cylinder.msh']
    domain.compile_fcflags = meshmove_flags('MESHMOVE_FFLAGS', '--cflags')
    domain.compile_libs = meshmove_flags('MESHMOVE_LIBS', '--libs')
