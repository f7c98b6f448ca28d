// A cylinder of diameter 1 in a channel [-4, 8] x [-3, 3], one layer of wedges 0.5 thick in z
// (the flow is two-dimensional: the faces z = 0 and z = 0.5 are symmetry planes).
// code_saturne's preprocessor keeps the physical groups' numbers, not their names, as the
// boundary zones' names: 1 inlet, 2 outlet, 3 walls, 4 cylinder, 5 symmetry planes.
// The layer is as thick as the far cells are wide: meshmove's multigrid does not coarsen a slab
// much thinner than its cells are wide (it then solves on one level, densely, every step).
// Mesh: gmsh -3 -format msh2 cylinder.geo -o cylinder.msh
lc_far = 0.5;
lc_body = 0.1;
r = 0.5;
Point(1) = {-4, -3, 0, lc_far};
Point(2) = {8, -3, 0, lc_far};
Point(3) = {8, 3, 0, lc_far};
Point(4) = {-4, 3, 0, lc_far};
Point(5) = {0, 0, 0, lc_body};
Point(6) = {r, 0, 0, lc_body};
Point(7) = {0, r, 0, lc_body};
Point(8) = {-r, 0, 0, lc_body};
Point(9) = {0, -r, 0, lc_body};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
// ext[0] the top face, ext[1] the volume, ext[2..] the sides of lines 1, 2, 3, 4, 5, 6, 7, 8.
ext[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{1}; Recombine; };
Physical Surface(1) = {ext[5]};
Physical Surface(2) = {ext[3]};
Physical Surface(3) = {ext[2], ext[4]};
Physical Surface(4) = {ext[6], ext[7], ext[8], ext[9]};
Physical Surface(5) = {1, ext[0]};
Physical Volume(10) = {ext[1]};
