// Block [0,a]x[0,b]x[0,c] with one physical group per face, for tests with symmetry planes.
// Physical groups: "x0", "x1", "y0", "y1", "z0", "z1" (faces), "block" (volume).
SetFactory("OpenCASCADE");
DefineConstant[ a = 1.0, b = 1.0, c = 1.0 ];
Box(1) = {0, 0, 0, a, b, c};
e = 1e-6;
Physical Surface("x0") = Surface In BoundingBox{-e, -e, -e, e, b + e, c + e};
Physical Surface("x1") = Surface In BoundingBox{a - e, -e, -e, a + e, b + e, c + e};
Physical Surface("y0") = Surface In BoundingBox{-e, -e, -e, a + e, e, c + e};
Physical Surface("y1") = Surface In BoundingBox{-e, b - e, -e, a + e, b + e, c + e};
Physical Surface("z0") = Surface In BoundingBox{-e, -e, -e, a + e, b + e, e};
Physical Surface("z1") = Surface In BoundingBox{-e, -e, c - e, a + e, b + e, c + e};
Physical Volume("block") = {1};
