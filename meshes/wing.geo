// A tapered flat wing in the xy plane (thesis Fig. 2.1/2.7): span along y from the root (y = 0) to
// the tip (y = span), the leading edge straight along x = 0, the trailing edge from x = root_chord
// at the root to x = tip_chord at the tip. Lengths in m. Physical groups: "root" (the strip of the
// first root_strip of span, a surface: the part a servo horn holds and rotates), "wing" (the rest),
// "trailing" (the trailing edge curve, where the design places its weights).
DefineConstant[ span = 0.3, root_chord = 0.1, tip_chord = 0.06, root_strip = 0.02 ];
c = root_chord + (tip_chord - root_chord) * root_strip / span;
Point(1) = {0, 0, 0};
Point(2) = {root_chord, 0, 0};
Point(3) = {c, root_strip, 0};
Point(4) = {0, root_strip, 0};
Point(5) = {tip_chord, span, 0};
Point(6) = {0, span, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {3, 5};
Line(6) = {5, 6};
Line(7) = {6, 4};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7};
Plane Surface(2) = {2};
Physical Surface("root") = {1};
Physical Surface("wing") = {2};
Physical Curve("trailing") = {2, 5};
