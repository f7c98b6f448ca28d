#!/usr/bin/env bash
# The time-stepping peer comparison of docs/PERFORMANCE.md: a sphere of radius 0.25 at the centre
# of the unit cube oscillating along x (amplitude 0.1, one period in 20 steps, the cube's walls
# fixed), moved over 20 time steps by OpenFOAM's `moveMesh` (displacementLaplacian, GAMG to a
# 1e-8 residual with relTol 0; the sphere's `oscillatingDisplacement`) and by `meshmove deform`
# (biharmonic and Laplacian to a 1e-8 relative residual; the sphere's periodic motion, one
# `advance` a step), one thread each, on the same Gmsh mesh (tetrahedra, or the hexahedra of
# Gmsh's subdivision of them): the seconds a step and the smallest volume ratio (a cell's volume
# over its volume in the mesh as read) over the period of each, as a Markdown table.
#
#   scripts/peer-openfoam-steps.sh [tet|hex] [H] [WORKDIR]
#
# H is Gmsh's mesh size: tetrahedra 0.032 give 26k vertices and 0.0146 about 250k; hexahedra
# (each tetrahedron cut into four) 0.092 give 30k and 0.047 about 250k. Defaults: tet,
# 0.032. Needs Gmsh and OpenFOAM (`gmshToFoam`, `moveMesh`, `postProcess` on PATH) and GNU time;
# without them it says so and exits 0. The volume ratios of our meshes need a Python with the
# `vtk` module (python3-vtk9); without it they are n/a. Not run in CI. The meshmove binary is
# $MESHMOVE, else target/release/meshmove (built with `cargo build --release`).
set -euo pipefail

CELLS="${1:-tet}"
H="${2:-0.032}"
WORK="${3:-$(mktemp -d -t meshmove-peer-steps-XXXXXX)}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
MESHMOVE="${MESHMOVE:-$ROOT/target/release/meshmove}"
STEPS=20
AMPLITUDE=0.1

for tool in gmsh gmshToFoam moveMesh postProcess; do
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
    tet) SUBDIVIDE=0 ;;
    hex) SUBDIVIDE=2 ;;
    *) echo "peer-openfoam-steps: cells must be tet or hex, got $CELLS" >&2; exit 2 ;;
esac
# Debian's packaged OpenFOAM runs without its environment once it knows where etc/ is.
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
    export WM_PROJECT_DIR=/usr/share/openfoam
fi
PYTHON=""
for p in python3 /usr/bin/python3; do
    if command -v "$p" >/dev/null 2>&1 && "$p" -c "import vtk" >/dev/null 2>&1; then PYTHON="$p"; break; fi
done

mkdir -p "$WORK"
cd "$WORK"

# The mesh: Gmsh's tetrahedra of the cube minus the sphere (patches `walls` and `sphere`), or
# their subdivision into hexahedra; MSH 2.2 ASCII, which both tools read.
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
vertices=$(awk '/^\$Nodes/ {getline; print; exit}' sphere.msh)
echo "peer-openfoam-steps: $CELLS, h = $H: $vertices vertices, in $WORK"

# OpenFOAM's case: the same mesh, the sphere oscillating as sin(2π t / 20) with t the step.
foam_header() {
    printf 'FoamFile\n{\n    version 2.0;\n    format ascii;\n    class %s;\n    location "%s";\n    object %s;\n}\n' "$1" "$2" "$3"
}
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
gmshToFoam sphere.msh -case foam >gmshToFoam.log 2>&1

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

# OpenFOAM, timed (writing only the last step), then again writing every step for the volumes.
/usr/bin/time -v moveMesh -case foam >foam-move.log 2>foam-time.log
control 1
moveMesh -case foam >foam-move-all.log 2>&1
postProcess -case foam -func writeCellVolumes >foam-volumes.log 2>&1
foam_ratio=$(awk -v steps="$STEPS" '
    # The cell volumes of foam/T/V, T = 0 .. steps: the smallest V_T / V_0.
    function read(f, v,   n, i, line, started) {
        n = 0; started = 0
        while ((getline line < f) > 0) {
            if (!started && line ~ /^internalField/) { started = 1; getline line < f; getline line < f; continue }
            if (started) { if (line ~ /^\)/) break; v[n++] = line + 0 }
        }
        close(f); return n
    }
    BEGIN {
        m = read("foam/0/V", v0); best = 1e300
        for (t = 1; t <= steps; t++) { if (read("foam/" t "/V", v) != m) { print "n/a"; exit }
            for (i = 0; i < m; i++) if (v[i] / v0[i] < best) best = v[i] / v0[i] }
        printf "%.4f", best
    }')

# meshmove: deform with the sphere's periodic motion, timed; again writing every step.
ours() {
    local name="$1" method="$2" kind="$3"
    cat >"$name.toml" <<TOML
method = "$method"
tolerance = 1e-8
threads = 1
steps = $STEPS

[[patch]]
patch = "sphere"
kind = "$kind"

[[motion]]
patch = "sphere"
translation = [$AMPLITUDE, 0.0, 0.0]
period = $STEPS
TOML
    /usr/bin/time -v "$MESHMOVE" deform sphere.msh --config "$name.toml" -o "$name.vtu" --report "$name.jsonl" \
        >"$name.log" 2>"$name-time.log"
    mkdir -p "$name-steps"
    "$MESHMOVE" deform sphere.msh --config "$name.toml" -o "$name-steps/s.vtu" --every 1 >/dev/null 2>&1 || true
}
ours biharmonic biharmonic clamped
ours laplacian laplacian fixed
# Setup + all steps (the deform line), a step: that over the steps.
motion_s() { grep -o 'cycles, [0-9.]* s' "$1.log" | awk -v n="$STEPS" '{printf "%.3f", $2 / n}'; }
solve_s() { grep -o '"seconds":[0-9.eE+-]*' "$1.jsonl" | cut -d: -f2 | awk '{s += $1} END {printf "%.3f", s / NR}'; }
cycles() { grep -o '"cycles":[0-9]*' "$1.jsonl" | cut -d: -f2 | awk '{s += $1} END {printf "%.1f", s / NR}'; }
our_ratio() {
    if [ -z "$PYTHON" ]; then echo "n/a"; return; fi
    "$PYTHON" - "$1-steps" <<'PY'
import glob, sys, vtk
best = float("inf")
for f in sorted(glob.glob(sys.argv[1] + "/s_*.vtu")):
    r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(f); r.Update()
    a = r.GetOutput().GetCellData().GetArray("volume_ratio")
    best = min([best] + [a.GetValue(i) for i in range(a.GetNumberOfTuples()) if a.GetValue(i) == a.GetValue(i)])
print("%.4f" % best)
PY
}
foam_its=$(grep -o 'cellDisplacementx, .*No Iterations [0-9]*' foam-move.log | awk '{s += $NF} END {printf "%.1f", s / NR}')

cat <<MD

Sphere in the unit cube, $CELLS, h = $H: $vertices vertices; the sphere oscillating along x by $AMPLITUDE, one period in $STEPS steps; one thread each.

| | OpenFOAM moveMesh, displacementLaplacian (GAMG, 1e-8) | meshmove biharmonic (1e-8) | meshmove Laplacian (1e-8) |
|---|---|---|---|
| process wall s (read, $STEPS steps, write) | $(wall_s foam-time.log) | $(wall_s biharmonic-time.log) | $(wall_s laplacian-time.log) |
| process CPU s over $STEPS steps, a step | $(cpu_step_s foam-time.log) | $(cpu_step_s biharmonic-time.log) | $(cpu_step_s laplacian-time.log) |
| motion s a step (OpenFOAM: CPU s of steps 2–$STEPS; ours: setup and steps over $STEPS, wall) | $(foam_step_s foam-move.log) | $(motion_s biharmonic) | $(motion_s laplacian) |
| solve s a step (wall) | | $(solve_s biharmonic) | $(solve_s laplacian) |
| iterations a step (x) | ${foam_its} (GAMG V-cycles) | $(cycles biharmonic) (CG + W-cycle) | $(cycles laplacian) (CG + W-cycle) |
| min volume ratio over the period | ${foam_ratio} | $(our_ratio biharmonic) | $(our_ratio laplacian) |
MD
