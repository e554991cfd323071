// A hook: a straight stem of length Ls along z (clamped at its base, z = 0) ending in a half ring of
// centre-line radius R, all of round cross-section with radius r. For hanging loads on the tip.
// Physical groups: "clamped" (the stem's base), "tip" (the free end of the ring), "surface", "hook".
SetFactory("OpenCASCADE");
DefineConstant[ Ls = 0.1, R = 0.03, r = 0.006 ];
Cylinder(1) = {0, 0, 0, 0, 0, Ls, r};
// Half torus in the xz plane, from the stem top (0, 0, Ls) over to (2R, 0, Ls), curling upwards.
Torus(2) = {R, 0, Ls, R, r, Pi};
Rotate {{1, 0, 0}, {R, 0, Ls}, Pi / 2} { Volume{2}; }
BooleanUnion(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
e = 1e-6;
clamped() = Surface In BoundingBox{-r - e, -r - e, -e, r + e, r + e, e};
tip() = Surface In BoundingBox{2 * R - r - e, -r - e, Ls - e, 2 * R + r + e, r + e, Ls + e};
surface() = Boundary{ Volume{3}; };
surface() -= clamped();
surface() -= tip();
Physical Surface("clamped") = clamped();
Physical Surface("tip") = tip();
Physical Surface("surface") = surface();
Physical Volume("hook") = {3};
