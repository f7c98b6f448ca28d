#!/usr/bin/env bash
# The 3D peer comparison of docs/PERFORMANCE.md: the bench's hexahedral box (N³ cells, the top
# moved by 0.1 cos 2πx cos 2πy in z, bottom fixed, sides sliding) moved by OpenFOAM's `moveMesh`
# with `displacementLaplacian` (GAMG to a 1e-8 residual, relTol 0: converged) and by
# `meshmove deform` (biharmonic and Laplacian, to a 1e-8 relative residual), one thread each, on
# the same mesh: the time, iterations, peak memory and quality of each, as a Markdown table.
#
#   scripts/peer-openfoam.sh [N] [WORKDIR]     N cells per side (default 62: 250047 vertices)
#
# Needs OpenFOAM (`moveMesh`, `checkMesh` on PATH) and GNU time (/usr/bin/time); without
# OpenFOAM it says so and exits 0. Not run in CI. The meshmove binary is $MESHMOVE, else
# target/release/meshmove (built with `cargo build --release`).
set -euo pipefail

N="${1:-62}"
WORK="${2:-$(mktemp -d -t meshmove-peer-XXXXXX)}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
MESHMOVE="${MESHMOVE:-$ROOT/target/release/meshmove}"

if ! command -v moveMesh >/dev/null 2>&1; then
    echo "peer-openfoam: OpenFOAM's moveMesh is not on PATH; nothing to compare (install OpenFOAM, e.g. apt-get install openfoam, or source its etc/bashrc)"
    exit 0
fi
if [ ! -x /usr/bin/time ]; then
    echo "peer-openfoam: GNU time (/usr/bin/time) is needed for the peak memory" >&2
    exit 1
fi
if [ ! -x "$MESHMOVE" ]; then
    echo "peer-openfoam: no meshmove binary at $MESHMOVE (cargo build --release, or set MESHMOVE)" >&2
    exit 1
fi
# Debian's packaged OpenFOAM runs without its environment once it knows where etc/ is.
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
    export WM_PROJECT_DIR=/usr/share/openfoam
fi

mkdir -p "$WORK"
cd "$WORK"
echo "peer-openfoam: ${N}^3 hexahedra in $WORK"
"$MESHMOVE" bench --out "$WORK" --peer-case "$N" >/dev/null
sed 's/^method = "biharmonic"/method = "laplacian"/' case.toml >case-laplacian.toml

# Peak resident set (MB) and wall seconds from a GNU time -v log.
peak_mb() { awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$1"; }
wall_s() {
    awk -F': ' '/Elapsed \(wall clock\)/ {
        n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.2f", s }' "$1"
}
# CPU seconds (user + system) of a GNU time -v log: on a shared machine the wall time counts the
# other jobs too, the CPU time of a one-thread process does not.
cpu_s() { awk -F': ' '/User time|System time/ {s += $2} END {printf "%.2f", s}' "$1"; }
# From a checkMesh log: min volume ratio (min volume × N³, every cell of the box being 1/N³),
# max non-orthogonality, max skewness.
quality() {
    local log="$1"
    local minv nonorth skew
    minv=$(grep -o 'Min volume = [0-9.eE+-]*' "$log" | awk '{print $4}')
    nonorth=$(grep -o 'non-orthogonality Max: [0-9.eE+-]*' "$log" | awk '{print $3}')
    skew=$(grep -o 'Max skewness = [0-9.eE+-]*' "$log" | awk '{print $4}')
    awk -v v="$minv" -v n="$N" -v o="$nonorth" -v s="$skew" 'BEGIN { printf "%.4f|%.1f|%.3f", v * n * n * n, o, s }'
}

# OpenFOAM: moveMesh (displacementLaplacian), then checkMesh of the moved mesh (time 1).
/usr/bin/time -v moveMesh -case foam >foam-move.log 2>foam-time.log
foam_its=$(grep -o 'cellDisplacementz, .*No Iterations [0-9]*' foam-move.log | awk '{print $NF}')
foam_exec=$(grep -o 'ExecutionTime = [0-9.]*' foam-move.log | tail -1 | awk '{print $3}')
# The linear solves, from OpenFOAM's profiling (fvMatrix::solve of cellDisplacement).
foam_solve=$(awk '/description/ {d = $0} /totalTime/ && d ~ /fvMatrix::solve.cellDisplacement/ {gsub(/;/, "", $2); printf "%.3f", $2; exit}' \
    foam/1/uniform/profiling 2>/dev/null || true)
checkMesh -case foam -time 1 >foam-check.log 2>&1 || true
foam_q=$(quality foam-check.log)

# meshmove: deform (biharmonic, Laplacian); our moved mesh written as time 2 for checkMesh.
ours() {
    local name="$1" config="$2"
    /usr/bin/time -v "$MESHMOVE" deform box.msh --config "$config" -o "$name.vtu" --report "$name.jsonl" >"$name.log" 2>"$name-time.log"
    "$MESHMOVE" bench --out "$WORK" --peer-points "$name.vtu" >/dev/null
    checkMesh -case foam -time 2 >"$name-check.log" 2>&1 || true
}
ours biharmonic case.toml
ours laplacian case-laplacian.toml
# Iterations, setup + solve seconds (the deform line) and the solve alone (the step report).
its() { grep -o '"cycles":[0-9]*' "$1.jsonl" | head -1 | cut -d: -f2; }
motion_s() { grep -o 'cycles, [0-9.]* s' "$1.log" | awk '{print $2}'; }
solve_s() { grep -o '"solve_seconds":[0-9.eE+-]*' "$1.jsonl" | head -1 | cut -d: -f2 | awk '{printf "%.3f", $1}'; }
# Where our wall seconds go: read + write (the process's wall outside the deform line's seconds),
# setup (the deform line's seconds outside the step), the step's solve and quality check.
first_field() { grep -o "\"$2\":[0-9.eE+-]*" "$1.jsonl" | head -1 | cut -d: -f2; }
phases() {
    awk -v w="$(wall_s "$1-time.log")" -v m="$(motion_s "$1")" -v st="$(first_field "$1" seconds)" \
        -v s="$(first_field "$1" solve_seconds)" -v q="$(first_field "$1" quality_seconds)" \
        'BEGIN {printf "%.2f / %.2f / %.2f / %.2f", w - m, m - st, s, q}'
}

vertices=$(( (N + 1) * (N + 1) * (N + 1) ))
q() { echo "$1" | cut -d'|' -f"$2"; }
bq=$(quality biharmonic-check.log)
lq=$(quality laplacian-check.log)
cat <<EOF

${N}^3 hexahedra, ${vertices} vertices; top moved by 0.1 cos 2πx cos 2πy in z; one thread each.

| | OpenFOAM moveMesh, displacementLaplacian (GAMG, 1e-8) | meshmove biharmonic (1e-8) | meshmove Laplacian (1e-8) |
|---|---|---|---|
| process CPU s (read, move, write) | $(cpu_s foam-time.log) | $(cpu_s biharmonic-time.log) | $(cpu_s laplacian-time.log) |
| process wall s (read, move, write) | $(wall_s foam-time.log) | $(wall_s biharmonic-time.log) | $(wall_s laplacian-time.log) |
| motion s (OpenFOAM: ExecutionTime, CPU; ours: setup + step, wall) | ${foam_exec} | $(motion_s biharmonic) | $(motion_s laplacian) |
| ours, wall s: read + write / setup / solve / quality | | $(phases biharmonic) | $(phases laplacian) |
| linear solve s (wall) | ${foam_solve:-n/a} | $(solve_s biharmonic) | $(solve_s laplacian) |
| iterations (z) | ${foam_its} (GAMG V-cycles) | $(its biharmonic) (CG + W-cycle) | $(its laplacian) (CG + W-cycle) |
| peak resident set MB | $(peak_mb foam-time.log) | $(peak_mb biharmonic-time.log) | $(peak_mb laplacian-time.log) |
| min volume ratio (checkMesh) | $(q "$foam_q" 1) | $(q "$bq" 1) | $(q "$lq" 1) |
| max non-orthogonality ° (checkMesh) | $(q "$foam_q" 2) | $(q "$bq" 2) | $(q "$lq" 2) |
| max skewness (checkMesh) | $(q "$foam_q" 3) | $(q "$bq" 3) | $(q "$lq" 3) |
EOF
