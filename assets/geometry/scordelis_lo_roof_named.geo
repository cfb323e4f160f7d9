// Names the parts of scordelis_lo_roof.step that the scene supports and probes, as Gmsh physical
// groups (the standard way to name the entities of a CAD part for a solver). Each group is found
// by a box around it, so it does not depend on the STEP file's entity numbers.
SetFactory("OpenCASCADE");
Merge "scordelis_lo_roof.step";
e = 1e-3;
Physical Surface("roof") = Surface{:};
Physical Curve("diaphragm") = Curve In BoundingBox{-1, 25 - e, -1, 30, 25 + e, 30};  // the end, y = 25
Physical Curve("midspan") = Curve In BoundingBox{-1, -e, -1, 30, e, 30};           // symmetry plane y = 0
Physical Curve("crown") = Curve In BoundingBox{-e, -1, 25 - e, e, 26, 25 + e};      // symmetry plane x = 0
Physical Point("midside") = Point In BoundingBox{16.06, -e, 19.14, 16.08, e, 19.16};  // free edge at mid-span
