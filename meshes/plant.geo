// A branching plant: a vertical stem of height Hs with two side branches of length Lb leaving it at
// 60 degrees from the vertical at heights 0.5 Hs and 0.8 Hs, all of round cross-section (radii rs,
// rb). Under gravity the branches droop; inverse design finds the rest shape that holds this one.
// Physical groups: "clamped" (the stem's base, z = 0), "surface", "plant" (the volume).
SetFactory("OpenCASCADE");
DefineConstant[ Hs = 0.12, Lb = 0.06, rs = 0.006, rb = 0.004 ];
Cylinder(1) = {0, 0, 0, 0, 0, Hs, rs};
s = Sin(Pi / 3); c = Cos(Pi / 3);
Cylinder(2) = {0, 0, 0.5 * Hs, Lb * s, 0, Lb * c, rb};
Cylinder(3) = {0, 0, 0.8 * Hs, -Lb * s, 0, Lb * c, rb};
BooleanUnion(4) = { Volume{1}; Delete; }{ Volume{2, 3}; Delete; };
e = 1e-6;
clamped() = Surface In BoundingBox{-rs - e, -rs - e, -e, rs + e, rs + e, e};
surface() = Boundary{ Volume{4}; };
surface() -= clamped();
Physical Surface("clamped") = clamped();
Physical Surface("surface") = surface();
Physical Volume("plant") = {4};
