// A planar lattice-free "Eiffel tower" silhouette in the xy plane (thesis Fig. 2.13): two legs
// standing on the ground, joined by an arch, tapering into a spire. Lengths in m. Physical
// groups: "base" (the two feet, the curves on y = 0, driven by a shaker), "tower" (the surface),
// "tip" (the top edge).
DefineConstant[ height = 1.0, base_width = 0.4, foot = 0.08, arch_height = 0.18, waist_height = 0.45,
                waist_width = 0.12, top_width = 0.03 ];
w = base_width / 2;
Point(1)  = {-w, 0, 0};
Point(2)  = {-w + foot, 0, 0};
Point(3)  = {0, arch_height, 0};  // top of the arch between the legs
Point(4)  = {w - foot, 0, 0};
Point(5)  = {w, 0, 0};
Point(6)  = {waist_width / 2, waist_height, 0};
Point(7)  = {top_width / 2, height, 0};
Point(8)  = {-top_width / 2, height, 0};
Point(9)  = {-waist_width / 2, waist_height, 0};
Point(10) = {0, (arch_height^2 - (w - foot)^2) / (2 * arch_height), 0}; // centre of the arch
Line(1) = {1, 2};
Circle(2) = {2, 10, 3};
Circle(3) = {3, 10, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 9};
Line(9) = {9, 1};
Curve Loop(1) = {1:9};
Plane Surface(1) = {1};
Physical Curve("base") = {1, 4};
Physical Curve("tip") = {7};
Physical Surface("tower") = {1};
