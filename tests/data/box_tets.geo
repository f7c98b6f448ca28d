// Unit cube meshed with tetrahedra: one physical volume and two physical surfaces (bottom z = 0,
// top z = 1); the four sides have no physical group. Regenerate with gen_fixtures.sh.
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
out[] = Extrude {0, 0, 1} { Surface{1}; };
// out[0]: the top surface, out[1]: the volume, out[2..5]: the sides.
Physical Surface("bottom", 1) = {1};
Physical Surface("top", 2) = {out[0]};
Physical Volume("solid", 10) = {out[1]};
