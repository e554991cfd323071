// Unit cube [0,1]^3 for manufactured solutions. Physical groups: "boundary" (all faces), "domain".
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Surface("boundary") = Boundary{ Volume{1}; };
Physical Volume("domain") = {1};
