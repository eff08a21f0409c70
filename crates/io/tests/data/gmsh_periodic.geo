// The box of gmsh_box.geo with the outlet a periodic copy of the inlet, for the files that
// carry a $Periodic section.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 2, 1, 1};
Periodic Surface {2} = {1} Translate {2, 0, 0};
Physical Surface("inlet", 7) = {1};
Physical Surface("outlet", 8) = {2};
Physical Surface("walls", 9) = {3, 4, 5, 6};
Physical Volume("fluid", 3) = {1};
