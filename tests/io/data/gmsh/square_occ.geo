// The unit square as a STEP part for the fuzz test (tests/cli/cli_fuzz_test.cpp):
//   gmsh -0 square_occ.geo     (writes square.step beside this file)
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Save "square.step";
