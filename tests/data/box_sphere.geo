// The unit cube minus a sphere of radius 0.25 at its centre, meshed with tetrahedra: physical
// surfaces "walls" (1: the cube's six sides) and "sphere" (2), physical volume "fluid" (10).
// Regenerate with gen_fixtures.sh (box_sphere.msh, and box_sphere.vtu by meshio's default export).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Sphere(2) = {0.5, 0.5, 0.5, 0.25};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Mesh.MeshSizeMin = 0.15;
Mesh.MeshSizeMax = 0.15;
Physical Surface("walls", 1) = {1, 2, 3, 4, 5, 6};
Physical Surface("sphere", 2) = {7};
Physical Volume("fluid", 10) = {3};
