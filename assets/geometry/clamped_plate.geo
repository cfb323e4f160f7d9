// The clamped square plate of assets/scenes/clamped_plate_pressure.toml (a = 1, Timoshenko &
// Woinowsky-Krieger Table 35) as a Gmsh script: FlexFrame meshes it into quads at part.mesh_size
// (Frontal-Delaunay with Blossom recombination). The centre is a point of the surface, so that
// every mesh has a node there for the probe. The triangle meshes of the accuracy comparison
// (docs/validation/imported-geometry.md) are written from this file by the gmsh program:
//     gmsh -2 clamped_plate.geo -clmax 0.25 -o ../../tests/io/data/gmsh/clamped_plate_tri_0p25.msh
// and likewise at 0.2 and 0.15 (Gmsh's default 2D algorithm, Frontal-Delaunay, without
// recombination: triangles).
Point(1) = {0, 0, 0, 1};
Point(2) = {1, 0, 0, 1};
Point(3) = {1, 1, 0, 1};
Point(4) = {0, 1, 0, 1};
Point(5) = {0.5, 0.5, 0, 1};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Point{5} In Surface{1};
Physical Surface("plate") = {1};
Physical Curve("edges") = {1, 2, 3, 4};
Physical Point("centre") = {5};
