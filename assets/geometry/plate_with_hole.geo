// A plate with a central circular hole under uniaxial tension along x, the quarter x >= 0, y >= 0
// with the two symmetry planes: hole radius a = 1, plate 2L x 2b = 40 x 20 (hole diameter over
// width d/W = 0.1). The part of assets/scenes/plate_with_hole_geo.toml and of the displacement check
// against Kirsch's infinite plate (tests/io/test_imported_geometry_validation.cpp,
// docs/validation/imported-geometry.md). The points on the hole at 0, 45 and 90 degrees and on
// the symmetry lines at r = 2a are corners of the geometry, so every mesh has nodes there for the
// probes. The points carry no size of their own (lc = L): part.mesh_size sets the size, and
// part.local_size_groups = ["hole"] makes the hole's edge finer.
a = 1;     // hole radius
L = 20;    // half length (the loaded edge is x = L)
b = 10;    // half width
lc = L;
Point(1) = {0, 0, 0, lc};                               // the hole's centre
Point(2) = {a, 0, 0, lc};                               // hole, theta = 0 (on the load axis)
Point(3) = {a * Cos(Pi / 4), a * Sin(Pi / 4), 0, lc};   // hole, theta = 45 degrees
Point(4) = {0, a, 0, lc};                               // hole, theta = 90 degrees
Point(5) = {2 * a, 0, 0, lc};
Point(6) = {L, 0, 0, lc};
Point(7) = {L, b, 0, lc};
Point(8) = {0, b, 0, lc};
Point(9) = {0, 2 * a, 0, lc};
Line(1) = {2, 5};
Line(2) = {5, 6};
Line(3) = {6, 7};
Line(4) = {7, 8};
Line(5) = {8, 9};
Line(6) = {9, 4};
Circle(7) = {4, 1, 3};
Circle(8) = {3, 1, 2};
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Plane Surface(1) = {1};
Physical Surface("plate") = {1};
Physical Curve("hole") = {7, 8};
Physical Curve("symmetry_y") = {1, 2};     // on the plane y = 0
Physical Curve("symmetry_x") = {5, 6};     // on the plane x = 0
Physical Curve("loaded") = {3};            // x = L, the tension
Physical Point("hole_0") = {2};
Physical Point("hole_45") = {3};
Physical Point("hole_90") = {4};
Physical Point("axis_x_2a") = {5};
Physical Point("axis_y_2a") = {9};
