#!/bin/sh
# Regenerates the Gmsh fixtures (needs gmsh; these were made with Gmsh 4.8.4).
set -e
cd "$(dirname "$0")"
gmsh -2 square_hole.geo -format msh22 -o square_hole_22.msh
gmsh -2 square_hole.geo -format msh22 -bin -o square_hole_22_bin.msh
gmsh -2 square_hole.geo -format msh41 -o square_hole_41.msh
gmsh -2 square_hole.geo -format msh41 -bin -o square_hole_41_bin.msh
gmsh -2 two_regions.geo -format msh41 -save_all -o two_regions_41.msh
gmsh -2 two_regions.geo -format msh22 -bin -o two_regions_22_bin.msh
gmsh -3 box_tets.geo -format msh41 -o box_tets_41.msh
gmsh -3 slab_prisms.geo -format msh41 -bin -o slab_prisms_41_bin.msh
gmsh -3 slab_prisms.geo -format msh22 -o slab_prisms_22.msh
# The cube minus a sphere, and meshio's default .vtu export of it (meshio 5.0; python3-meshio).
gmsh -3 box_sphere.geo -format msh41 -o box_sphere.msh
python3 -c "import meshio; meshio.write('box_sphere.vtu', meshio.read('box_sphere.msh'))"
