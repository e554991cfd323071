// An inverted T of solid material (thesis Fig. 2.12): a square stem along z on a crossbar along x
// at the bottom. Lengths in m. Physical groups: "top" (the stem's upper face, driven by a rotating
// clamp), "solid" (the volume).
SetFactory("OpenCASCADE");
DefineConstant[ stem_width = 0.02, stem_height = 0.1, bar_length = 0.12, bar_height = 0.02 ];
Box(1) = {-bar_length / 2, -stem_width / 2, 0, bar_length, stem_width, bar_height};
Box(2) = {-stem_width / 2, -stem_width / 2, bar_height, stem_width, stem_width, stem_height};
BooleanUnion(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
top = bar_height + stem_height;
eps = 1e-6;
Physical Surface("top") = Surface In BoundingBox{-stem_width, -stem_width, top - eps, stem_width, stem_width, top + eps};
Physical Volume("solid") = {3};
