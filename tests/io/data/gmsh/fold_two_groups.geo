// Two plane faces meeting at 90 degrees along x = 1 (a floor and a wall), each its own physical
// surface, for parts cut from one file by part.group (tests/io/test_mesh_import_gmsh.cpp).
Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25}; Point(3) = {1, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Point(5) = {1, 0, 1, 0.25}; Point(6) = {1, 1, 1, 0.25};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Physical Surface("floor") = {1};
Physical Surface("wall") = {2};
Physical Curve("clamped") = {4};
Physical Curve("top") = {6};
