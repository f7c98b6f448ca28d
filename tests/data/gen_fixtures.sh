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
