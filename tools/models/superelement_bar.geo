// A 1 m steel bar of 0.05 m x 0.05 m section along x (issue 58's size target), meshed in
// tet10 (C3D10) for CalculiX: tests/bench/superelement_vs_calculix.sh gives the element size
// (-clmax; 0.008 m: 40 680 nodes, 121 245 free DOFs) and the material and boundary.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1.0, 0.05, 0.05};
Physical Volume("bar") = {1};
Mesh.ElementOrder = 2;
