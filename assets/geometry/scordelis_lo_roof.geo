// The Scordelis-Lo roof's quarter surface (MacNeal & Harder 1985, problem 3) as a CAD part, built
// with Gmsh's OpenCASCADE kernel and written as STEP:
//     gmsh -0 scordelis_lo_roof.geo      (writes scordelis_lo_roof.step beside this file)
// The quarter FlexFrame's own `cylinder` generator builds for the same benchmark: radius 25 about
// the y axis, the crown (azimuth 0) at z = 25 along x = 0, the free edge at 40 degrees from the
// crown, y from 0 (the mid-span symmetry plane) to 25 (the end diaphragm).
SetFactory("OpenCASCADE");
R = 25;
half_span = 25;
edge_angle = 40 * Pi / 180;
Point(1) = {0, 0, 0};                                  // centre of the arc
Point(2) = {0, 0, R};                                  // crown
Point(3) = {R * Sin(edge_angle), 0, R * Cos(edge_angle)};  // free edge
Circle(1) = {2, 1, 3};
Extrude {0, half_span, 0} { Curve{1}; }
Recursive Delete { Point{1}; }
Save "scordelis_lo_roof.step";
