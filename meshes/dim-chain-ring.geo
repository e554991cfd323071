// A torus ring for the triangulated ring chain (prm/dim-mesh-ring-chain.prm): major radius R = 4,
// tube radius r = 1 [mm], centred at the origin in the xy plane (the validation ring of
// prm/dim-ring-chain.prm as a triangulated surface). Meshed as a closed surface (2D) by nlmech with
// the prm's mesh size.
SetFactory("OpenCASCADE");
DefineConstant[ R = 4, r = 1 ];
Torus(1) = {0, 0, 0, R, r};
