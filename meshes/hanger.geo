// A clothes hanger (ANM paper Fig. 8, a hanger-like shape): two shoulder arms from the apex down to
// the ends of a horizontal bottom bar of width W, at height Hh below the apex, and a neck of length
// Ln above the apex, clamped at its top (where the hook would sit on a rail). All of round
// cross-section with radius r; spheres round the three corners. Designed to keep its bottom bar
// horizontal under its own weight, and to sag by a chosen amount under the weight of a garment.
// Physical groups: "clamped" (the neck's top, z = Ln), "bar" (unused by default), "surface",
// "hanger" (the volume).
SetFactory("OpenCASCADE");
DefineConstant[ W = 0.3, Hh = 0.1, Ln = 0.03, r = 0.006 ];
Cylinder(1) = {0, 0, 0, 0, 0, Ln, r};
Cylinder(2) = {0, 0, 0, -W / 2, 0, -Hh, r};
Cylinder(3) = {0, 0, 0, W / 2, 0, -Hh, r};
Cylinder(4) = {-W / 2, 0, -Hh, W, 0, 0, r};
Sphere(5) = {0, 0, 0, r};
Sphere(6) = {-W / 2, 0, -Hh, r};
Sphere(7) = {W / 2, 0, -Hh, r};
BooleanUnion(8) = { Volume{1}; Delete; }{ Volume{2, 3, 4, 5, 6, 7}; Delete; };
e = 1e-6;
clamped() = Surface In BoundingBox{-r - e, -r - e, Ln - e, r + e, r + e, Ln + e};
surface() = Boundary{ Volume{8}; };
surface() -= clamped();
Physical Surface("clamped") = clamped();
Physical Surface("surface") = surface();
Physical Volume("hanger") = {8};
