#!/usr/bin/env bash
# The time-stepping peer comparison of docs/PERFORMANCE.md: a sphere of radius 0.25 at the centre
# of the unit cube oscillating along x (amplitude 0.1, one period in 20 steps, the cube's walls
# fixed), moved over 20 time steps by OpenFOAM's `moveMesh` (displacementLaplacian, GAMG to a
# 1e-8 residual with relTol 0; the sphere's `oscillatingDisplacement`) and by `meshmove deform`
# (biharmonic and Laplacian to a 1e-8 relative residual; the sphere's periodic motion, one
# `advance` a step), one thread each, on the same mesh: the seconds a step, where our step goes
# and the smallest volume ratio (a cell's volume over its volume in the mesh as read, by
# OpenFOAM's `writeCellVolumes` for both tools' meshes) over the period of each, as a Markdown
# table. Both tools read the same OpenFOAM case (constant/polyMesh).
#
#   [REFERENCE=original] scripts/peer-openfoam-steps.sh [tet|hex|block] [H] [WORKDIR]
#
# REFERENCE is our case file's `reference`: `incremental` (the default: each step solved on the
# previous step's mesh, re-referenced after it) or `original` (each step's total displacement
# solved on the mesh as read; OpenFOAM's displacementLaplacian also solves for the total
# displacement from the mesh as read, its operator on the current mesh).
#
# The mesh: `tet`, Gmsh's tetrahedra of size H (0.032 gives 26k vertices, 0.0146 about 250k);
# `hex`, the hexahedra of Gmsh's subdivision of each of them into four (0.092 gives 30k, 0.047
# about 250k); `block`, blockMesh's structured hexahedra, six blocks between the sphere and the
# cube's faces, H cells along a block's edge on the sphere and 2H/3 from the sphere to the cube
# (19 gives 30 352 vertices, 39 about 246k). Defaults: tet, 0.032 (block: 19). Needs OpenFOAM
# (`moveMesh`, `postProcess`; `gmshToFoam` and Gmsh for tet and hex, `blockMesh` for block) and
# GNU time; without them it says so and exits 0. Not run in CI. The meshmove binary is
# $MESHMOVE, else target/release/meshmove (built with `cargo build --release`).
set -euo pipefail

CELLS="${1:-tet}"
case "$CELLS" in
    tet | hex) H="${2:-0.032}"; TOOLS="gmsh gmshToFoam moveMesh postProcess" ;;
    block) H="${2:-19}"; TOOLS="blockMesh moveMesh postProcess" ;;
    *) echo "peer-openfoam-steps: cells must be tet, hex or block, got $CELLS" >&2; exit 2 ;;
esac
WORK="${3:-$(mktemp -d -t meshmove-peer-steps-XXXXXX)}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
MESHMOVE="${MESHMOVE:-$ROOT/target/release/meshmove}"
STEPS=20
AMPLITUDE=0.1
REFERENCE="${REFERENCE:-incremental}"
case "$REFERENCE" in
    incremental | original) ;;
    *) echo "peer-openfoam-steps: REFERENCE must be incremental or original, got $REFERENCE" >&2; exit 2 ;;
esac

for tool in $TOOLS; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "peer-openfoam-steps: $tool is not on PATH; nothing to compare (install Gmsh and OpenFOAM, e.g. apt-get install gmsh openfoam)"
        exit 0
    fi
done
if [ ! -x /usr/bin/time ]; then
    echo "peer-openfoam-steps: GNU time (/usr/bin/time) is needed" >&2
    exit 1
fi
if [ ! -x "$MESHMOVE" ]; then
    echo "peer-openfoam-steps: no meshmove binary at $MESHMOVE (cargo build --release, or set MESHMOVE)" >&2
    exit 1
fi
case "$CELLS" in
    hex) SUBDIVIDE=2 ;;
    *) SUBDIVIDE=0 ;;
esac
if [ "$CELLS" = block ] && ! [[ "$H" =~ ^[1-9][0-9]*$ ]]; then
    echo "peer-openfoam-steps: block wants a whole number of cells, got $H" >&2
    exit 2
fi
# Debian's packaged OpenFOAM runs without its environment once it knows where etc/ is.
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
    export WM_PROJECT_DIR=/usr/share/openfoam
fi
mkdir -p "$WORK"
cd "$WORK"

# OpenFOAM's case: the same mesh, the sphere oscillating as sin(2π t / 20) with t the step.
foam_header() {
    printf 'FoamFile\n{\n    version 2.0;\n    format ascii;\n    class %s;\n    location "%s";\n    object %s;\n}\n' "$1" "$2" "$3"
}
rm -rf foam
mkdir -p foam/system foam/constant foam/0
omega=$(awk -v n="$STEPS" 'BEGIN { printf "%.17g", 2 * atan2(0, -1) / n }')
control() {
    {
        foam_header dictionary system controlDict
        printf 'application moveMesh;\nstartFrom startTime;\nstartTime 0;\nstopAt endTime;\nendTime %s;\ndeltaT 1;\n' "$STEPS"
        printf 'writeControl timeStep;\nwriteInterval %s;\nwriteFormat ascii;\nwritePrecision 17;\nwriteCompression off;\n' "$1"
        printf 'timeFormat general;\ntimePrecision 6;\nrunTimeModifiable false;\n'
    } >foam/system/controlDict
}
control "$STEPS"
{
    foam_header dictionary system fvSchemes
    printf 'ddtSchemes { default Euler; }\ngradSchemes { default Gauss linear; }\ndivSchemes { default none; }\n'
    printf 'laplacianSchemes { default Gauss linear corrected; }\ninterpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n'
} >foam/system/fvSchemes
{
    foam_header dictionary system fvSolution
    printf 'solvers\n{\n    cellDisplacement\n    {\n        solver GAMG;\n        smoother GaussSeidel;\n'
    printf '        tolerance 1e-8;\n        relTol 0;\n        maxIter 1000;\n    }\n}\n'
} >foam/system/fvSolution
{
    foam_header dictionary constant dynamicMeshDict
    printf 'dynamicFvMesh dynamicMotionSolverFvMesh;\nmotionSolverLibs ("libfvMotionSolvers.so");\n'
    printf 'motionSolver displacementLaplacian;\nsolver displacementLaplacian;\ndisplacementLaplacianCoeffs { diffusivity uniform; }\n'
} >foam/constant/dynamicMeshDict
{
    foam_header pointVectorField 0 pointDisplacement
    printf 'dimensions [0 1 0 0 0 0 0];\ninternalField uniform (0 0 0);\nboundaryField\n{\n'
    printf '    walls { type fixedValue; value uniform (0 0 0); }\n'
    printf '    defaultFaces { type fixedValue; value uniform (0 0 0); }\n'
    printf '    sphere { type oscillatingDisplacement; amplitude (%s 0 0); omega %s; value uniform (0 0 0); }\n}\n' "$AMPLITUDE" "$omega"
} >foam/0/pointDisplacement

# The mesh, as foam/constant/polyMesh (patches `walls` and `sphere`).
if [ "$CELLS" = block ]; then
    # Six blocks between the sphere (the inner cube's corners 0-7 and faces projected onto it,
    # its edges arcs of it) and the cube's faces (corners 8-15).
    awk -v n="$H" 'BEGIN {
        m = int((2 * n + 1) / 3); c = 0.5; r = 0.25; h = r / sqrt(3); lo = c - r / sqrt(2); hi = c + r / sqrt(2)
        printf "FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }\n"
        printf "scale 1;\ngeometry { sphere { type sphere; origin (%g %g %g); radius %g; } }\nvertices\n(\n", c, c, c, r
        split("-1 1 1 -1", sx, " "); split("-1 -1 1 1", sy, " ")
        for (k = 0; k < 2; k++) for (i = 1; i <= 4; i++) printf "(%.17g %.17g %.17g)\n", c + sx[i] * h, c + sy[i] * h, c + (2 * k - 1) * h
        for (k = 0; k < 2; k++) for (i = 1; i <= 4; i++) printf "(%g %g %g)\n", c + sx[i] * c, c + sy[i] * c, c + (2 * k - 1) * c
        printf ");\nblocks\n(\n"
        split("9 8 12 13 1 0 4 5|10 9 13 14 2 1 5 6|11 10 14 15 3 2 6 7|8 11 15 12 0 3 7 4|8 9 10 11 0 1 2 3|13 12 15 14 5 4 7 6", b, "|")
        for (i = 1; i <= 6; i++) printf "hex (%s) (%d %d %d) simpleGrading (1 1 1)\n", b[i], n, n, m
        printf ");\nedges\n(\n"
        printf "arc 0 1 (%.17g %.17g %.17g)\narc 3 2 (%.17g %.17g %.17g)\narc 7 6 (%.17g %.17g %.17g)\narc 4 5 (%.17g %.17g %.17g)\n", c, lo, lo, c, hi, lo, c, hi, hi, c, lo, hi
        printf "arc 0 3 (%.17g %.17g %.17g)\narc 1 2 (%.17g %.17g %.17g)\narc 5 6 (%.17g %.17g %.17g)\narc 4 7 (%.17g %.17g %.17g)\n", lo, c, lo, hi, c, lo, hi, c, hi, lo, c, hi
        printf "arc 0 4 (%.17g %.17g %.17g)\narc 1 5 (%.17g %.17g %.17g)\narc 2 6 (%.17g %.17g %.17g)\narc 3 7 (%.17g %.17g %.17g)\n", lo, lo, c, hi, lo, c, hi, hi, c, lo, hi, c
        split("1 0 4 5|2 1 5 6|3 2 6 7|0 3 7 4|0 1 2 3|5 4 7 6", s, "|")
        split("8 12 15 11|10 14 13 9|9 13 12 8|11 15 14 10|8 11 10 9|12 13 14 15", w, "|")
        printf ");\nfaces\n(\n"; for (i = 1; i <= 6; i++) printf "project (%s) sphere\n", s[i]
        printf ");\nboundary\n(\nsphere { type wall; faces ("; for (i = 1; i <= 6; i++) printf " (%s)", s[i]
        printf "); }\nwalls { type wall; faces ("; for (i = 1; i <= 6; i++) printf " (%s)", w[i]
        printf "); }\n);\n"
    }' >foam/system/blockMeshDict
    blockMesh -case foam >blockMesh.log 2>&1
else
    # Gmsh's tetrahedra of the cube minus the sphere, or their subdivision into hexahedra; MSH
    # 2.2 ASCII for gmshToFoam.
    cat >sphere.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Sphere(2) = {0.5, 0.5, 0.5, 0.25};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Mesh.MeshSizeMin = h;
Mesh.MeshSizeMax = h;
Mesh.SubdivisionAlgorithm = subdivide;
Physical Surface("walls", 1) = {1, 2, 3, 4, 5, 6};
Physical Surface("sphere", 2) = {7};
Physical Volume("fluid", 10) = {3};
GEO
    gmsh -3 sphere.geo -setnumber h "$H" -setnumber subdivide "$SUBDIVIDE" -format msh22 -o sphere.msh >gmsh.log 2>&1
    gmshToFoam sphere.msh -case foam >gmshToFoam.log 2>&1
fi
vertices=$(awk '/^[0-9]+$/ {print; exit}' foam/constant/polyMesh/points)
cells=$(grep -o 'nCells: *[0-9]*' foam/constant/polyMesh/owner | head -1 | tr -dc '0-9')
echo "peer-openfoam-steps: $CELLS, $H: $vertices vertices, $cells cells, in $WORK"
# Our runs read a copy of the case as it is now (the mesh as read, no time directories).
for name in biharmonic laplacian; do
    rm -rf "$name-case"
    mkdir -p "$name-case/0"
    cp -r foam/constant foam/system "$name-case/"
done

# Seconds of a GNU time -v log.
wall_s() {
    awk -F': ' '/Elapsed \(wall clock\)/ {
        n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.2f", s }' "$1"
}
# CPU seconds (user + system) of a GNU time -v log, over the steps: on a shared machine the
# wall time counts the other jobs too, the CPU time of a one-thread process does not.
cpu_step_s() {
    awk -F': ' -v n="$STEPS" '/User time|System time/ {s += $2} END {printf "%.3f", s / n}' "$1"
}
# The CPU seconds between the first and the last time step of a moveMesh log, a step (the mesh's
# reading and the solver's setup before the first step left out).
foam_step_s() {
    grep -o 'ExecutionTime = [0-9.]*' "$1" | awk '{t[NR] = $3} END { printf "%.3f", (t[NR] - t[1]) / (NR - 1) }'
}

# The smallest V_T / V_0 over T = 1 .. steps of a case's cell volumes CASE/T/V (postProcess's
# writeCellVolumes), n/a where a time's volumes are missing.
min_ratio() {
    postProcess -case "$1" -func writeCellVolumes >"$1-volumes.log" 2>&1 || true
    awk -v steps="$STEPS" -v dir="$1" '
        function read(f, v,   n, line, started) {
            n = 0; started = 0
            while ((getline line < f) > 0) {
                if (!started && line ~ /^internalField/) { started = 1; getline line < f; getline line < f; continue }
                if (started) { if (line ~ /^\)/) break; v[n++] = line + 0 }
            }
            close(f); return n
        }
        BEGIN {
            m = read(dir "/0/V", v0); best = 1e300
            if (m == 0) { print "n/a"; exit }
            for (t = 1; t <= steps; t++) { if (read(dir "/" t "/V", v) != m) { print "n/a"; exit }
                for (i = 0; i < m; i++) if (v[i] / v0[i] < best) best = v[i] / v0[i] }
            printf "%.4f", best
        }'
}

# OpenFOAM, timed (writing only the last step), then again writing every step for the volumes.
/usr/bin/time -v moveMesh -case foam >foam-move.log 2>foam-time.log
control 1
moveMesh -case foam >foam-move-all.log 2>&1
foam_ratio=$(min_ratio foam)

# meshmove: deform of the case with the sphere's periodic motion, timed; again writing every
# step's polyMesh, moved into the case's time directories for writeCellVolumes.
ours() {
    local name="$1" method="$2" kind="$3"
    cat >"$name.toml" <<TOML
method = "$method"
tolerance = 1e-8
threads = 1
steps = $STEPS
reference = "$REFERENCE"

[[patch]]
patch = "sphere"
kind = "$kind"

[[motion]]
patch = "sphere"
translation = [$AMPLITUDE, 0.0, 0.0]
period = $STEPS
TOML
    mkdir -p "$name-out"
    /usr/bin/time -v "$MESHMOVE" deform "$name-case" --config "$name.toml" -o "$name-out/polyMesh" \
        --report "$name.jsonl" >"$name.log" 2>"$name-time.log"
    mkdir -p "$name-case/final"
    "$MESHMOVE" deform "$name-case" --config "$name.toml" -o "$name-case/final/polyMesh" --every 1 \
        >"$name-every.log" 2>&1 || true
    for t in $(seq 1 "$STEPS"); do
        if [ -d "$name-case/final/polyMesh_$(printf '%04d' "$t")" ]; then
            rm -rf "${name:?}-case/$t"
            mkdir -p "$name-case/$t"
            mv "$name-case/final/polyMesh_$(printf '%04d' "$t")" "$name-case/$t/polyMesh"
        fi
    done
}
ours biharmonic biharmonic clamped
ours laplacian laplacian fixed
# Sums over the steps of a report field (wall s), and that over the steps.
field_sum() { grep -o "\"$2\":[0-9.eE+-]*" "$1.jsonl" | cut -d: -f2 | awk '{s += $1} END {printf "%.3f", s}'; }
a_step() { awk -v s="$1" -v n="$STEPS" 'BEGIN {printf "%.3f", s / n}'; }
# Setup and all steps (the deform line's seconds), wall.
motion_total() { grep -o 'cycles, [0-9.]* s' "$1.log" | awk '{print $2}'; }
# Where a run's wall seconds go: read + write (the process's wall outside setup and steps),
# setup (the deform line's seconds outside the steps), and a step's re-reference, solve and
# quality check (the step reports: a step's seconds are its solve and quality check, its
# re-reference apart).
phases() {
    local wall motion steps
    wall=$(wall_s "$1-time.log")
    motion=$(motion_total "$1")
    steps=$(awk -v a="$(field_sum "$1" seconds)" -v b="$(field_sum "$1" reference_seconds)" 'BEGIN {print a + b}')
    awk -v w="$wall" -v m="$motion" -v s="$steps" 'BEGIN {printf "%.2f / %.2f", w - m, m - s}'
    printf ' / %s / %s / %s' "$(a_step "$(field_sum "$1" reference_seconds)")" \
        "$(a_step "$(field_sum "$1" solve_seconds)")" "$(a_step "$(field_sum "$1" quality_seconds)")"
}
cycles() {
    grep -o '"cycles":[0-9]*' "$1.jsonl" | cut -d: -f2 | awk '{s += $1; if (NR == 1) f = $1} END {printf "%.2f (first %d)", s / NR, f}'
}
foam_its=$(grep -o 'cellDisplacementx, .*No Iterations [0-9]*' foam-move.log | awk '{s += $NF} END {printf "%.2f", s / NR}')
foam_step_cpu=$(foam_step_s foam-move.log)
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", a / b}'; }

cat <<MD

Sphere in the unit cube, $CELLS $H: $vertices vertices, $cells cells; the sphere oscillating along x by $AMPLITUDE, one period in $STEPS steps; one thread each; our reference $REFERENCE.

| | OpenFOAM moveMesh, displacementLaplacian (GAMG, 1e-8) | meshmove biharmonic (1e-8) | meshmove Laplacian (1e-8) |
|---|---|---|---|
| process CPU s over $STEPS steps, a step (reading, setup, writing included) | $(cpu_step_s foam-time.log) | $(cpu_step_s biharmonic-time.log) ($(ratio "$(cpu_step_s biharmonic-time.log)" "$(cpu_step_s foam-time.log)")×) | $(cpu_step_s laplacian-time.log) ($(ratio "$(cpu_step_s laplacian-time.log)" "$(cpu_step_s foam-time.log)")×) |
| process wall s (read, $STEPS steps, write) | $(wall_s foam-time.log) | $(wall_s biharmonic-time.log) | $(wall_s laplacian-time.log) |
| OpenFOAM: CPU s a step, steps 2–$STEPS | ${foam_step_cpu} | | |
| ours, wall s: read + write / setup / a step's re-reference / solve / quality | | $(phases biharmonic) | $(phases laplacian) |
| iterations a step (x) | ${foam_its} (GAMG V-cycles) | $(cycles biharmonic) (CG + W-cycle) | $(cycles laplacian) (CG + W-cycle) |
| min volume ratio over the period (writeCellVolumes) | ${foam_ratio} | $(min_ratio biharmonic-case) | $(min_ratio laplacian-case) |
MD
