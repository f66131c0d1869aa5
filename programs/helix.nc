%
(helix.nc: helical arcs: two turns of radius 5 mm descending 2 mm per turn, then an XZ and a YZ arc)
G21 G90 G17 G64
G0 X5 Y0 Z0
G2 X5 Y0 Z-4 I-5 J0 P2 F600
G18 (XZ plane)
G2 X-5 Z-4 R5 F600
G19 (YZ plane)
G3 Y5 Z1 J5 K0 F600
G17
G0 Z5
M2
%
