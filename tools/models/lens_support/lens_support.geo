// The lens support of a metrology frame as a 3-D solid (issue 58): a steel ring, outer radius
// 0.3 m, inner 0.2 m, 0.05 m thick, its bottom face at z = 0. Meshed in tet10 (C3D10) for
// CalculiX by make_lens_support.py, which gives the element size (-clmax) and the material.
SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 0.05, 0.3};
Cylinder(2) = {0, 0, 0, 0, 0, 0.05, 0.2};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Physical Volume("ring") = {3};
Mesh.ElementOrder = 2;
