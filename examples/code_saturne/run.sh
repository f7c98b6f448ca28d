#!/usr/bin/env bash
# Runs the example case: run.sh [--nprocs N] WORKDIR [meshmove|code_saturne] [STEPS [AMPLITUDE]]
#   --nprocs N    code_saturne on N MPI ranks (default 1, serial); with meshmove as the mover,
#                 N > 1 needs meshmove built with MPI and -DMESHMOVE_MPI in MESHMOVE_FFLAGS
#   WORKDIR       made anew: a code_saturne study (MESH/, case/DATA, case/SRC, case/RESU);
#                 the run's files end in WORKDIR/case/RESU/run
#   meshmove      usalcl moves the mesh with meshmove (the default);
#   code_saturne  code_saturne's own ALE mesh solve, only the cylinder imposed
#   STEPS         time steps (default 40, one period of the motion)
#   AMPLITUDE     of the cylinder's motion across the channel (default 1, its diameter)
# Exit status 0: the run made every step; 1: it failed; 3: code_saturne stopped before the
# last step (the files of the steps made are kept).
# MESHMOVE_FFLAGS and MESHMOVE_LIBS say where meshmove is (DATA/cs_user_scripts.py).
set -euo pipefail
nprocs=1
if [ "${1:-}" = "--nprocs" ]; then
    nprocs=${2:?run.sh: --nprocs needs a number}
    shift 2
fi
case "$nprocs" in
    '' | *[!0-9]* | 0) echo "run.sh: --nprocs takes a positive number, not '$nprocs'" >&2; exit 2 ;;
esac
here=$(cd "$(dirname "$0")" && pwd)
work=${1:?usage: run.sh [--nprocs N] WORKDIR [meshmove|code_saturne] [STEPS [AMPLITUDE]]}
mover=${2:-meshmove}
steps=${3:-40}
amplitude=${4:-1}
case "$mover" in
    meshmove | code_saturne) ;;
    *) echo "run.sh: the mover is meshmove or code_saturne, not '$mover'" >&2; exit 2 ;;
esac
# code_saturne's run script needs USER; its MPI launcher refuses root unless told, and more
# ranks than cores unless told.
export USER="${USER:-$(id -un)}"
if [ "$(id -u)" -eq 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_mpi_yield_when_idle=1
export CS_MESH_MOVER="$mover" CS_STEPS="$steps" CS_AMPLITUDE="$amplitude" OMP_NUM_THREADS=1
rm -rf "$work"
mkdir -p "$work/MESH" "$work/case/DATA" "$work/case/SRC" "$work/case/RESU"
cp "$here/cylinder.msh" "$work/MESH/"
cp "$here/DATA/cs_user_scripts.py" "$work/case/DATA/"
cp "$here"/SRC/* "$work/case/SRC/"
cd "$work/case/DATA"
if ! code_saturne run --id run --nprocs "$nprocs" > "$work/run.log" 2>&1; then
    cat "$work/run.log" >&2
    for f in compile.log run_solver.log listing error; do
        [ -f "$work/case/RESU/run/$f" ] && tail -n 40 "$work/case/RESU/run/$f" >&2
    done
    exit 1
fi
result="$work/case/RESU/run"
# code_saturne ends a run that stops early (a negative cell volume) with a success status: the
# run is complete when its last time step's coordinates are written (cs_user_extra_operations).
last=$(grep -o "TIME STEP NUMBER *[0-9]*" "$result/listing" | tail -n 1 | grep -o "[0-9]*$" || true)
if [ "${last:-0}" != "$steps" ] || grep -q "^Abort" "$result/listing"; then
    grep "^Abort" "$result/listing" >&2 || true
    echo "run.sh: code_saturne stopped at time step ${last:-0} of $steps ($result)" >&2
    exit 3
fi
echo "$result"
