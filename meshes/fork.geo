// A planar tuning-fork-shaped thin shell in the xy plane (thesis Fig. 2.2): a stem along x from
// x = 0, a crossbar and two tines. Lengths in m. Physical groups: "handle" (the first handle_length
// of the stem, a surface: the part a shaker holds), "body" (the rest), "end" (the stem's end edge
// at x = 0). A shell held or driven only along one straight edge could still rotate about it (no
// rotational unknowns), hence the handle region.
DefineConstant[ stem_length = 0.06, stem_width = 0.02, bar_length = 0.02, bar_width = 0.07,
                tine_length = 0.08, tine_width = 0.015, handle_length = 0.012 ];
s = stem_length; b = s + bar_length; e = b + tine_length; h = handle_length;
Point(1)  = {0, -stem_width / 2, 0};
Point(2)  = {s, -stem_width / 2, 0};
Point(3)  = {s, -bar_width / 2, 0};
Point(4)  = {e, -bar_width / 2, 0};
Point(5)  = {e, -bar_width / 2 + tine_width, 0};
Point(6)  = {b, -bar_width / 2 + tine_width, 0};
Point(7)  = {b, bar_width / 2 - tine_width, 0};
Point(8)  = {e, bar_width / 2 - tine_width, 0};
Point(9)  = {e, bar_width / 2, 0};
Point(10) = {s, bar_width / 2, 0};
Point(11) = {s, stem_width / 2, 0};
Point(12) = {0, stem_width / 2, 0};
Point(13) = {h, -stem_width / 2, 0};
Point(14) = {h, stem_width / 2, 0};
Line(1) = {13, 2};
For i In {2:10}
  Line(i) = {i, i + 1};
EndFor
Line(11) = {11, 14};
Line(12) = {14, 13}; // the handle's inner edge
Line(13) = {14, 12};
Line(14) = {12, 1};  // the stem's end
Line(15) = {1, 13};
Curve Loop(1) = {15, -12, 13, 14};
Plane Surface(1) = {1};
Curve Loop(2) = {1:11, 12};
Plane Surface(2) = {2};
Physical Surface("handle") = {1};
Physical Surface("body") = {2};
Physical Curve("end") = {14};
