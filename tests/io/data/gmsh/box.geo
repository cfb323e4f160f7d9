// A meshed cube (tetrahedra): a volume mesh that the shell import refuses. gmsh -3 box.geo -o box_volume.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Mesh.MeshSizeMax = 1;
