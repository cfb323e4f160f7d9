// The unit square of the Gmsh import tests (tests/io/test_mesh_import_gmsh.cpp), written as .msh by
//   gmsh -2 square.geo -o square_quads_v4.msh                    (4 x 4 structured quads)
//   gmsh -2 square.geo -format msh22 -o square_quads_v22.msh
//   gmsh -2 square.geo -setnumber triangles 1 -o square_triangles.msh
//   gmsh -2 square.geo -setnumber triangles 1 -o square_triangles.stl     (ASCII STL: triangles only)
If (!Exists(triangles))
  triangles = 0;
EndIf
Point(1) = {0, 0, 0, 0.25};
Point(2) = {1, 0, 0, 0.25};
Point(3) = {1, 1, 0, 0.25};
Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
If (!triangles)
  Transfinite Curve{1, 2, 3, 4} = 5;
  Transfinite Surface{1};
  Recombine Surface{1};
EndIf
Physical Curve("left") = {4};
Physical Curve("right") = {2};
Physical Point("corner") = {3};
Physical Surface("plate") = {1};
