// A torus element for the DIM "mesh element" pattern: major radius R, tube radius r [mm], centred
// at the origin in the xy plane. Meshed as a closed surface (2D) by nlmech with the prm's mesh size.
SetFactory("OpenCASCADE");
DefineConstant[ R = 3, r = 1 ];
Torus(1) = {0, 0, 0, R, r};
