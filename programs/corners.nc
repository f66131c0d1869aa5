%
(corners.nc: a CAM-style profile at F3000 under a contour tolerance G64 P0.02: sharp corners,)
(corners closer together than the Acc/Dec filter is long, an arc; compare square.nc)
G21 G17 G90 G64 P0.02
G0 X0 Y0 Z1
G1 Z0 F600
G1 X30 F3000
G1 Y10
G1 X25 Y12
G1 X22 Y10.5
G1 X18 Y14
G3 X10 Y14 I-4 J0
G1 X0 Y20
G1 Y0
G0 Z1
M2
%
