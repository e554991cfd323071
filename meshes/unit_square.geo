// Unit square [0,1]^2 for manufactured solutions. Physical groups: "boundary" (all edges), "domain".
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 1, 1};
Physical Curve("boundary") = Boundary{ Surface{1}; };
Physical Surface("domain") = {1};
