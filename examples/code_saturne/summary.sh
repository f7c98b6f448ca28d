#!/usr/bin/env bash
# The timings of a run of the example: summary.sh RUN_DIR (WORKDIR/case/RESU/run of run.sh).
# Prints the time steps made, the mean wall-clock seconds of a time step (the first left out: it
# holds the set-up), the mean seconds of meshmove's move in one (0 when code_saturne moves the
# mesh itself), and the seconds per call of code_saturne's own mesh-velocity solve (setup and
# solution of the linear system, from its performance.log; it runs with either mover).
set -euo pipefail
run=${1:?usage: summary.sh RUN_DIR}
awk '!/^#/ { n++; s += $2; m += $3 }
     END { printf "time steps timed: %d, seconds per step: %.4f, of which meshmove: %.4f\n", n, s / n, m / n }' \
    "$run/steps.txt"
awk '/Summary of resolutions for "Mesh Velocity"/ { on = 1 }
     on && /Number of calls:/ { calls = $NF }
     on && /Total setup time:/ { t += $NF }
     on && /Total solution time:/ {
         t += $NF
         printf "code_saturne mesh-velocity solve: %d calls, %.4f s per call\n", calls, t / calls
         exit
     }' \
    "$run/performance.log"
