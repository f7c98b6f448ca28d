#!/usr/bin/env bash
# The distributed bench (docs/PERFORMANCE.md, "Distributed meshes"): `meshmove bench --parts
# ranks` under mpirun on 1, 2 and 4 ranks (oversubscribed where the machine has fewer cores),
# one solver thread per rank, the rows appended to OUT/ranks.csv. A rank that waits for a message
# yields its core (OpenMPI's mpi_yield_when_idle) instead of polling on it: on a machine with fewer
# free cores than ranks a polling rank takes the core its partner needs to send.
#   scripts/bench-ranks.sh OUT [--quick]
set -euo pipefail
out=${1:?usage: scripts/bench-ranks.sh OUT [--quick]}
shift
cd "$(dirname "$0")/.."
cargo build --release -p meshmove-cli --features mpi
rm -f "$out/ranks.csv"
for np in 1 2 4; do
    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1 \
        mpirun --oversubscribe --bind-to none -x RAYON_NUM_THREADS=1 -np "$np" \
        target/release/meshmove bench --parts ranks --out "$out" "$@"
done
