// The 2 x 1 x 1 box of the gmsh_box* test files (see README.md for the commands).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Physical Surface("inlet", 7) = {1};
Physical Surface("outlet", 8) = {2};
Physical Surface("walls", 9) = {3, 4, 5, 6};
Physical Volume("fluid", 3) = {1};
