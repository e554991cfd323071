// Sphere surface of radius R as a triangulated surface (Triangulation<2,3>) for shell models.
// Physical groups: "surface".
SetFactory("OpenCASCADE");
DefineConstant[ R = 1.0 ];
Sphere(1) = {0, 0, 0, R};
Physical Surface("surface") = Boundary{ Volume{1}; };
