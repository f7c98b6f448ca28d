// A triangulated unit square extruded in two layers of prisms (Gmsh element type 6): one physical
// volume and two physical surfaces (bottom z = 0, top z = 0.5). Regenerate with gen_fixtures.sh.
lc = 0.5;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{2}; Recombine; };
Physical Surface("bottom", 1) = {1};
Physical Surface("top", 2) = {out[0]};
Physical Volume("slab", 7) = {out[1]};
