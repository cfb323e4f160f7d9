// The hemisphere with an 18 degree hole (MacNeal & Harder 1985; Sze, Liu & Lo 2004 section 3.4) as
// a CAD surface: a quarter of an OpenCASCADE sphere of radius 10, centre at the origin, from the
// equator z = 0 to the hole's edge at 18 degrees from the pole, azimuth 0 to 90 degrees - the
// quarter that FlexFrame's spherical_cap generator builds for assets/scenes/hemisphere_18deg_h004.toml.
// OpenCASCADE builds a sphere sector as a solid; only its spherical face is kept. The face's seam
// (azimuth 0) is its edge on the plane y = 0 and the pole lies in the hole, so neither is inside
// the mesh. The directors are the sphere's own normals (radial). FlexFrame meshes it into quads at
// part.mesh_size (at most 1.7 here: see docs/validation/imported-geometry.md). The triangle meshes
// of that comparison were written from this file by the gmsh program (Frontal-Delaunay triangles;
// the points have no size of their own, so Gmsh's default, a tenth of the bounding box's diagonal,
// 1.704, is scaled to the size s wanted: -clscale s / 1.704):
//     gmsh -2 hemisphere_18deg_quarter.geo -clscale 1.5258 -o hemisphere_tri_2p6.msh    (s = 2.6)
//     gmsh -2 hemisphere_18deg_quarter.geo -clscale 1.1737 -o hemisphere_tri_2p0.msh    (s = 2.0)
//     gmsh -2 hemisphere_18deg_quarter.geo -clscale 0.8216 -o hemisphere_tri_1p4.msh    (s = 1.4)
//     gmsh -2 hemisphere_18deg_quarter.geo -clscale 1.1737 -string "Mesh.SubdivisionAlgorithm=1;" \
//          -o hemisphere_tri_2p0_subdivided_on_cad.msh   (the 2.0 triangles split by Gmsh onto the sphere)
// (in tests/io/data/gmsh/).
SetFactory("OpenCASCADE");
R = 10;
hole = 18 * Pi / 180;
Sphere(1) = {0, 0, 0, R, 0, Pi / 2 - hole, Pi / 2};   // latitude 0 to 72 degrees, azimuth 0 to 90
e = 1e-3;
flat() = Surface In BoundingBox{-e, -e, -e, R + e, R + e, e};                                // the equator's disc
flat() += Surface In BoundingBox{-e, -e, R * Cos(hole) - e, R + e, R + e, R * Cos(hole) + e};  // the hole's disc
flat() += Surface In BoundingBox{-e, -e, -e, R + e, e, R + e};                               // the plane y = 0
flat() += Surface In BoundingBox{-e, -e, -e, e, R + e, R + e};                               // the plane x = 0
Delete { Volume{1}; }
Recursive Delete { Surface{flat()}; }
Physical Surface("hemisphere") = Surface{:};
Physical Curve("symmetry_x") = Curve In BoundingBox{-e, -e, -e, e, R + e, R + e};   // on the plane x = 0
Physical Curve("symmetry_y") = Curve In BoundingBox{-e, -e, -e, R + e, e, R + e};   // on the plane y = 0
Physical Point("load_outward") = Point In BoundingBox{R - e, -e, -e, R + e, e, e};   // (R, 0, 0)
Physical Point("load_inward") = Point In BoundingBox{-e, R - e, -e, e, R + e, e};    // (0, R, 0)
