(arcs-planes.nc: rs274 differential edge cases: arcs in every plane, full circles, P turns, R signs)
G21 G17 G90 G94
G0 X10 Y0 Z0
G1 X10 Y0 Z0 F600
(XY: full circle, end omitted, then with end written, then helical P3)
G2 I-10 J0
G3 X10 Y0 I-10 J0
G2 X10 Y0 Z-3 I-10 J0 P3
(R format: positive = short arc, negative = long arc, both directions)
G2 X0 Y10 R10
G3 X-10 Y0 R-10
G2 X0 Y-10 R-10
G3 X10 Y0 R10
(XZ plane: first axis Z, second X)
G18
G2 X10 Z-13 I0 K-5
G3 X10 Z-3 I0 K5 P2
G2 X20 Z-3 R5
G3 Y5 X30 Z-3 R-5
(YZ plane: first axis Y, second Z)
G19
G2 Y15 Z-3 J5 K0
G3 Y5 Z-3 J-5 K0 X35 P2
G2 Y-5 Z-3 R-5
(back to XY with incremental arcs)
G17 G91
G2 X10 Y10 I10 J0
G3 X-10 Y10 R10
G90
M2
