#!/usr/bin/env bash
# The peer comparison on a real polyhedral mesh: a snappyHexMesh mesh of the box [-1,1]³ round a
# ball (radius 0.4 at the origin; hexahedra, and polyhedra where the ball's refinement and
# snapping made them), the ball translated by (0.1, 0.05, 0) with the box's faces fixed, moved by
# OpenFOAM's `moveMesh` (displacementLaplacian, GAMG to a 1e-8 residual, relTol 0) and by
# `meshmove deform` on the polyMesh itself (biharmonic with the ball clamped, and Laplacian, to a
# 1e-8 relative residual), one thread each; meshmove's moved meshes are written as the case's
# times 2 and 3, so that `checkMesh` measures all three alike. Prints a Markdown table.
#
#   scripts/peer-openfoam-snappy.sh [N] [LEVEL] [WORKDIR]   N base cells per side (default 24),
#                                                            LEVEL the ball's refinement (default 2)
#
# Needs OpenFOAM (`blockMesh`, `snappyHexMesh`, `moveMesh`, `checkMesh` on PATH) and GNU time;
# without OpenFOAM it says so and exits 0. Not run in CI. The meshmove binary is $MESHMOVE, else
# target/release/meshmove.
set -euo pipefail

N="${1:-24}"
LEVEL="${2:-2}"
WORK="${3:-$(mktemp -d -t meshmove-snappy-XXXXXX)}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
MESHMOVE="${MESHMOVE:-$ROOT/target/release/meshmove}"

for tool in blockMesh snappyHexMesh moveMesh checkMesh; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "peer-openfoam-snappy: OpenFOAM's $tool is not on PATH; nothing to compare"
        exit 0
    fi
done
if [ ! -x /usr/bin/time ] || [ ! -x "$MESHMOVE" ]; then
    echo "peer-openfoam-snappy: needs GNU time (/usr/bin/time) and the meshmove binary at $MESHMOVE" >&2
    exit 1
fi
if [ -z "${WM_PROJECT_DIR:-}" ] && [ -f /usr/share/openfoam/etc/controlDict ]; then
    export WM_PROJECT_DIR=/usr/share/openfoam
fi

C="$WORK/case"
mkdir -p "$C/system" "$C/constant" "$C/0"
hdr() { echo "FoamFile { version 2.0; format ascii; class $1; object $2; }"; }
{
    hdr dictionary controlDict
    echo "application moveMesh; startFrom startTime; startTime 0; stopAt endTime; endTime 1; deltaT 1;"
    echo "writeControl timeStep; writeInterval 1; writeFormat binary; writePrecision 17; writeCompression off;"
    echo "timeFormat general; timePrecision 6; runTimeModifiable false;"
} >"$C/system/controlDict"
{
    hdr dictionary fvSchemes
    echo "ddtSchemes { default Euler; } gradSchemes { default Gauss linear; } divSchemes { default none; }"
    echo "laplacianSchemes { default Gauss linear corrected; } interpolationSchemes { default linear; }"
    echo "snGradSchemes { default corrected; }"
} >"$C/system/fvSchemes"
{
    hdr dictionary fvSolution
    echo "solvers { cellDisplacement { solver GAMG; smoother GaussSeidel; tolerance 1e-8; relTol 0; maxIter 1000; } }"
} >"$C/system/fvSolution"
{
    hdr dictionary blockMeshDict
    echo "vertices ( (-1 -1 -1) (1 -1 -1) (1 1 -1) (-1 1 -1) (-1 -1 1) (1 -1 1) (1 1 1) (-1 1 1) );"
    echo "blocks ( hex (0 1 2 3 4 5 6 7) ($N $N $N) simpleGrading (1 1 1) ); edges ();"
    echo "boundary ( outer { type wall; faces ( (0 3 2 1) (4 5 6 7) (0 4 7 3) (1 2 6 5) (0 1 5 4) (3 7 6 2) ); } );"
} >"$C/system/blockMeshDict"
{
    hdr dictionary snappyHexMeshDict
    echo "castellatedMesh true; snap true; addLayers false;"
    echo "geometry { ball { type searchableSphere; centre (0 0 0); radius 0.4; } }"
    echo "castellatedMeshControls { maxLocalCells 10000000; maxGlobalCells 20000000; minRefinementCells 0;"
    echo "  maxLoadUnbalance 0.1; nCellsBetweenLevels 2; features ();"
    echo "  refinementSurfaces { ball { level ($LEVEL $LEVEL); patchInfo { type wall; } } }"
    echo "  resolveFeatureAngle 30; refinementRegions {} locationInMesh (0.83 0.81 0.79); allowFreeStandingZoneFaces true; }"
    echo "snapControls { nSmoothPatch 3; tolerance 2.0; nSolveIter 30; nRelaxIter 5; nFeatureSnapIter 10;"
    echo "  implicitFeatureSnap false; explicitFeatureSnap false; multiRegionFeatureSnap false; }"
    echo "addLayersControls { relativeSizes true; layers {} expansionRatio 1; finalLayerThickness 0.3; minThickness 0.1;"
    echo "  nGrow 0; featureAngle 60; nRelaxIter 3; nSmoothSurfaceNormals 1; nSmoothNormals 3; nSmoothThickness 10;"
    echo "  maxFaceThicknessRatio 0.5; maxThicknessToMedialRatio 0.3; minMedialAxisAngle 90; nBufferCellsNoExtrude 0;"
    echo "  nLayerIter 50; }"
    echo "meshQualityControls { maxNonOrtho 65; maxBoundarySkewness 20; maxInternalSkewness 4; maxConcave 80;"
    echo "  minVol 1e-13; minTetQuality 1e-15; minArea -1; minTwist 0.02; minDeterminant 0.001; minFaceWeight 0.05;"
    echo "  minVolRatio 0.01; minTriangleTwist -1; nSmoothScale 4; errorReduction 0.75; relaxed { maxNonOrtho 75; } }"
    echo "mergeTolerance 1e-6;"
} >"$C/system/snappyHexMeshDict"
{
    hdr dictionary dynamicMeshDict
    echo "dynamicFvMesh dynamicMotionSolverFvMesh; motionSolverLibs (\"libfvMotionSolvers.so\");"
    echo "motionSolver displacementLaplacian; solver displacementLaplacian;"
    echo "displacementLaplacianCoeffs { diffusivity uniform; }"
} >"$C/constant/dynamicMeshDict"
{
    hdr pointVectorField pointDisplacement
    echo "dimensions [0 1 0 0 0 0 0]; internalField uniform (0 0 0);"
    echo "boundaryField { outer { type fixedValue; value uniform (0 0 0); }"
    echo "  ball { type fixedValue; value uniform (0.1 0.05 0); } }"
} >"$C/0/pointDisplacement"
cat >"$WORK/biharmonic.toml" <<EOF
method = "biharmonic"
tolerance = 1e-8
threads = 1

[[patch]]
patch = "outer"
kind = "fixed"

[[patch]]
patch = "ball"
kind = "clamped"

[[motion]]
patch = "ball"
translation = [0.1, 0.05, 0.0]
EOF
sed -e 's/"biharmonic"/"laplacian"/' -e 's/"clamped"/"fixed"/' "$WORK/biharmonic.toml" >"$WORK/laplacian.toml"

cd "$WORK"
blockMesh -case "$C" >blockMesh.log 2>&1
snappyHexMesh -case "$C" -overwrite >snappy.log 2>&1
checkMesh -case "$C" -constant >check0.log 2>&1 || true
cells=$(grep -o 'cells: *[0-9]*' check0.log | head -1 | awk '{print $2}')
points=$(grep -o 'points: *[0-9]*' check0.log | head -1 | awk '{print $2}')
polyhedra=$(awk '/polyhedra:/ {print $2; exit}' check0.log)

/usr/bin/time -v moveMesh -case "$C" >foam-move.log 2>foam-time.log
foam_its=$(grep -o 'cellDisplacementx, .*No Iterations [0-9]*' foam-move.log | awk '{print $NF}')
foam_exec=$(grep -o 'ExecutionTime = [0-9.]*' foam-move.log | tail -1 | awk '{printf "%.2f", $3}')
checkMesh -case "$C" -time 1 >foam-check.log 2>&1 || true

ours() {
    local name="$1" time="$2"
    /usr/bin/time -v "$MESHMOVE" deform "$C" --config "$name.toml" -o "$C/$time/polyMesh" --report "$name.jsonl" \
        >"$name.log" 2>"$name-time.log"
    checkMesh -case "$C" -time "$time" >"$name-check.log" 2>&1 || true
}
ours biharmonic 2
ours laplacian 3

peak_mb() { awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$1"; }
wall_s() {
    awk -F': ' '/Elapsed \(wall clock\)/ {
        n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.2f", s }' "$1"
}
minvol() { grep -o 'Min volume = [0-9.eE+-]*' "$1" | awk '{print $4}'; }
ratio() { awk -v a="$(minvol "$1")" -v b="$(minvol check0.log)" 'BEGIN { printf "%.4f", a / b }'; }
nonorth() { grep -o 'non-orthogonality Max: [0-9.eE+-]*' "$1" | awk '{printf "%.1f", $3}'; }
ok() { if grep -q 'Mesh OK.' "$1"; then echo OK; else echo "$(grep -c '\*\*\*' "$1") failed checks"; fi; }
its() { grep -o '"cycles":[0-9]*' "$1.jsonl" | head -1 | cut -d: -f2; }
motion_s() { grep -o 'cycles, [0-9.]* s' "$1.log" | awk '{print $2}'; }

cat <<EOF

snappyHexMesh round a ball: ${N}^3 base cells, refinement level ${LEVEL} at the ball; ${cells} cells
(${polyhedra} polyhedra as checkMesh counts them), ${points} points; the ball moved by (0.1, 0.05, 0); one thread each.

| | OpenFOAM moveMesh, displacementLaplacian (GAMG, 1e-8) | meshmove biharmonic (1e-8) | meshmove Laplacian (1e-8) |
|---|---|---|---|
| process wall s (read, move, write) | $(wall_s foam-time.log) | $(wall_s biharmonic-time.log) | $(wall_s laplacian-time.log) |
| motion s | ${foam_exec} | $(motion_s biharmonic) | $(motion_s laplacian) |
| iterations | ${foam_its} (GAMG, x) | $(its biharmonic) (CG + W-cycle) | $(its laplacian) (CG + W-cycle) |
| peak resident set MB | $(peak_mb foam-time.log) | $(peak_mb biharmonic-time.log) | $(peak_mb laplacian-time.log) |
| smallest cell volume / the unmoved mesh's (checkMesh) | $(ratio foam-check.log) | $(ratio biharmonic-check.log) | $(ratio laplacian-check.log) |
| max non-orthogonality ° (checkMesh; unmoved $(nonorth check0.log)) | $(nonorth foam-check.log) | $(nonorth biharmonic-check.log) | $(nonorth laplacian-check.log) |
| checkMesh | $(ok foam-check.log) | $(ok biharmonic-check.log) | $(ok laplacian-check.log) |
EOF
