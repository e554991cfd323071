// Cantilever beam: a box of length L (x), width W (y) and height H (z).
// Physical groups: "clamped" (x = 0 face), "tip" (x = L face), "sides" (all other faces), "beam" (volume).
// L, W and H can be overridden from the parameter file; the element size is set by nlmech.
SetFactory("OpenCASCADE");
DefineConstant[ L = 1.0, W = 0.1, H = 0.1 ];
Box(1) = {0, 0, 0, L, W, H};
eps = 1e-6 * L;
clamped() = Surface In BoundingBox{-eps, -eps, -eps, eps, W + eps, H + eps};
tip() = Surface In BoundingBox{L - eps, -eps, -eps, L + eps, W + eps, H + eps};
all() = Boundary{ Volume{1}; };
sides() = all();
sides() -= clamped();
sides() -= tip();
Physical Surface("clamped") = clamped();
Physical Surface("tip") = tip();
Physical Surface("sides") = sides();
Physical Volume("beam") = {1};
